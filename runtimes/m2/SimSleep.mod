IMPLEMENTATION MODULE SimSleep ;

(* Sleeping islands: the Python reference's grounded, at_rest, jolted and
   can_sleep. *)

FROM SYSTEM IMPORT ADR ;
FROM SimScene IMPORT Bodies, BodyRef, RestSpeed ;
FROM SimQueue IMPORT CollisionEvent, FeatPE ;
FROM SimSupport IMPORT flat, static ;


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
   mx, my, load, ut: REAL ;
BEGIN
   IF M^.fixed OR M^.asleep OR NOT grounded (G) THEN RETURN FALSE END ;
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
   IF M^.polygon THEN
      IF (ABS (M^.om) * M^.bound >= RestSpeed) OR (ev.feature # FeatPE) OR (ev.i < 0) THEN RETURN FALSE END ;
      RETURN flat (ADR (Bodies^[ev.a]), ADR (Bodies^[ev.b]), ev.i, ev.j, -nx, -ny, load)
   END ;
   RETURN TRUE
END can_sleep ;


END SimSleep.
