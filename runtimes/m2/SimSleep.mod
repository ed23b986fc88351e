IMPLEMENTATION MODULE SimSleep ;

(* Sleeping islands: the Python reference's grounded, at_rest, jolted,
   over_face and can_sleep. *)

FROM SYSTEM IMPORT ADR ;
FROM SimScene IMPORT Bodies, BodyRef, RestContact, RestSlots, RestSpeed, Tol, Verts ;
FROM CMath IMPORT sqrt ;
FROM SimQueue IMPORT CollisionEvent, FeatPE ;
FROM SimSupport IMPORT flat, static, support_frame ;
FROM SimMotion IMPORT PointAt ;


(* A body others can fall asleep on: asleep, or fixed and unmoving. *)
PROCEDURE grounded (G: BodyRef) : BOOLEAN ;
BEGIN
   RETURN G^.asleep OR (G^.fixed AND static (G))
END grounded ;


(* A body supported by an unmoving body, slower than rest_speed along its
   edge, that static friction would hold there (|at| <= mu load, as in
   slide_accel at u = 0; on a level frictionless edge at = 0): it stays where
   it is.  On a moving support: never (it does not sleep); nor on a movable
   one (carried: grounded is false while it carries). *)
PROCEDURE at_rest (A: BodyRef) : BOOLEAN ;
VAR
   u, f: REAL ;
   B: BodyRef ;
BEGIN
   B := ADR (Bodies^[A^.sup]) ;
   IF NOT grounded (B) THEN RETURN FALSE END ;
   u := A^.vx * A^.tx + A^.vy * A^.ty ;
   IF NOT (u * u < RestSpeed * RestSpeed) THEN RETURN FALSE END ;
   f := A^.mu * B^.mu * A^.load ;
   RETURN (NOT (A^.at > f)) AND NOT (A^.at < -f)
END at_rest ;


(* A sleeper an impulse has set moving. *)
PROCEDURE jolted (S: BodyRef) : BOOLEAN ;
BEGIN
   RETURN (S^.vx # 0.0) OR (S^.vy # 0.0) OR (S^.om # 0.0)
END jolted ;


(* M's centre of mass projects inside the support segment of the contact of
   V's vertex i on E's edge j, shrunk by the tolerance: along the edge's
   tangent t, the overlap of the edge [s1, s2] with V's face (vertex i and
   each neighbour on the edge's line within the face tolerance of flat), all
   relative to E's centre.  A polygon whose centre lies past its support's
   end would tip: it does not sleep. *)
PROCEDURE over_face (M, V, E: BodyRef; i, j: INTEGER; load: REAL) : BOOLEAN ;
VAR
   tx, ty, ox, oy, ftol, r, h, px, py, lo, hi, q, c: REAL ;
   n, l, k: INTEGER ;
BEGIN
   support_frame (E, j, tx, ty, ox, oy) ;
   (* Python's max(tol, r): tol unless r is larger *)
   ftol := Tol ;
   r := RestSpeed * RestSpeed / load ;
   IF r > ftol THEN ftol := r END ;
   h := Verts^[E^.v0 + j].h ;
   PointAt (V, V^.v0 + i, V^.tb, px, py) ;
   lo := (px - E^.px) * tx + (py - E^.py) * ty ;
   hi := lo ;
   n := V^.nv ;
   FOR l := 0 TO 1 DO
      IF l = 0 THEN k := (i + n - 1) MOD n ELSE k := (i + 1) MOD n END ;
      PointAt (V, V^.v0 + k, V^.tb, px, py) ;
      IF (px - E^.px) * ox + (py - E^.py) * oy - h <= ftol THEN
         q := (px - E^.px) * tx + (py - E^.py) * ty ;
         IF q < lo THEN lo := q END ;
         IF q > hi THEN hi := q END
      END
   END ;
   IF Verts^[E^.v0 + j].s1 > lo THEN lo := Verts^[E^.v0 + j].s1 END ;
   IF Verts^[E^.v0 + j].s2 < hi THEN hi := Verts^[E^.v0 + j].s2 END ;
   c := (M^.px - E^.px) * tx + (M^.py - E^.py) * ty ;
   RETURN (NOT (c < lo + Tol)) AND NOT (c > hi - Tol)
END over_face ;


(* Awake movable M, one body of the collision ev with grounded G (both
   advanced; (nx, ny) the contact's unit normal from ev.a to ev.b, vn its
   normal speed), falls asleep on G: M's free acceleration presses it onto G
   (load > 0), the contact is slow (vn < rest_speed and eM eG (-vn) <
   rest_speed), M's speed across the normal is below rest_speed, and a
   polygon M turns slower than rest_speed / bound and lies on a face: a
   vertex-edge contact with a neighbour of the vertex on the edge's line
   (flat, whichever body has the vertex). *)
PROCEDURE can_sleep (M, G: BodyRef; ev: CollisionEvent; nx, ny, vn: REAL) : BOOLEAN ;
VAR
   mx, my, load: REAL ;
   V, E: BodyRef ;
BEGIN
   IF (NOT grounded (G)) OR (NOT slow_press (M, G, ev, nx, ny, vn)) THEN RETURN FALSE END ;
   IF M^.polygon THEN
      IF (ev.feature # FeatPE) OR (ev.i < 0) THEN RETURN FALSE END ;
      IF M^.idx = ev.a THEN
         mx := nx ;
         my := ny
      ELSE
         mx := -nx ;
         my := -ny
      END ;
      load := M^.fax * mx + M^.fay * my ;
      V := ADR (Bodies^[ev.a]) ;
      E := ADR (Bodies^[ev.b]) ;
      RETURN flat (V, E, ev.i, ev.j, -nx, -ny, load) AND over_face (M, V, E, ev.i, ev.j, load)
   END ;
   RETURN TRUE
END can_sleep ;


(* The contact of ev of awake movable M with G is slow and presses M onto G:
   M's free acceleration has a positive load along the normal from M to G,
   vn < rest_speed and eM eG (-vn) < rest_speed, M's speed across the normal
   is below rest_speed, and a polygon M turns slower than rest_speed / bound. *)
PROCEDURE slow_press (M, G: BodyRef; ev: CollisionEvent; nx, ny, vn: REAL) : BOOLEAN ;
VAR
   mx, my, load: REAL ;
BEGIN
   IF M^.fixed OR M^.asleep THEN RETURN FALSE END ;
   IF M^.idx = ev.a THEN
      mx := nx ;
      my := ny
   ELSE
      mx := -nx ;
      my := -ny
   END ;
   load := M^.fax * mx + M^.fay * my ;
   IF NOT (load > 0.0) THEN RETURN FALSE END ;
   RETURN slow_touch (M, G, ev, nx, ny, vn)
END slow_press ;


(* The contact of ev of awake movable M with G is slow: slow_press without
   the load (a contact across M's free acceleration, a wall a box leans on,
   counts). *)
PROCEDURE slow_touch (M, G: BodyRef; ev: CollisionEvent; nx, ny, vn: REAL) : BOOLEAN ;
VAR
   mx, my, ut: REAL ;
BEGIN
   IF M^.fixed OR M^.asleep THEN RETURN FALSE END ;
   IF M^.idx = ev.a THEN
      mx := nx ;
      my := ny
   ELSE
      mx := -nx ;
      my := -ny
   END ;
   IF (vn >= RestSpeed) OR (M^.e * G^.e * (-vn) >= RestSpeed) THEN RETURN FALSE END ;
   ut := M^.vy * mx - M^.vx * my ;
   IF ut * ut >= RestSpeed * RestSpeed THEN RETURN FALSE END ;
   RETURN (NOT M^.polygon) OR (ABS (M^.om) * M^.bound < RestSpeed)
END slow_touch ;


(* With G grounded, keeps the slow contact of ev at (cx, cy) first among M's
   last RestSlots slow contacts (distinct by key), with G's and M's positions and angles
   now: an earlier one with the same key leaves its place, the others move
   down one, the oldest beyond the slots is dropped. *)
PROCEDURE note_rest (M, G: BodyRef; ev: CollisionEvent; cx, cy, nx, ny: REAL) ;
VAR
   r: RestContact ;
   k: INTEGER ;
BEGIN
   IF NOT grounded (G) THEN RETURN END ;   (* an awake body moves: a contact with it would not hold *)
   r.side := M^.idx = ev.a ;
   IF r.side THEN
      r.mx := nx ;
      r.my := ny
   ELSE
      r.mx := -nx ;
      r.my := -ny
   END ;
   r.other1 := G^.idx + 1 ;
   r.feature := ev.feature ;
   r.i := ev.i ;
   r.j := ev.j ;
   r.px := cx ;
   r.py := cy ;
   r.gx := G^.px ;
   r.gy := G^.py ;
   r.gang := G^.ang ;
   r.bx := M^.px ;
   r.by := M^.py ;
   r.bang := M^.ang ;
   k := 0 ;
   (* the first slot empty, or with the same key (other body, feature, i, j, side), or the last *)
   WHILE (k < RestSlots - 1) AND (M^.rc[k].other1 # 0)
         AND NOT ((M^.rc[k].other1 = r.other1) AND (M^.rc[k].feature = r.feature) AND (M^.rc[k].i = r.i)
                  AND (M^.rc[k].j = r.j) AND (M^.rc[k].side = r.side)) DO
      INC (k)
   END ;
   WHILE k > 0 DO
      M^.rc[k] := M^.rc[k - 1] ;
      DEC (k)
   END ;
   M^.rc[0] := r
END note_rest ;


(* The face tolerance of M's noted contacts, max(tol, rest_speed^2 / |faM|)
   (fa: |faM|). *)
PROCEDURE rest_ftol (M: BodyRef; VAR fa: REAL) : REAL ;
VAR
   ftol: REAL ;
BEGIN
   fa := sqrt (M^.fax * M^.fax + M^.fay * M^.fay) ;
   ftol := RestSpeed * RestSpeed / fa ;
   IF Tol > ftol THEN ftol := Tol END ;
   RETURN ftol
END rest_ftol ;


(* M's noted slow contacts that still hold, in slot order, but the one with
   ev's key: the other body is not removed, grounded, at the position and
   angle noted (bit for bit), and M has moved less than ftol since (its
   centre, and its angle times its bound).  Their slot numbers go to held;
   returns how many. *)
PROCEDURE holding (M: BodyRef; ev: CollisionEvent; ftol: REAL; VAR held: ARRAY OF INTEGER) : INTEGER ;
VAR
   k, n, other1: INTEGER ;
   side: BOOLEAN ;
   O: BodyRef ;
   r: POINTER TO RestContact ;
   dx, dy: REAL ;
BEGIN
   side := M^.idx = ev.a ;
   IF side THEN other1 := ev.b + 1 ELSE other1 := ev.a + 1 END ;
   n := 0 ;
   k := 0 ;
   WHILE (k < RestSlots) AND (M^.rc[k].other1 # 0) DO
      r := ADR (M^.rc[k]) ;
      IF NOT ((r^.other1 = other1) AND (r^.feature = ev.feature) AND (r^.i = ev.i) AND (r^.j = ev.j)
              AND (r^.side = side)) THEN
         O := ADR (Bodies^[r^.other1 - 1]) ;
         IF (NOT O^.gone) AND grounded (O) AND (O^.px = r^.gx) AND (O^.py = r^.gy) AND (O^.ang = r^.gang) THEN
            dx := M^.px - r^.bx ;
            dy := M^.py - r^.by ;
            IF (NOT (dx * dx + dy * dy > ftol * ftol)) AND NOT (ABS (M^.ang - r^.bang) * M^.bound > ftol) THEN
               held[n] := k ;
               INC (n)
            END
         END
      END ;
      INC (k)
   END ;
   RETURN n
END holding ;


(* c := a x b for the rays' three components (force x, force y, torque). *)
PROCEDURE Cross3 (VAR a, b, c: ARRAY OF REAL) ;
BEGIN
   c[0] := a[1] * b[2] - a[2] * b[1] ;
   c[1] := a[2] * b[0] - a[0] * b[2] ;
   c[2] := a[0] * b[1] - a[1] * b[0]
END Cross3 ;


PROCEDURE Dot3 (VAR a, b: ARRAY OF REAL) : REAL ;
BEGIN
   RETURN a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
END Dot3 ;


TYPE
   Vec3 = ARRAY [0..2] OF REAL ;
   Contact5 = ARRAY [0..4] OF REAL ;


(* Adds the ray (dx, dy, rx dy - ry dx) as rays[n], then n + 1. *)
PROCEDURE AddRay (VAR rays: ARRAY OF Vec3; VAR n: INTEGER; rx, ry, dx, dy: REAL) ;
BEGIN
   rays[n][0] := dx ;
   rays[n][1] := dy ;
   rays[n][2] := rx * dy - ry * dx ;
   INC (n)
END AddRay ;


(* The contacts pts[0..np-1] = (px, py, mx, my, mu) of M (unit normal m
   from M to the other body) admit a static equilibrium with a margin: each
   of four targets T is a combination with coefficients >= 0 of the contact
   rays (per contact -m + mu t and -m - mu t, t = (-my, mx); -m alone when
   mu = 0), each ray written (dx, dy, (p - pM) x d).  By Caratheodory a
   target in the cone of the rays lies in the cone of three independent
   ones: the triples i < j < k are tried with Cramer's rule until every
   target is found in one (docs/simulator.md, "Several contacts"). *)
PROCEDURE balanced (M: BodyRef; VAR pts: ARRAY OF Contact5; np: INTEGER; fa: REAL) : BOOLEAN ;
VAR
   rays: ARRAY [0..2 * RestSlots + 1] OF Vec3 ;
   targets: ARRAY [0..3] OF Vec3 ;
   found: ARRAY [0..3] OF BOOLEAN ;
   cij, cjk, cki: Vec3 ;
   n, c, i, j, k, q, left: INTEGER ;
   rx, ry, mx, my, mu, e, wx, wy, tq, d, li, lj, lk: REAL ;
   out: BOOLEAN ;
BEGIN
   n := 0 ;
   FOR c := 0 TO np - 1 DO
      rx := pts[c][0] - M^.px ;
      ry := pts[c][1] - M^.py ;
      mx := pts[c][2] ;
      my := pts[c][3] ;
      mu := pts[c][4] ;
      IF mu > 0.0 THEN
         AddRay (rays, n, rx, ry, -mx - mu * my, -my + mu * mx) ;
         AddRay (rays, n, rx, ry, -mx + mu * my, -my - mu * mx)
      ELSE
         AddRay (rays, n, rx, ry, -mx, -my)
      END
   END ;
   IF n < 3 THEN RETURN FALSE END ;
   e := Tol / M^.bound ;
   wx := -e * M^.fay ;
   wy := e * M^.fax ;
   tq := fa * Tol ;
   targets[0][0] := -M^.fax + wx ; targets[0][1] := -M^.fay + wy ; targets[0][2] := 0.0 ;
   targets[1][0] := -M^.fax - wx ; targets[1][1] := -M^.fay - wy ; targets[1][2] := 0.0 ;
   targets[2][0] := -M^.fax ; targets[2][1] := -M^.fay ; targets[2][2] := tq ;
   targets[3][0] := -M^.fax ; targets[3][1] := -M^.fay ; targets[3][2] := -tq ;
   FOR q := 0 TO 3 DO found[q] := FALSE END ;
   left := 4 ;
   FOR i := 0 TO n - 3 DO
      FOR j := i + 1 TO n - 2 DO
         Cross3 (rays[i], rays[j], cij) ;
         FOR k := j + 1 TO n - 1 DO
            Cross3 (rays[j], rays[k], cjk) ;
            Cross3 (rays[k], rays[i], cki) ;
            d := Dot3 (rays[i], cjk) ;
            IF (d > 0.0) OR (d < 0.0) THEN
               FOR q := 0 TO 3 DO
                  IF NOT found[q] THEN
                     li := Dot3 (targets[q], cjk) ;
                     lj := Dot3 (targets[q], cki) ;
                     lk := Dot3 (targets[q], cij) ;
                     IF d > 0.0 THEN
                        out := (li < 0.0) OR (lj < 0.0) OR (lk < 0.0)
                     ELSE
                        out := (li > 0.0) OR (lj > 0.0) OR (lk > 0.0)
                     END ;
                     IF NOT out THEN
                        found[q] := TRUE ;
                        DEC (left) ;
                        IF left = 0 THEN RETURN TRUE END
                     END
                  END
               END
            END
         END
      END
   END ;
   RETURN FALSE
END balanced ;


(* Awake movable M, in the slow pressing contact of ev with grounded G at
   (cx, cy), falls asleep resting on several contacts (docs/simulator.md,
   "Several contacts"): this contact and M's noted ones that still hold
   (holding) admit a static equilibrium with a margin (balanced). *)
PROCEDURE can_sleep_many (M, G: BodyRef; ev: CollisionEvent; cx, cy, nx, ny, vn: REAL) : BOOLEAN ;
VAR
   held: ARRAY [0..RestSlots - 1] OF INTEGER ;
   pts: ARRAY [0..RestSlots] OF Contact5 ;
   nh, h: INTEGER ;
   fa, ftol: REAL ;
BEGIN
   IF (NOT grounded (G)) OR (NOT slow_press (M, G, ev, nx, ny, vn)) THEN RETURN FALSE END ;
   ftol := rest_ftol (M, fa) ;
   nh := holding (M, ev, ftol, held) ;
   IF nh = 0 THEN RETURN FALSE END ;
   pts[0][0] := cx ;
   pts[0][1] := cy ;
   IF M^.idx = ev.a THEN
      pts[0][2] := nx ;
      pts[0][3] := ny
   ELSE
      pts[0][2] := -nx ;
      pts[0][3] := -ny
   END ;
   pts[0][4] := M^.mu * G^.mu ;
   FOR h := 0 TO nh - 1 DO
      pts[h + 1][0] := M^.rc[held[h]].px ;
      pts[h + 1][1] := M^.rc[held[h]].py ;
      pts[h + 1][2] := M^.rc[held[h]].mx ;
      pts[h + 1][3] := M^.rc[held[h]].my ;
      pts[h + 1][4] := M^.mu * Bodies^[M^.rc[held[h]].other1 - 1].mu
   END ;
   RETURN balanced (M, pts, nh + 1, fa)
END can_sleep_many ;


END SimSleep.
