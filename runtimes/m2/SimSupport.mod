IMPLEMENTATION MODULE SimSupport ;

(* Support and carried bodies: the Python reference's support_frame,
   static, flat, can_support, slide_accel, enter_support, end_support,
   can_carry, enter_carried, first_crossing, support_relative and
   schedule_support, with the same IEEE double operations in the same
   order. *)

FROM SYSTEM IMPORT ADR ;
FROM RealMath IMPORT cos, sin ;
FROM Roots IMPORT SmallestRoot ;
FROM SimScene IMPORT Bodies, BodyRef, EndT, NBodies, RestSpeed, Tol, Verts ;
FROM SimQueue IMPORT Event, FeatPE, KLeave, KStop ;
FROM SimWorld IMPORT push ;
FROM SimMotion IMPORT PointAt, StateAt ;


(* Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j of B in
   the world (B does not turn). *)
PROCEDURE support_frame (B: BodyRef; j: INTEGER; VAR tx, ty, ox, oy: REAL) ;
VAR
   c, s, enx, eny: REAL ;
BEGIN
   enx := Verts^[B^.v0 + j].nx ;
   eny := Verts^[B^.v0 + j].ny ;
   c := cos (B^.ang) ;
   s := sin (B^.ang) ;
   ox := c * enx - s * eny ;
   oy := s * enx + c * eny ;
   tx := -oy ;
   ty := ox
END support_frame ;


PROCEDURE static (B: BodyRef) : BOOLEAN ;
BEGIN
   RETURN (B^.vx = 0.0) AND (B^.vy = 0.0) AND (B^.ax = 0.0) AND (B^.ay = 0.0) AND (B^.om = 0.0)
END static ;


(* A neighbour of A's vertex i lies on edge j's line within the face
   tolerance max(tol, rest_speed^2 / load): A rests on a face. *)
PROCEDURE flat (A, B: BodyRef; i, j: INTEGER; ox, oy, load: REAL) : BOOLEAN ;
VAR
   ftol, q, h, px, py: REAL ;
   n, m, k: INTEGER ;
BEGIN
   (* Python's max(tol, q): tol unless q is larger *)
   ftol := Tol ;
   q := RestSpeed * RestSpeed / load ;
   IF q > ftol THEN ftol := q END ;
   n := A^.nv ;
   h := Verts^[B^.v0 + j].h ;
   FOR m := 0 TO 1 DO
      IF m = 0 THEN k := (i + n - 1) MOD n ELSE k := (i + 1) MOD n END ;
      PointAt (A, A^.v0 + k, A^.tb, px, py) ;
      IF (px - B^.px) * ox + (py - B^.py) * oy - h <= ftol THEN RETURN TRUE END
   END ;
   RETURN FALSE
END flat ;


(* A point-edge contact of movable A on edge j of a fixed polygon B that
   does not turn (it may translate) becomes support, everything relative to
   B (docs/simulator.md, Contact model); both advanced. *)
PROCEDURE can_support (A, B: BodyRef; feature, i, j: INTEGER; vn: REAL) : BOOLEAN ;
BEGIN
   IF (feature # FeatPE) OR A^.fixed OR (NOT B^.fixed) OR (B^.om # 0.0) THEN RETURN FALSE END ;
   RETURN supportable (A, B, i, j, vn)
END can_support ;


(* Acceleration along an edge of a body sliding at u relative to it: the
   free part at less Coulomb friction f (mu times the load) against the
   motion; at relative rest none while static friction holds. *)
PROCEDURE friction_accel (at, f, u: REAL) : REAL ;
BEGIN
   IF u > 0.0 THEN
      RETURN at - f
   ELSIF u < 0.0 THEN
      RETURN at + f
   ELSIF at > f THEN
      RETURN at - f
   ELSIF at < -f THEN
      RETURN at + f
   END ;
   RETURN 0.0
END friction_accel ;


(* Sleeping base B (at rest on edge frame (B.tx, B.ty) of fixed body
   B.rest) stays at rest under its free acceleration, the force (px, py)
   and the force of each body supported on it (by index, its reaction
   -m (a - fa)): the resting contact's normal force n = -(mB faB + P) . o
   is positive and its tangential force t = -(mB faB + P) . t lies within
   static friction, |t| <= mu n. *)
PROCEDURE base_holds (B: BodyRef; px, py: REAL) : BOOLEAN ;
VAR
   k: INTEGER ;
   mB, fx, fy, n, t, f: REAL ;
BEGIN
   IF B^.carry > 0 THEN
      FOR k := 0 TO NBodies - 1 DO
         IF Bodies^[k].sup = B^.idx THEN
            px := px - (Bodies^[k].ax - Bodies^[k].fax) / Bodies^[k].invM ;
            py := py - (Bodies^[k].ay - Bodies^[k].fay) / Bodies^[k].invM
         END
      END
   END ;
   mB := 1.0 / B^.invM ;
   fx := mB * B^.fax + px ;
   fy := mB * B^.fay + py ;
   n := -(fx * B^.ty - fy * B^.tx) ;
   t := -(fx * B^.tx + fy * B^.ty) ;
   f := B^.mu * Bodies^[B^.rest].mu * n ;
   RETURN (n > 0.0) AND (NOT (t > f)) AND (NOT (t < -f))
END base_holds ;


(* A point-edge contact of movable A on edge j of a sleeping polygon B that
   fell asleep supported on a fixed body (B.rest) becomes support on B, as
   on a fixed body that does not move (docs/simulator.md, "Sliding on a
   sleeping base"), when B's resting contact holds the force A's sliding
   puts on B besides B's other riders (base_holds). *)
PROCEDURE can_ride (A, B: BodyRef; feature, i, j: INTEGER; vn: REAL) : BOOLEAN ;
VAR
   tx, ty, ox, oy, u, a: REAL ;
BEGIN
   IF (feature # FeatPE) OR A^.fixed OR (NOT B^.asleep) OR (B^.rest < 0) OR (NOT B^.polygon) THEN
      RETURN FALSE
   END ;
   IF NOT supportable (A, B, i, j, vn) THEN RETURN FALSE END ;
   support_frame (B, j, tx, ty, ox, oy) ;
   u := A^.vx * tx + A^.vy * ty ;
   a := friction_accel (A^.fax * tx + A^.fay * ty, A^.mu * B^.mu * (-(A^.fax * ox + A^.fay * oy)), u) ;
   RETURN base_holds (B, (-(a * tx - A^.fax)) / A^.invM, (-(a * ty - A^.fay)) / A^.invM)
END can_ride ;


(* The checks of can_support after the bodies' kinds: pressed onto edge j,
   slow, over the edge and not leaving it, a polygon flat on it. *)
PROCEDURE supportable (A, B: BodyRef; i, j: INTEGER; vn: REAL) : BOOLEAN ;
VAR
   tx, ty, ox, oy, load, q, u: REAL ;
BEGIN
   support_frame (B, j, tx, ty, ox, oy) ;
   load := -((A^.fax - B^.ax) * ox + (A^.fay - B^.ay) * oy) ;
   IF (NOT (load > 0.0)) OR (vn >= RestSpeed) OR (A^.e * B^.e * (-vn) >= RestSpeed) THEN RETURN FALSE END ;
   q := (A^.px - B^.px) * tx + (A^.py - B^.py) * ty ;
   IF (q < Verts^[B^.v0 + j].s1) OR (q > Verts^[B^.v0 + j].s2) THEN RETURN FALSE END ;
   (* at an end of the edge (within the tolerance) and moving past it: it is
      leaving (a support would end at once, again and again) *)
   u := (A^.vx - B^.vx) * tx + (A^.vy - B^.vy) * ty ;
   IF ((u > 0.0) AND (q >= Verts^[B^.v0 + j].s2 - Tol)) OR ((u < 0.0) AND (q <= Verts^[B^.v0 + j].s1 + Tol)) THEN
      RETURN FALSE
   END ;
   IF A^.polygon THEN
      IF ABS (A^.om) * A^.bound >= RestSpeed THEN RETURN FALSE END ;
      RETURN flat (A, B, i, j, ox, oy, load)
   END ;
   RETURN TRUE
END supportable ;


(* Acceleration of supported A with tangential speed u relative to its
   support B: the relative free acceleration along the edge less Coulomb
   friction mu |a_n| against the relative motion; at relative rest, none
   while friction can hold it; plus B's acceleration when B moves. *)
PROCEDURE slide_accel (A: BodyRef; u: REAL) ;
VAR
   a: REAL ;
   B: BodyRef ;
BEGIN
   B := ADR (Bodies^[A^.sup]) ;
   a := friction_accel (A^.at, A^.mu * B^.mu * A^.load, u) ;
   IF static (B) THEN
      A^.ax := a * A^.tx ;
      A^.ay := a * A^.ty
   ELSE
      A^.ax := B^.ax + a * A^.tx ;
      A^.ay := B^.ay + a * A^.ty
   END
END slide_accel ;


(* A (advanced to now, as B) keeps only its velocity relative to B along the
   edge, stops turning, and from now on accelerates relative to B along the
   edge only. *)
PROCEDURE enter_support (A, B: BodyRef; j: INTEGER) ;
VAR
   tx, ty, ox, oy, u: REAL ;
BEGIN
   support_frame (B, j, tx, ty, ox, oy) ;
   u := (A^.vx - B^.vx) * tx + (A^.vy - B^.vy) * ty ;
   IF static (B) THEN
      A^.vx := u * tx ;
      A^.vy := u * ty
   ELSE
      A^.vx := B^.vx + u * tx ;
      A^.vy := B^.vy + u * ty
   END ;
   IF A^.polygon THEN A^.om := 0.0 END ;
   A^.sup := B^.idx ;
   A^.sup_edge := j ;
   A^.tx := tx ;
   A^.ty := ty ;
   A^.load := -((A^.fax - B^.ax) * ox + (A^.fay - B^.ay) * oy) ;
   A^.at := (A^.fax - B^.ax) * tx + (A^.fay - B^.ay) * ty ;
   IF NOT B^.fixed THEN INC (B^.carry) END ;      (* a sleeping base counts what it supports *)
   slide_accel (A, u)
END enter_support ;


(* A's support (or carrier) ends: its free acceleration again. *)
PROCEDURE end_support (A: BodyRef) ;
VAR
   B: BodyRef ;
BEGIN
   B := ADR (Bodies^[A^.sup]) ;
   IF NOT B^.fixed THEN DEC (B^.carry) END ;
   A^.ax := A^.fax ;
   A^.ay := A^.fay ;
   A^.sup := -1 ;
   A^.sup_edge := -1
END end_support ;


(* A point-edge contact of movable A on edge j of a movable polygon B that
   does not turn and is itself supported or carried (its motion a
   polynomial: constant acceleration) becomes carrying (docs/simulator.md,
   "Carried bodies"); both advanced.  As can_support, everything relative to
   B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn) <
   rest_speed), A's centre over the edge; and A at relative rest along it
   (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds it
   (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A (no
   loop), and |vB|^2 <= |vA|^2: taking B's velocity never raises A's kinetic
   energy.  A polygon also turns slower than rest_speed / bound and lies on
   a face (flat). *)
PROCEDURE can_carry (A, B: BodyRef; feature, i, j: INTEGER; vn: REAL) : BOOLEAN ;
VAR
   tx, ty, ox, oy, load, q, u, at, f: REAL ;
   k: INTEGER ;
BEGIN
   IF (feature # FeatPE) OR A^.fixed OR B^.fixed OR (NOT B^.polygon) OR (B^.om # 0.0) OR (B^.sup < 0) THEN
      RETURN FALSE
   END ;
   k := B^.sup ;
   WHILE k >= 0 DO
      IF k = A^.idx THEN RETURN FALSE END ;
      k := Bodies^[k].sup
   END ;
   support_frame (B, j, tx, ty, ox, oy) ;
   load := -((A^.fax - B^.ax) * ox + (A^.fay - B^.ay) * oy) ;
   IF (NOT (load > 0.0)) OR (vn >= RestSpeed) OR (A^.e * B^.e * (-vn) >= RestSpeed) THEN RETURN FALSE END ;
   q := (A^.px - B^.px) * tx + (A^.py - B^.py) * ty ;
   IF (q < Verts^[B^.v0 + j].s1) OR (q > Verts^[B^.v0 + j].s2) THEN RETURN FALSE END ;
   u := (A^.vx - B^.vx) * tx + (A^.vy - B^.vy) * ty ;
   IF NOT (u * u < RestSpeed * RestSpeed) THEN RETURN FALSE END ;
   at := (A^.fax - B^.ax) * tx + (A^.fay - B^.ay) * ty ;
   f := A^.mu * B^.mu * load ;
   IF (at > f) OR (at < -f) THEN RETURN FALSE END ;
   IF B^.vx * B^.vx + B^.vy * B^.vy > A^.vx * A^.vx + A^.vy * A^.vy THEN RETURN FALSE END ;
   IF A^.polygon THEN
      IF ABS (A^.om) * A^.bound >= RestSpeed THEN RETURN FALSE END ;
      RETURN flat (A, B, i, j, ox, oy, load)
   END ;
   RETURN TRUE
END can_carry ;


(* A (advanced to now, as B) moves with B from now on: B's velocity and
   acceleration exactly (its offset from B constant), no turn. *)
PROCEDURE enter_carried (A, B: BodyRef; j: INTEGER) ;
VAR
   tx, ty, ox, oy: REAL ;
BEGIN
   support_frame (B, j, tx, ty, ox, oy) ;
   A^.vx := B^.vx ;
   A^.vy := B^.vy ;
   IF A^.polygon THEN A^.om := 0.0 END ;
   A^.sup := B^.idx ;
   A^.sup_edge := j ;
   A^.tx := tx ;
   A^.ty := ty ;
   A^.load := -((A^.fax - B^.ax) * ox + (A^.fay - B^.ay) * oy) ;
   A^.at := (A^.fax - B^.ax) * tx + (A^.fay - B^.ay) * ty ;
   A^.ax := B^.ax ;
   A^.ay := B^.ay ;
   INC (B^.carry)
END enter_carried ;


(* The first u in [lo, hi] where p + v u + a u^2 / 2 crosses zero moving in
   the direction (+1 up, -1 down); FALSE when none. *)
PROCEDURE first_crossing (p, v, a: REAL; direction: INTEGER; lo, hi: REAL; VAR u: REAL) : BOOLEAN ;
VAR
   c: ARRAY [0..2] OF REAL ;
   it: INTEGER ;
BEGIN
   c[0] := p ;
   c[1] := v ;
   c[2] := 0.5 * a ;
   FOR it := 1 TO 3 DO
      IF NOT SmallestRoot (c, 2, lo, hi, u) THEN RETURN FALSE END ;
      IF (v + a * u) * VAL (REAL, direction) > 0.0 THEN RETURN TRUE END ;
      lo := u
   END ;
   RETURN FALSE
END first_crossing ;


(* Supported b's motion relative to its support B along the edge, at b's
   time: q the centre's coordinate along the tangent from B's centre, u, a
   its speed and acceleration. *)
PROCEDURE support_relative (b: BodyRef; VAR q, u, a: REAL) ;
VAR
   B: BodyRef ;
   bx, by, bvx, bvy, bang: REAL ;
BEGIN
   B := ADR (Bodies^[b^.sup]) ;
   StateAt (B, b^.tb, bx, by, bvx, bvy, bang) ;
   q := (b^.px - bx) * b^.tx + (b^.py - by) * b^.ty ;
   u := (b^.vx - bvx) * b^.tx + (b^.vy - bvy) * b^.ty ;
   a := (b^.ax - B^.ax) * b^.tx + (b^.ay - B^.ay) * b^.ty
END support_relative ;


(* A supported body's stop (its tangential speed relative to the support
   reaches zero) and leave (its centre, projected on the edge, reaches an
   end) events; b is at its own time tb (the reference's now). *)
PROCEDURE schedule_support (b: BodyRef) ;
VAR
   u, a, q, hi, s1, s2: REAL ;
   ed: INTEGER ;
   f1, f2: BOOLEAN ;
   ev: Event ;
BEGIN
   support_relative (b, q, u, a) ;
   IF (u # 0.0) AND (a # 0.0) AND ((u > 0.0) # (a > 0.0)) THEN
      ev.t := b^.tb + (-u) / a ;
      ev.kind := KStop ;
      ev.stop.body := b^.idx ;
      ev.stop.stamp := b^.stamp ;
      push (ev)
   END ;
   ed := Bodies^[b^.sup].v0 + b^.sup_edge ;
   hi := EndT - b^.tb ;
   f2 := first_crossing (q - Verts^[ed].s2, u, a, 1, 0.0, hi, s2) ;
   f1 := first_crossing (q - Verts^[ed].s1, u, a, -1, 0.0, hi, s1) ;
   IF f1 AND ((NOT f2) OR (s1 < s2)) THEN
      f2 := TRUE ;
      s2 := s1
   END ;
   IF f2 THEN
      ev.t := b^.tb + s2 ;
      ev.kind := KLeave ;
      ev.leave.body := b^.idx ;
      ev.leave.stamp := b^.stamp ;
      push (ev)
   END
END schedule_support ;


END SimSupport.
