IMPLEMENTATION MODULE SimSleep ;

(* Sleeping islands: the Python reference's grounded, at_rest, jolted,
   over_face and can_sleep. *)

FROM SYSTEM IMPORT ADR ;
FROM SimScene IMPORT Bodies, BodyRef, RestContact, RestSpeed, Tol, Verts ;
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
   mx, my, load, ut: REAL ;
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
   IF (NOT (load > 0.0)) OR (vn >= RestSpeed) OR (M^.e * G^.e * (-vn) >= RestSpeed) THEN RETURN FALSE END ;
   ut := M^.vy * mx - M^.vx * my ;
   IF ut * ut >= RestSpeed * RestSpeed THEN RETURN FALSE END ;
   RETURN (NOT M^.polygon) OR (ABS (M^.om) * M^.bound < RestSpeed)
END slow_press ;


(* Keeps the contact of ev at (cx, cy) as M's last slow pressing contact,
   with G's and M's positions and angles now; the one before, when it was
   with another body, is kept too. *)
PROCEDURE note_rest (M, G: BodyRef; ev: CollisionEvent; cx, cy, nx, ny: REAL) ;
VAR
   mx, my: REAL ;
BEGIN
   IF M^.idx = ev.a THEN
      mx := nx ;
      my := ny
   ELSE
      mx := -nx ;
      my := -ny
   END ;
   IF M^.rc[0].other1 # G^.idx + 1 THEN M^.rc[1] := M^.rc[0] END ;
   M^.rc[0].px := cx ;
   M^.rc[0].py := cy ;
   M^.rc[0].other1 := G^.idx + 1 ;
   M^.rc[0].mx := mx ;
   M^.rc[0].my := my ;
   M^.rc[0].load := M^.fax * mx + M^.fay * my ;
   M^.rc[0].gx := G^.px ;
   M^.rc[0].gy := G^.py ;
   M^.rc[0].gang := G^.ang ;
   M^.rc[0].bx := M^.px ;
   M^.rc[0].by := M^.py ;
   M^.rc[0].bang := M^.ang
END note_rest ;


(* M's last slow pressing contact with a body other than G: FALSE when none. *)
PROCEDURE rest_other (M, G: BodyRef; VAR r: RestContact) : BOOLEAN ;
BEGIN
   IF M^.rc[0].other1 - 1 = G^.idx THEN r := M^.rc[1] ELSE r := M^.rc[0] END ;
   RETURN (r.other1 # 0) AND (r.other1 - 1 # G^.idx)
END rest_other ;


(* A contact force along (gx, gy) at a contact of unit normal (mx, my) lies
   in the friction cone: c > 0 and |m x g| <= mu c. *)
PROCEDURE in_cone (mx, my, gx, gy, mu: REAL) : BOOLEAN ;
VAR
   c, s: REAL ;
BEGIN
   c := mx * gx + my * gy ;
   s := ABS (mx * gy - my * gx) ;
   RETURN (c > 0.0) AND NOT (s > mu * c)
END in_cone ;


(* Awake movable M, in the slow pressing contact of ev with grounded G at
   (cx, cy), falls asleep on two supports (docs/simulator.md, "Two
   supports"): its last slow pressing contact with another body G1 that is
   grounded and has not moved since; M has moved less than the face
   tolerance since (its centre, and its angle times its bound); both
   contacts can push along M's free acceleration within their friction
   cones, and M's centre lies strictly between the two contact points across
   that direction (by more than the tolerance). *)
PROCEDURE can_sleep_two (M, G: BodyRef; ev: CollisionEvent; cx, cy, nx, ny, vn: REAL) : BOOLEAN ;
VAR
   r: RestContact ;
   G1: BodyRef ;
   ftol, dx, dy, fa, gx, gy, mx, my, x1, x2: REAL ;
BEGIN
   IF (NOT grounded (G)) OR (NOT slow_press (M, G, ev, nx, ny, vn)) THEN RETURN FALSE END ;
   IF NOT rest_other (M, G, r) THEN RETURN FALSE END ;
   G1 := ADR (Bodies^[r.other1 - 1]) ;
   IF G1^.gone OR (NOT grounded (G1)) OR (G1^.px # r.gx) OR (G1^.py # r.gy) OR (G1^.ang # r.gang) THEN
      RETURN FALSE
   END ;
   ftol := RestSpeed * RestSpeed / r.load ;
   IF Tol > ftol THEN ftol := Tol END ;
   dx := M^.px - r.bx ;
   dy := M^.py - r.by ;
   IF (dx * dx + dy * dy > ftol * ftol) OR (ABS (M^.ang - r.bang) * M^.bound > ftol) THEN RETURN FALSE END ;
   fa := sqrt (M^.fax * M^.fax + M^.fay * M^.fay) ;
   gx := M^.fax / fa ;
   gy := M^.fay / fa ;
   IF M^.idx = ev.a THEN
      mx := nx ;
      my := ny
   ELSE
      mx := -nx ;
      my := -ny
   END ;
   IF (NOT in_cone (r.mx, r.my, gx, gy, M^.mu * G1^.mu)) OR (NOT in_cone (mx, my, gx, gy, M^.mu * G^.mu)) THEN
      RETURN FALSE
   END ;
   x1 := (r.px - M^.px) * (-gy) + (r.py - M^.py) * gx ;
   x2 := (cx - M^.px) * (-gy) + (cy - M^.py) * gx ;
   RETURN ((x1 < -Tol) AND (x2 > Tol)) OR ((x1 > Tol) AND (x2 < -Tol))
END can_sleep_two ;


END SimSleep.
