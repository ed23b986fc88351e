IMPLEMENTATION MODULE SimMotion ;

(* Motion between events: the state of a body at any time from its state
   at its own time tb. *)

FROM RealMath IMPORT cos, sin ;
FROM SimScene IMPORT BodyRef, Verts ;


(* Carries b's state to time t (only events do this: re-basing rounds). *)
PROCEDURE rebase (b: BodyRef; t: REAL) ;
VAR
   dt: REAL ;
BEGIN
   dt := t - b^.tb ;
   b^.px := b^.px + (b^.vx + 0.5 * b^.ax * dt) * dt ;
   b^.py := b^.py + (b^.vy + 0.5 * b^.ay * dt) * dt ;
   b^.vx := b^.vx + b^.ax * dt ;
   b^.vy := b^.vy + b^.ay * dt ;
   b^.ang := b^.ang + b^.om * dt ;
   b^.tb := t
END rebase ;


(* Centre, velocity and angle at time t (the body is not changed). *)
PROCEDURE StateAt (b: BodyRef; t: REAL; VAR x, y, vx, vy, ang: REAL) ;
VAR
   dt: REAL ;
BEGIN
   dt := t - b^.tb ;
   x := b^.px + (b^.vx + 0.5 * b^.ax * dt) * dt ;
   y := b^.py + (b^.vy + 0.5 * b^.ay * dt) * dt ;
   vx := b^.vx + b^.ax * dt ;
   vy := b^.vy + b^.ay * dt ;
   ang := b^.ang + b^.om * dt
END StateAt ;


PROCEDURE TurnRate (b: BodyRef) : REAL ;
BEGIN
   IF b^.polygon OR (b^.orbit > 0.0) THEN
      RETURN ABS (b^.om)
   END ;
   RETURN 0.0
END TurnRate ;


(* World position of a circle's centre (v < 0) or of vertex v, at t. *)
PROCEDURE PointAt (b: BodyRef; v: INTEGER; t: REAL; VAR x, y: REAL) ;
VAR
   vx, vy, ang, d, beta: REAL ;
BEGIN
   StateAt (b, t, x, y, vx, vy, ang) ;
   IF v < 0 THEN
      d := b^.orbit ;
      beta := b^.ophase
   ELSE
      d := Verts^[v].rho ;
      beta := Verts^[v].beta
   END ;
   IF d = 0.0 THEN RETURN END ;
   x := x + d * cos (ang + beta) ;
   y := y + d * sin (ang + beta)
END PointAt ;


END SimMotion.
