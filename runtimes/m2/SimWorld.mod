IMPLEMENTATION MODULE SimWorld ;

(* The discrete-event simulator of docs/simulator.md in Modula-2, as the
   live world of docs/engine-api.md.  A transcription of the Python
   reference (runtimes/python/max2code_rt/sim.py, class World), procedure
   for procedure, with the same IEEE double operations in the same order
   (no FMA: built with -ffp-contract=off; sin and cos are libm's through
   RealMath, floor and sqrt libm's through C), so that it writes the same
   bytes.

   One module per concept, as the C runtime: SimScene (the scene, its bodies
   and reading it), SimGrid (the broad phase's cells), SimHeap (the event
   queue), SimOut (the trace writer; numbers as "%.17g" writes them).  This
   module holds the motion, the predictions, one handler per event kind, the
   dispatch that calls them and the live API, with the names
   docs/simulator.md gives the reference's steps (handle_input,
   handle_collision, handle_cell, handle_horizon, handle_frame,
   handle_support, handle_stop, handle_leave, start, finish, dispatch,
   process, is_stale, push, push_collision, push_horizon, contact_frame,
   contact_impulse, normal_speed, can_support, flat, enter_support,
   slide_accel, end_support, support_relative, schedule_support, first_crossing, rebase,
   overlapping, separation, edge_line, edges_separation, circle_separation,
   live_input, drivable, inputs_now, remove, drive, wake_touching, grounded, at_rest,
   hop, pay_floor, closing, circles_gap, can_carry, enter_carried, leave, release, predict_released, along, held, held_impulse, can_sleep, sleeper_impulse, jolted, handle_sleep, handle_wake,
   predict_woken, bound_polygon, place_large, unplace_large, walls_in,
   large_near, clear_time, clear_axes, clear_root, reach, touch, repeated,
   handle_cluster, cluster, joins, part, give, nudge, sweeps, kinetic,
   velocities, set_velocities, mix, pressing_contact, solve_cluster,
   jolted_sleeper, wedged, holds, settle, predict_apart (the reference's
   touched and touched_t are Touched and TouchedT; its rows, movers and
   pushes are Rows, Movers and Pushes);
   behind; the reference's features is Features; the reference's predict_cc, predict_pe,
   pe_coefficients, pe_first, circles_first, circles_apart, cc_count,
   centre_params, circle_params and bounds_meet are PredictCC, PredictPE,
   PeCoefficients, PeFirst, CirclesFirst, CirclesApart, CcCount,
   CentreParams, CircleParams and BoundsMeet).

   Every prediction goes through the generated entries of
   equations/circle-circle.mxm and equations/point-edge.mxm, included below
   from the build directory, and through Roots.SmallestRoot.  The build
   defines SIM_CC_VARIANTS and SIM_PE_VARIANTS, the number of variants each
   NAME_variant counts (max2code/toolchain/m2.py, from the generator's
   selection). *)

FROM SYSTEM IMPORT ADR, ADDRESS ;
FROM RealMath IMPORT sin, cos ;
FROM Roots IMPORT SmallestRoot ;
FROM CMath IMPORT sqrt ;
FROM SimC IMPORT snprintf, strtod, realloc ;
FROM SimHeap IMPORT Event, Push, Pop, Top, Clear, KInput, KCollision, KStop, KLeave, KCell, KHorizon, KFrame,
                    InputEvent, CollisionEvent, StopEvent, LeaveEvent, CellEvent, HorizonEvent, FrameEvent ;
FROM SimOut IMPORT Str, Int, Real, SpReal, Ln, Flush, SetOn ;
FROM SimScene IMPORT Vertex, Input, AddInput, BodyRef, Bodies, Verts, Inputs, NBodies, NVerts, NInputs,
                     EndT, FrameDt, Tol, RestSpeed, Alpha, MaxSame, GridX0, GridY0, CellW, CellH, GridNX, GridNY, GridMargin, HalfCell,
                     ReadText, ReadFile, ReadStdin, ReadError, ReadBodyText, Grow, MaxItems ;
FROM SimGrid IMPORT Cells, Walls, Large, NLarge, IntList, InitGrid, CellOf, CellAdd, CellRemove, WallAdd, WallRemove,
                    LargeAdd, LargeRemove ;

#include "circle_circle.mxd"
#include "point_edge.mxd"

CONST
   MsgLen = 511 ;
   (* input modes (the flat scene's MODE; docs/simulator.md) *)
   SetVelocityMode = 0 ;
   AddVelocityMode = 1 ;
   ImpulseMode = 2 ;
   TeleportMode = 3 ;
   RemoveMode = 4 ;
   MaxContacts = 16777216 ;    (* bound of the array type only: storage grows *)
   HalfPi = 1.5707963267948966 ;
   (* the most stages (a meeting of the bounds, a clear stretch, a Taylor
      window) one prediction of a pair goes through before it leaves the rest
      to a horizon *)
   Chain = 8 ;   (* pi/2 rounded to double (cos x = sin(x + pi/2)) *)
   (* CirclesApart's margins: far above the coefficients' rounding *)
   TwoM40 = 1.0 / 1099511627776.0 ;
   TwoM30 = 1.0 / 1073741824.0 ;
   TwoM90 = TwoM30 * TwoM30 * TwoM30 ;
   TwoM450 = TwoM90 * TwoM90 * TwoM90 * TwoM90 * TwoM90 ;   (* ... and its bounds on sizes *)
   TwoP450 = 1.0 / TwoM450 ;
   TwoM900 = TwoM450 * TwoM450 ;
   (* contact features *)
   FeatCC = 0 ;
   FeatPE = 1 ;
   CcVariants = SIM_CC_VARIANTS ;
   PeVariants = SIM_PE_VARIANTS ;
   CcMaxDegree = circle_circle_coefficients_max_degree ;
   (* simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
      contacts"): how many times one contact is handled at one instant
      before it and the contacts it touches are solved together; the most
      sweeps of the cluster's sequential impulses, and the sweep that ends
      them: no impulse in it changed a normal speed by more than ClusterTol
      rest_speed *)
   ClusterRepeats = 64 ;
   ClusterSweeps = 100 ;
   ClusterTol = 1.0E-9 ;
   (* the separation speed (times rest_speed) of a cluster's contact that
      nothing presses: above the rounding of a normal speed, so that it is
      not met again at once (2^-20) *)
   ClusterApart = 9.5367431640625E-7 ;
   (* the angle (rad) within which one push holds a free acceleration (wedged) *)
   HoldTol = 1.0E-9 ;
   (* a body's part in a cluster's solve: held (fixed, or asleep: infinite
      mass), free, or sliding on a fixed body's edge (moves along the edge only) *)
   Held = 0 ;
   Free = 1 ;
   Slider = 2 ;
   PeMaxDegree = point_edge_coefficients_max_degree ;

TYPE
   ContactArray = POINTER TO ARRAY [0..MaxContacts - 1] OF Contact ;
   (* the point_edge polynomial of one edge (bound_polygon's) *)
   EdgePoly = RECORD
      deg: INTEGER ;
      c: ARRAY [0..PeMaxDegree] OF REAL ;
   END ;
   EdgePolyArray = POINTER TO ARRAY [0..MaxItems - 1] OF EdgePoly ;
   (* the counters written as the trace's N lines, in this order *)
   StatCounts = RECORD
      collisions, inputs, frames, cells, horizons, stale, pairs, features, supports, stops, leaves, sleeps,
      wakes: LONGINT ;
   END ;

   (* a contact handled at the instant TouchedT (touch), and how many times *)
   Touch = RECORD
      a, b, feature, i, j, times: INTEGER ;
   END ;
   TouchArray = POINTER TO ARRAY [0..MaxItems - 1] OF Touch ;
   (* a contact of a cluster (cluster, solve_cluster): its bodies and
      feature, its frame at the instant, the arms across n, kn (how much a
      unit impulse along n changes its normal speed), its normal impulse
      acc (acc2: the one of the first solve, mixed), its target speed *)
   Row = RECORD
      a, b, feature, i, j: INTEGER ;
      cx, cy, nx, ny, ran, rbn, kn, acc, acc2, target: REAL ;
   END ;
   RowArray = POINTER TO ARRAY [0..MaxItems - 1] OF Row ;
   (* a body a cluster's solve moves, with its velocities before (s), after
      the first solve (v2) and from rest (vs) *)
   Mover = RECORD
      idx: INTEGER ;
      sx, sy, som, v2x, v2y, v2om, vsx, vsy, vsom: REAL ;
   END ;
   MoverArray = POINTER TO ARRAY [0..MaxItems - 1] OF Mover ;
   (* a unit direction that pushes a body (wedged, holds) *)
   Direction = RECORD
      x, y: REAL ;
   END ;
   PushArray = POINTER TO ARRAY [0..MaxItems - 1] OF Direction ;

VAR
   Seq: LONGINT ;              (* the next scheduling counter *)
   Stats: StatCounts ;
   CcCounts: ARRAY [0..CcVariants - 1] OF LONGINT ;
   PeCounts: ARRAY [0..PeVariants - 1] OF LONGINT ;
   (* the point-edge check of the prediction under way (predict_pe's inside) *)
   ChkX, ChkY: BodyRef ;
   ChkRho, ChkBeta: REAL ;     (* the point: rho, beta about X's centre (rho 0: the centre) *)
   ChkEdge: INTEGER ;
   ChkVert: INTEGER ;          (* the point is X's vertex ChkVert (local index; -1: not a vertex) *)
   ChkNow: REAL ;
   (* events at the current instant (the "stuck" check) *)
   LastT: REAL ;
   Same: LONGINT ;
   (* the world *)
   Loaded: BOOLEAN ;           (* a scene was read and started *)
   WorldT: REAL ;              (* s: the world's current time *)
   Failed: BOOLEAN ;           (* the world failed: ErrMsg says why; every call now fails *)
   ErrMsg: ARRAY [0..MsgLen] OF CHAR ;
   Inf: REAL ;                 (* +infinity *)
   (* the contacts handled since the last report (Advance, Finish) *)
   Contacts: ContactArray ;
   NContacts, CapContacts: INTEGER ;
   Reporting: BOOLEAN ;        (* a ContactProc is being called *)
   NAdded: INTEGER ;           (* bodies added by AddBody (a recording refuses them) *)
   Unpaid: BOOLEAN ;           (* a hop since sleeper_impulse cleared it added energy (pay_floor could not pay) *)
   EdgePolys: EdgePolyArray ;  (* bound_polygon's polynomials, one per edge of the polygon *)
   Mark: LONGINT ;             (* the mark of the last large_near (walls_in lists a body once per mark) *)
   Near: IntList ;             (* large_near's and handle_cell's list of large bodies *)
   CapNear: INTEGER ;
   (* the bodies that left their support or carrier (leave), in order, with
      the body each one's prediction skips (-1: none): LeftBody^[k],
      LeftSkip^[k] for k < NLeft; predict_released predicts them *)
   LeftBody, LeftSkip: IntList ;
   NLeft, CapLeft: INTEGER ;
   CapEdgePolys: INTEGER ;
   (* the contacts handled at the instant TouchedT (touch): Touched^[0 .. NTouched - 1] *)
   TouchedT: REAL ;
   Touched: TouchArray ;
   NTouched, CapTouched: INTEGER ;
   (* the cluster being solved (handle_cluster): its contacts Rows^[0 .. NRows - 1],
      its moving bodies Movers^[0 .. NMovers - 1] (room for CapRows and 2 CapRows) *)
   Rows: RowArray ;
   NRows, CapRows: INTEGER ;
   Movers: MoverArray ;
   NMovers: INTEGER ;
   Pushes: PushArray ;         (* wedged's pushes (room for 2 CapRows + 1) *)
   (* cluster's bodies that join; handle_cluster's bodies whose state is
      written and those predicted (or asleep) *)
   Joined, Written, Finished: IntList ;
   NJoined, CapJoined, CapWritten, NFinished, CapFinished: INTEGER ;


(* ---- errors ------------------------------------------------------------ *)

(* Appends t to s (0C-terminated, cut at HIGH (s)). *)
PROCEDURE Append (VAR s: ARRAY OF CHAR; t: ARRAY OF CHAR) ;
VAR
   n, k: CARDINAL ;
BEGIN
   n := 0 ;
   WHILE (n < HIGH (s)) AND (s[n] # 0C) DO INC (n) END ;
   k := 0 ;
   WHILE (n < HIGH (s)) AND (k <= HIGH (t)) AND (t[k] # 0C) DO
      s[n] := t[k] ;
      INC (n) ;
      INC (k)
   END ;
   s[n] := 0C
END Append ;


(* Appends x as "%.17g" writes it. *)
PROCEDURE AppendReal (VAR s: ARRAY OF CHAR; x: REAL) ;
VAR
   d: ARRAY [0..39] OF CHAR ;
BEGIN
   d[0] := 0C ;
   IF snprintf (ADR (d), 40, "%.17g", x) > 0 THEN Append (s, d) END
END AppendReal ;


PROCEDURE AppendInt (VAR s: ARRAY OF CHAR; v: LONGINT) ;
VAR
   d: ARRAY [0..39] OF CHAR ;
BEGIN
   d[0] := 0C ;
   IF snprintf (ADR (d), 40, "%ld", v) > 0 THEN Append (s, d) END
END AppendInt ;


(* The world fails with this message (the reference's SimError): the trace
   stops here, and every later call returns FALSE. *)
PROCEDURE Fails (msg: ARRAY OF CHAR) ;
BEGIN
   IF Failed THEN RETURN END ;
   Failed := TRUE ;
   ErrMsg[0] := 0C ;
   Append (ErrMsg, msg) ;
   SetOn (FALSE)
END Fails ;


(* A call that is refused (the reference raises SimError): FALSE with msg
   as the message; the world goes on. *)
PROCEDURE Refuse (msg: ARRAY OF CHAR) : BOOLEAN ;
BEGIN
   ErrMsg[0] := 0C ;
   Append (ErrMsg, msg) ;
   RETURN FALSE
END Refuse ;


(* FALSE (with the message) when there is no world or it failed. *)
PROCEDURE Usable () : BOOLEAN ;
BEGIN
   IF Failed THEN RETURN FALSE END ;   (* the failure's message stays *)
   IF NOT Loaded THEN RETURN Refuse ("no world: call New, FromFile or FromStdin first") END ;
   IF Reporting THEN RETURN Refuse ("the world cannot be driven from inside its ContactProc") END ;
   RETURN TRUE
END Usable ;


PROCEDURE Error (VAR msg: ARRAY OF CHAR) ;
BEGIN
   msg[0] := 0C ;
   Append (msg, ErrMsg)
END Error ;


(* ---- motion ------------------------------------------------------------ *)

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


(* ---- the event queue --------------------------------------------------- *)

(* Queues ev (its t, kind and record set) as the next in scheduling order. *)
PROCEDURE push (VAR ev: Event) ;
BEGIN
   ev.seq := Seq ;
   IF NOT Push (ev) THEN Fails ("out of memory (event queue)") END ;
   INC (Seq)
END push ;


PROCEDURE push_collision (t: REAL; feature: INTEGER; A, B: BodyRef; i, j: INTEGER) ;
VAR
   ev: Event ;
BEGIN
   ev.t := t ;
   ev.kind := KCollision ;
   ev.collision.a := A^.idx ;
   ev.collision.b := B^.idx ;
   ev.collision.feature := feature ;
   ev.collision.i := i ;
   ev.collision.j := j ;
   ev.collision.stamp_a := A^.stamp ;
   ev.collision.stamp_b := B^.stamp ;
   push (ev)
END push_collision ;


PROCEDURE push_horizon (t: REAL; A, B: BodyRef) ;
VAR
   ev: Event ;
BEGIN
   ev.t := t ;
   ev.kind := KHorizon ;
   ev.horizon.a := A^.idx ;
   ev.horizon.b := B^.idx ;
   ev.horizon.stamp_a := A^.stamp ;
   ev.horizon.stamp_b := B^.stamp ;
   push (ev)
END push_horizon ;


PROCEDURE push_frame (t: REAL; k: INTEGER) ;
VAR
   ev: Event ;
BEGIN
   ev.t := t ;
   ev.kind := KFrame ;
   ev.frame.k := k ;
   push (ev)
END push_frame ;


(* ---- helpers ---------------------------------------------------------- *)

PROCEDURE Max (a, b: INTEGER) : INTEGER ;
BEGIN
   IF a > b THEN RETURN a END ;
   RETURN b
END Max ;


PROCEDURE Min (a, b: INTEGER) : INTEGER ;
BEGIN
   IF a < b THEN RETURN a END ;
   RETURN b
END Min ;


(* ---- first valid root of one feature ----------------------------------- *)

(* A neighbour of X's vertex i at t lies more than the tolerance behind the
   line (c, sn) . (p - (qx, qy)) = h (an edge's line: its outward unit
   normal (c, sn), its body's centre (qx, qy)), previous neighbour first
   (docs/simulator.md, "Corners"). *)
PROCEDURE behind (X: BodyRef; i: INTEGER; t, qx, qy, c, sn, h: REAL) : BOOLEAN ;
VAR
   px, py, pvx, pvy, pa, lim, kx, ky: REAL ;
   n, m, k: INTEGER ;
   v: Vertex ;
BEGIN
   n := X^.nv ;
   StateAt (X, t, px, py, pvx, pvy, pa) ;
   lim := -Tol ;
   FOR m := 0 TO 1 DO
      IF m = 0 THEN k := (i + n - 1) MOD n ELSE k := (i + 1) MOD n END ;
      v := Verts^[X^.v0 + k] ;
      kx := px + v.rho * cos (pa + v.beta) ;
      ky := py + v.rho * sin (pa + v.beta) ;
      IF (kx - qx) * c + (ky - qy) * sn - h < lim THEN RETURN TRUE END
   END ;
   RETURN FALSE
END behind ;


(* The point-edge check of predict_pe: whether the contact at s lies on the
   edge (within the tolerance) and, when the point is X's vertex ChkVert,
   neither of its neighbours lies behind the edge's line (behind); the
   prediction sets Chk*. *)
PROCEDURE Inside (s: REAL) : BOOLEAN ;
VAR
   t, px, py, pvx, pvy, pa, qx, qy, qvx, qvy, qa, th, c, sn, along: REAL ;
   ed: Vertex ;
BEGIN
   ed := Verts^[ChkEdge] ;
   t := ChkNow + s ;
   StateAt (ChkX, t, px, py, pvx, pvy, pa) ;
   IF ChkRho # 0.0 THEN
      px := px + ChkRho * cos (pa + ChkBeta) ;
      py := py + ChkRho * sin (pa + ChkBeta)
   END ;
   StateAt (ChkY, t, qx, qy, qvx, qvy, qa) ;
   th := qa + ed.psi ;
   c := cos (th) ;
   sn := sin (th) ;
   along := (px - qx) * (-sn) + (py - qy) * c ;
   IF NOT ((ed.s1 - Tol <= along) AND (along <= ed.s2 + Tol)) THEN RETURN FALSE END ;
   IF ChkVert < 0 THEN RETURN TRUE END ;
   RETURN NOT behind (ChkX, ChkVert, t, qx, qy, c, sn, ed.h)
END Inside ;


PROCEDURE Check (edge: BOOLEAN; s: REAL) : BOOLEAN ;
BEGIN
   IF edge THEN RETURN Inside (s) END ;
   RETURN TRUE
END Check ;


(* At a zero s of the gap c: approaching (first derivative d < 0), or
   resting and pressed together (d = 0, second derivative < 0). *)
PROCEDURE pressing (VAR c: ARRAY OF REAL; deg: INTEGER; d, s: REAL) : BOOLEAN ;
VAR
   dd: REAL ;
   k: INTEGER ;
BEGIN
   IF d < 0.0 THEN RETURN TRUE END ;
   IF (d # 0.0) OR (deg < 2) THEN RETURN FALSE END ;
   dd := 0.0 ;
   FOR k := deg TO 2 BY -1 DO
      dd := dd * s + VAL (REAL, k * (k - 1)) * c[k]
   END ;
   RETURN dd < 0.0
END pressing ;


(* At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
   pressed together (c2 < 0) so that the gap closes again before it ever
   exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.  (A
   resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.) *)
PROCEDURE touching_now (VAR c: ARRAY OF REAL; deg: INTEGER; kappa: REAL) : BOOLEAN ;
BEGIN
   IF c[1] < 0.0 THEN RETURN TRUE END ;
   IF (deg < 2) OR NOT (c[2] < 0.0) THEN RETURN FALSE END ;
   RETURN c[0] + c[1] * c[1] / (4.0 * (-c[2])) <= kappa
END touching_now ;


(* The smallest s in [0, w] where the gap c(s) reaches zero while
   decreasing, or touches zero with zero slope while pressed together
   (resting contact), and the check holds (edge: Inside, else always).  At
   s = 0 the gap counts as zero within kappa: approaching or pressed
   (touching_now) means contact now, separating or merely touching never. *)
PROCEDURE FirstContact (VAR c: ARRAY OF REAL; deg: INTEGER; w, kappa: REAL; edge: BOOLEAN;
                        VAR s: REAL) : BOOLEAN ;
VAR
   lo, d: REAL ;
   it, k: INTEGER ;
BEGIN
   IF (deg >= 1) AND (ABS (c[0]) <= kappa) AND touching_now (c, deg, kappa) AND Check (edge, 0.0) THEN
      s := 0.0 ;
      RETURN TRUE
   END ;
   lo := 0.0 ;
   FOR it := 0 TO deg + 1 DO
      IF NOT SmallestRoot (c, deg, lo, w, s) THEN RETURN FALSE END ;
      d := 0.0 ;
      FOR k := deg TO 1 BY -1 DO
         d := d * s + VAL (REAL, k) * c[k]
      END ;
      IF pressing (c, deg, d, s) AND Check (edge, s) THEN RETURN TRUE END ;
      lo := s
   END ;
   RETURN FALSE
END FirstContact ;


(* ---- features ------------------------------------------------------------ *)

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


(* circle_circle parameters of a circle's centre (v < 0) or of a polygon's
   vertex v, at time now: x, vx, ax, d, e (= om), f (= phase + pi/2);
   y, vy, ay, p (= om), q (= phase). *)
PROCEDURE CircleParams (b: BodyRef; now: REAL; v: INTEGER;
                        VAR x, vx, ax, d, e, f, y, vy, ay, p, q: REAL) ;
VAR
   ang, phase, om: REAL ;
BEGIN
   StateAt (b, now, x, y, vx, vy, ang) ;
   IF v < 0 THEN
      d := b^.orbit ;
      phase := ang + b^.ophase
   ELSE
      d := Verts^[v].rho ;
      phase := ang + Verts^[v].beta
   END ;
   om := b^.om ;
   IF (om = 0.0) AND (d # 0.0) THEN
      (* an orbit that does not turn is a fixed offset: fold it in *)
      x := x + d * cos (phase) ;
      y := y + d * sin (phase) ;
      d := 0.0
   END ;
   IF d = 0.0 THEN
      om := 0.0 ;
      phase := 0.0
   END ;
   ax := b^.ax ;
   e := om ;
   f := phase + HalfPi ;
   ay := b^.ay ;
   p := om ;
   q := phase
END CircleParams ;


(* The generated circle_circle selection: counts the variant, fills coef and
   returns its degree. *)
PROCEDURE CcCoefficients (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z: REAL;
                          VAR coef: ARRAY OF REAL) : INTEGER ;
VAR
   idx: INTEGER ;
BEGIN
   idx := circle_circle_variant (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z) ;
   IF (idx < 0) OR (idx >= CcVariants) THEN
      Fails ("circle_circle: the scene uses an effect the generated code leaves out") ;
      coef[0] := 1.0 ;
      RETURN 0                 (* no contact: the world has failed, nothing more is handled *)
   END ;
   INC (CcCounts[idx]) ;
   INC (Stats.features) ;
   RETURN circle_circle_coefficients (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z,
                                      coef)
END CcCoefficients ;


(* Counts a circle_circle prediction that CirclesApart decided: its variant
   and the features counter, as CcCoefficients would. *)
PROCEDURE CcCount (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z: REAL) ;
VAR
   idx: INTEGER ;
BEGIN
   idx := circle_circle_variant (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z) ;
   IF (idx < 0) OR (idx >= CcVariants) THEN
      Fails ("circle_circle: the scene uses an effect the generated code leaves out") ;
      RETURN
   END ;
   INC (CcCounts[idx]) ;
   INC (Stats.features)
END CcCount ;


(* The circle_circle parameters of a moving circle's centre (CircleParams
   or CentreParams), in the order x, vx, ax, d, e, f, y, vy, ay, p, q. *)
TYPE
   CParams = ARRAY [0..10] OF REAL ;


PROCEDURE CircleParamsOf (b: BodyRef; now: REAL; v: INTEGER; VAR c: CParams) ;
BEGIN
   CircleParams (b, now, v, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10])
END CircleParamsOf ;


(* circle_circle parameters of b's centre of rotation at time now, no orbit:
   the centre of a bounding circle (CircleParams of a polygon). *)
PROCEDURE CentreParams (b: BodyRef; now: REAL; VAR c: CParams) ;
VAR
   ang: REAL ;
BEGIN
   StateAt (b, now, c[0], c[6], c[1], c[7], ang) ;
   c[2] := b^.ax ;
   c[3] := 0.0 ;
   c[4] := 0.0 ;
   c[5] := HalfPi ;
   c[8] := b^.ay ;
   c[9] := 0.0 ;
   c[10] := 0.0
END CentreParams ;


(* The first contact within [0, w] of a circle of radius ra moving as pa
   and one of radius rb moving as pb. *)
PROCEDURE CirclesFirst (VAR pa: CParams; ra: REAL; VAR pb: CParams; rb, w: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   kappa: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   kappa := Tol * (2.0 * (ra + rb) + Tol) ;
   IF (pa[2] - pb[2] = 0.0) AND (pa[8] - pb[8] = 0.0) AND (pa[3] = 0.0) AND (pb[3] = 0.0)
      AND CirclesApart (pa[0] - pb[0], pa[1] - pb[1], pa[6] - pb[6], pa[7] - pb[7], ra + rb, kappa) THEN
      CcCount (pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2], pa[3], pa[4], pa[5],
               pa[6] - pb[6], pa[7] - pb[7], pa[8] - pb[8], pa[9], pa[10],
               0.0, 0.0, 0.0, pb[3], pb[4], pb[5], 0.0, 0.0, 0.0, pb[9], pb[10], ra, rb) ;
      RETURN FALSE
   END ;
   deg := circles_gap (pa, ra, pb, rb, coef) ;
   RETURN FirstContact (coef, deg, w, kappa, FALSE, t)
END CirclesFirst ;


(* The reference's circles_apart, for a pair whose circles do not orbit and
   whose relative acceleration is zero (CirclesFirst tests that): relative
   position (x, y), velocity (vx, vy), r = ra + rb.  The pair surely has no
   contact, decided without the polynomial (docs/simulator.md, "Pairs that
   stay apart"): the centres separate (p . v > 0 by more than its rounding),
   or they approach on a line that passes farther than r from each other
   ((p x v)^2 > (r^2 + kappa) |v|^2 by more than the rounding); sizes
   bounded so that nothing underflows or overflows. *)
PROCEDURE CirclesApart (x, vx, y, vy, r, kappa: REAL) : BOOLEAN ;
VAR
   px, py, size, v2, p2, cross: REAL ;
BEGIN
   px := x * vx ;
   py := y * vy ;
   size := ABS (px) + ABS (py) ;
   IF (size >= TwoM900) AND (px + py > TwoM40 * size) THEN
      RETURN TRUE
   END ;
   v2 := vx * vx + vy * vy ;
   p2 := x * x + y * y ;
   IF NOT ((v2 >= TwoM450) AND (v2 <= TwoP450) AND (p2 >= TwoM450) AND (p2 <= TwoP450)) THEN
      RETURN FALSE
   END ;
   cross := x * vy - y * vx ;
   RETURN cross * cross - (r * r + kappa) * v2 > TwoM30 * p2 * v2
END CirclesApart ;


(* The circle_circle polynomial (squared distance of the centres less
   (ra + rb)^2, in s from the parameters' time) of a circle of radius ra
   moving as pa (CircleParams) and one of radius rb moving as pb: fills coef
   and returns its degree. *)
PROCEDURE circles_gap (VAR pa: CParams; ra: REAL; VAR pb: CParams; rb: REAL; VAR coef: ARRAY OF REAL) : INTEGER ;
BEGIN
   (* only differences of the centres' motions matter: circle 1 moves
      relative to circle 2's centre of rotation, so that a common gravity
      cancels (no_accel variants) and far from the origin nothing is lost *)
   RETURN CcCoefficients (pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2], pa[3], pa[4], pa[5],
                          pa[6] - pb[6], pa[7] - pb[7], pa[8] - pb[8], pa[9], pa[10],
                          0.0, 0.0, 0.0, pb[3], pb[4], pb[5], 0.0, 0.0, 0.0, pb[9], pb[10], ra, rb, coef)
END circles_gap ;


(* Circle of A against circle of B (vb < 0, radius rb) or vertex vb of B
   (radius 0). *)
PROCEDURE PredictCC (A, B: BodyRef; vb: INTEGER; rb, now, w: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   pa, pb: CParams ;
BEGIN
   CircleParamsOf (A, now, -1, pa) ;
   CircleParamsOf (B, now, vb, pb) ;
   RETURN CirclesFirst (pa, A^.r, pb, rb, w, t)
END PredictCC ;


(* The point_edge polynomial of a circle of radius rad whose centre orbits
   X's centre at rho (phase beta in X's frame) against the line of edge j of
   Y, in s = t - now (its coef[0]: the gap now): its degree, or -1 when the
   generated code leaves the effect out (the world has failed). *)
PROCEDURE PeCoefficients (X, Y: BodyRef; rho, beta, rad: REAL; j: INTEGER; now: REAL;
                          VAR coef: ARRAY OF REAL) : INTEGER ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2: REAL ;
   phn, wr, phr, h: REAL ;
   ed: INTEGER ;
   idx: INTEGER ;
   a1, a2, a3, a4, a5, a6: REAL ;
BEGIN
   ed := Y^.v0 + j ;
   StateAt (X, now, x1, y1, u1, v1, ang1) ;
   StateAt (Y, now, x2, y2, u2, v2, ang2) ;
   phn := ang2 + Verts^[ed].psi ;
   wr := X^.om - Y^.om ;
   phr := (ang1 + beta) - phn ;
   h := Verts^[ed].h + rad ;
   IF (wr = 0.0) AND (rho # 0.0) THEN
      (* the point does not turn relative to the edge: its offset along the
         normal is a constant, folded into the line's offset *)
      h := h - rho * cos (phr) ;
      rho := 0.0
   END ;
   a1 := x1 - x2 ;
   a2 := u1 - u2 ;
   a3 := X^.ax - Y^.ax ;
   a4 := y1 - y2 ;
   a5 := v1 - v2 ;
   a6 := X^.ay - Y^.ay ;
   idx := point_edge_variant (a1, a2, a3, a4, a5, a6, rho, wr, phr, Y^.om, phn, h) ;
   IF (idx < 0) OR (idx >= PeVariants) THEN
      Fails ("point_edge: the scene uses an effect the generated code leaves out") ;
      coef[0] := 1.0 ;
      RETURN -1                (* the world has failed, nothing more is handled *)
   END ;
   INC (PeCounts[idx]) ;
   INC (Stats.features) ;
   RETURN point_edge_coefficients (a1, a2, a3, a4, a5, a6, rho, wr, phr, Y^.om, phn, h, coef)
END PeCoefficients ;


(* The first contact within [0, w] of PeCoefficients' polynomial (degree
   deg; none when deg < 0) whose point (X's centre, or rho, beta about it)
   lies on edge j's segment; when the point is X's vertex i (i >= 0), both
   neighbours of that vertex must also lie no more than the tolerance behind
   edge j's line (behind: else that line does not separate the bodies
   there, a corner meeting a corner: another feature pair is the contact). *)
PROCEDURE PeFirst (VAR coef: ARRAY OF REAL; deg: INTEGER; X, Y: BodyRef; rho, beta: REAL; j: INTEGER;
                   now, w: REAL; i: INTEGER; VAR t: REAL) : BOOLEAN ;
BEGIN
   IF deg < 0 THEN RETURN FALSE END ;
   ChkX := X ;
   ChkY := Y ;
   ChkRho := rho ;
   ChkBeta := beta ;
   ChkEdge := Y^.v0 + j ;
   ChkVert := i ;
   ChkNow := now ;
   RETURN FirstContact (coef, deg, w, Tol, TRUE, t)
END PeFirst ;


(* Point of X (circle centre with radius, vx < 0, or vertex vx: the index in
   Verts of X's vertex vx - X^.v0) against the line of edge j of Y (none while a fixed body covers the edge: its cover
   is not gone; nothing is counted). *)
PROCEDURE PredictPE (X, Y: BodyRef; vx, j: INTEGER; now, w: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   rho, beta, rad: REAL ;
   deg, cover: INTEGER ;
   coef: ARRAY [0..PeMaxDegree] OF REAL ;
BEGIN
   cover := Verts^[Y^.v0 + j].cover ;
   IF (cover >= 0) AND (cover < NBodies) AND NOT Bodies^[cover].gone THEN RETURN FALSE END ;
   IF vx < 0 THEN
      rho := X^.orbit ;
      beta := X^.ophase ;
      rad := X^.r
   ELSE
      rho := Verts^[vx].rho ;
      beta := Verts^[vx].beta ;
      rad := 0.0
   END ;
   deg := PeCoefficients (X, Y, rho, beta, rad, j, now, coef) ;
   IF vx < 0 THEN
      RETURN PeFirst (coef, deg, X, Y, rho, beta, j, now, w, -1, t)
   END ;
   RETURN PeFirst (coef, deg, X, Y, rho, beta, j, now, w, vx - X^.v0, t)
END PredictPE ;


(* ---- pairs ----------------------------------------------------------------- *)

(* The best contact of a pair so far. *)
TYPE
   Best = RECORD
      found: BOOLEAN ;
      t: REAL ;
      feat, a, b, i, j: INTEGER ;
   END ;


PROCEDURE Better (VAR best: Best; found: BOOLEAN; t: REAL; feat, a, b, i, j: INTEGER) ;
BEGIN
   IF found AND ((NOT best.found) OR (t < best.t)) THEN
      best.found := TRUE ;
      best.t := t ;
      best.feat := feat ;
      best.a := a ;
      best.b := b ;
      best.i := i ;
      best.j := j
   END
END Better ;


(* T turns, polygon P does not: when T's bounding circle (radius T.bound
   about T's centre of rotation, which does not turn) first touches P itself
   (its edges, then its vertices) within (0, w]: TRUE and meet = 0.0 when no
   edge line of P has the circle beyond it by more than the tolerance now
   (overlapping, or near a corner), TRUE and meet > 0 when they touch later,
   FALSE when they do not meet.  Exact: neither the circle nor P turns. *)
PROCEDURE bound_polygon (T, P: BodyRef; now, w: REAL; VAR meet: REAL) : BOOLEAN ;
VAR
   j, k: INTEGER ;
   apart, found, got: BOOLEAN ;
   t: REAL ;
   pt, pv: CParams ;
BEGIN
   IF P^.nv > CapEdgePolys THEN
      CapEdgePolys := P^.nv ;
      EdgePolys := Grow (EdgePolys, CapEdgePolys, SIZE (EdgePoly))
   END ;
   apart := FALSE ;
   FOR j := 0 TO P^.nv - 1 DO
      EdgePolys^[j].deg := PeCoefficients (T, P, 0.0, 0.0, T^.bound, j, now, EdgePolys^[j].c) ;
      IF EdgePolys^[j].c[0] > Tol THEN apart := TRUE END
   END ;
   IF NOT apart THEN
      meet := 0.0 ;
      RETURN TRUE
   END ;
   found := FALSE ;
   meet := 0.0 ;
   FOR j := 0 TO P^.nv - 1 DO
      got := PeFirst (EdgePolys^[j].c, EdgePolys^[j].deg, T, P, 0.0, 0.0, j, now, w, -1, t) ;
      IF got AND ((NOT found) OR (t < meet)) THEN
         found := TRUE ;
         meet := t
      END
   END ;
   CentreParams (T, now, pt) ;
   FOR k := 0 TO P^.nv - 1 DO
      CircleParamsOf (P, now, P^.v0 + k, pv) ;
      got := CirclesFirst (pt, T^.bound, pv, 0.0, w, t) ;
      IF got AND ((NOT found) OR (t < meet)) THEN
         found := TRUE ;
         meet := t
      END
   END ;
   RETURN found
END bound_polygon ;


(* When the bounding circles first touch within (0, w]: TRUE and meet = 0.0
   when they overlap or touch now (within the tolerance), TRUE and meet > 0
   when they touch later, FALSE when they do not meet (exact: bounding
   circles do not turn). *)
PROCEDURE BoundsMeet (A, B: BodyRef; now, w: REAL; VAR meet: REAL) : BOOLEAN ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   StateAt (A, now, x1, y1, u1, v1, ang1) ;
   StateAt (B, now, x2, y2, u2, v2, ang2) ;
   deg := CcCoefficients (x1 - x2, u1 - u2, A^.ax - B^.ax, 0.0, 0.0, HalfPi, y1 - y2, v1 - v2, A^.ay - B^.ay,
                          0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, HalfPi, 0.0, 0.0, 0.0, 0.0, 0.0,
                          A^.bound, B^.bound, coef) ;
   IF coef[0] <= Tol * (2.0 * (A^.bound + B^.bound) + Tol) THEN
      meet := 0.0 ;
      RETURN TRUE
   END ;
   RETURN SmallestRoot (coef, deg, 0.0, w, meet)
END BoundsMeet ;


PROCEDURE CirclePolygon (C, P: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   j, k: INTEGER ;
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   FOR j := 0 TO P^.nv - 1 DO
      found := PredictPE (C, P, -1, j, now, w, t) ;
      Better (best, found, t, FeatPE, C^.idx, P^.idx, -1, j)
   END ;
   FOR k := 0 TO P^.nv - 1 DO
      found := PredictCC (C, P, P^.v0 + k, 0.0, now, w, t) ;
      Better (best, found, t, FeatCC, C^.idx, P^.idx, -1, k)
   END
END CirclePolygon ;


PROCEDURE VerticesEdges (A, B: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   i, j: INTEGER ;
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   FOR i := 0 TO A^.nv - 1 DO
      FOR j := 0 TO B^.nv - 1 DO
         found := PredictPE (A, B, A^.v0 + i, j, now, w, t) ;
         Better (best, found, t, FeatPE, A^.idx, B^.idx, i, j)
      END
   END
END VerticesEdges ;


(* The earliest contact of A's and B's features within [0, w] after now
   (circle-circle, circle-polygon, or A's vertices on B's edges then B's on
   A's): best.found and its fields, else not best.found. *)
PROCEDURE Features (A, B: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   best.found := FALSE ;
   best.t := 0.0 ;
   IF (NOT A^.polygon) AND (NOT B^.polygon) THEN
      found := PredictCC (A, B, -1, B^.r, now, w, t) ;
      Better (best, found, t, FeatCC, A^.idx, B^.idx, -1, -1)
   ELSIF NOT A^.polygon THEN
      CirclePolygon (A, B, now, w, best)
   ELSIF NOT B^.polygon THEN
      CirclePolygon (B, A, now, w, best)
   ELSE
      VerticesEdges (A, B, now, w, best) ;
      VerticesEdges (B, A, now, w, best)
   END
END Features ;


(* The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
   +infinity when it has none (r <= 0 and q = 0). *)
PROCEDURE clear_root (g, r, q: REAL) : REAL ;
BEGIN
   IF NOT (g > 0.0) THEN RETURN 0.0 END ;
   IF r > 0.0 THEN RETURN 2.0 * g / (r + sqrt (r * r + 2.0 * q * g)) END ;
   IF q > 0.0 THEN RETURN (sqrt (r * r + 2.0 * q * g) - r) / q END ;
   RETURN Inf
END clear_root ;


(* The largest projection of b on the unit axis (nx, ny) at now (a circle:
   its centre's plus its radius). *)
PROCEDURE reach (b: BodyRef; nx, ny, now: REAL) : REAL ;
VAR
   px, py, best, d: REAL ;
   k: INTEGER ;
BEGIN
   IF NOT b^.polygon THEN
      PointAt (b, -1, now, px, py) ;
      RETURN nx * px + ny * py + b^.r
   END ;
   best := -Inf ;
   FOR k := 0 TO b^.nv - 1 DO
      PointAt (b, b^.v0 + k, now, px, py) ;
      d := nx * px + ny * py ;
      IF d > best THEN best := d END        (* Python's max(best, d) *)
   END ;
   RETURN best
END reach ;


(* clear_time along each edge normal of P (P does not turn, T does): the
   largest of the times. *)
PROCEDURE clear_axes (T, P: BodyRef; now: REAL) : REAL ;
VAR
   x1, y1, u1, v1, a1, x2, y2, u2, v2, a2, du, dv, dax, day, spin, best, ox, oy, off, c: REAL ;
   j: INTEGER ;
BEGIN
   StateAt (T, now, x1, y1, u1, v1, a1) ;
   StateAt (P, now, x2, y2, u2, v2, a2) ;
   du := u1 - u2 ;
   dv := v1 - v2 ;
   dax := T^.ax - P^.ax ;
   day := T^.ay - P^.ay ;
   spin := T^.bound * TurnRate (T) ;
   best := 0.0 ;
   FOR j := 0 TO P^.nv - 1 DO
      edge_line (P, j, now, ox, oy, off) ;
      c := clear_root (-reach (T, -ox, -oy, now) - off - Tol, spin - (ox * du + oy * dv),
                       ABS (ox * dax + oy * day)) ;
      IF c > best THEN best := c END        (* Python's max(best, c) *)
   END ;
   RETURN best
END clear_axes ;


(* How long A and B surely stay more than the tolerance apart, from their
   gap g along a fixed unit axis n now (0 when not apart now): along n the
   gap changes by (dv . n) s + (da . n) s^2/2 from the centres' relative
   motion and closes by at most spin s from the turns (spin: each turning
   body's bound times its turn rate), so it stays above the tolerance for s
   below the positive root of |da . n|/2 s^2 + r s - (g - tol),
   r = spin - dv . n (clear_root).  The axes: P's edge normals when one body
   is a polygon P that does not turn and the other turns (clear_axes); else
   the larger of the line of the centres and the separating axis of
   separation (which may turn: unsigned norms). *)
PROCEDURE clear_time (A, B: BodyRef; now: REAL) : REAL ;
VAR
   x1, y1, u1, v1, a1, x2, y2, u2, v2, a2, dx, dy, d, nx, ny, hi, lo, spin, along, anyway: REAL ;
BEGIN
   IF B^.polygon AND (B^.om = 0.0) AND (TurnRate (A) > 0.0) THEN RETURN clear_axes (A, B, now) END ;
   IF A^.polygon AND (A^.om = 0.0) AND (TurnRate (B) > 0.0) THEN RETURN clear_axes (B, A, now) END ;
   StateAt (A, now, x1, y1, u1, v1, a1) ;
   StateAt (B, now, x2, y2, u2, v2, a2) ;
   dx := x2 - x1 ;
   dy := y2 - y1 ;
   d := sqrt (dx * dx + dy * dy) ;
   IF NOT (d > 0.0) THEN RETURN 0.0 END ;
   nx := dx / d ;
   ny := dy / d ;
   hi := reach (A, nx, ny, now) ;
   lo := -reach (B, -nx, -ny, now) ;
   spin := A^.bound * TurnRate (A) + B^.bound * TurnRate (B) ;
   along := clear_root (lo - hi - Tol, spin - (nx * (u2 - u1) + ny * (v2 - v1)),
                        ABS (nx * (B^.ax - A^.ax) + ny * (B^.ay - A^.ay))) ;
   (* and along the best separating axis, which may turn: the norms, |x| + |y| *)
   anyway := clear_root (separation (A, B, now) - Tol, spin + ABS (u2 - u1) + ABS (v2 - v1),
                         ABS (B^.ax - A^.ax) + ABS (B^.ay - A^.ay)) ;
   IF anyway > along THEN RETURN anyway END ;     (* Python's max(along, anyway) *)
   RETURN along
END clear_time ;


(* Schedules the first contact of A and B after now, or a horizon event
   where the Taylor polynomials of their turns stop being good.  Cheap
   steps chain: a later meeting of the bounds or a clear stretch moves now
   on (up to Chain stages, at most one Taylor window). *)
PROCEDURE PredictPair (A, B: BodyRef; now: REAL) ;
VAR
   w, ta, tb, q, meet, clear: REAL ;
   best: Best ;
   found, windowed: BOOLEAN ;
   stage: INTEGER ;
BEGIN
   IF (A^.sup = B^.idx) OR (B^.sup = A^.idx) THEN
      RETURN      (* the support's edge line separates them (both convex): only leaving ends it *)
   END ;
   IF (A^.asleep AND grounded (B)) OR (B^.asleep AND grounded (A)) THEN
      RETURN      (* a sleeper against a sleeper or an unmoving fixed body: nothing moves *)
   END ;
   INC (Stats.pairs) ;
   ta := TurnRate (A) ;
   tb := TurnRate (B) ;
   windowed := FALSE ;
   stage := 0 ;
   LOOP
      IF stage = Chain THEN EXIT END ;
      INC (stage) ;
      w := EndT - now ;
      IF NOT (w > 0.0) THEN RETURN END ;
      meet := 0.0 ;
      IF A^.polygon OR B^.polygon THEN
         (* bounds that do not turn: until they touch, nothing can *)
         IF B^.polygon AND (ta > 0.0) AND (B^.om = 0.0) THEN
            found := bound_polygon (A, B, now, w, meet)
         ELSIF A^.polygon AND (tb > 0.0) AND (A^.om = 0.0) THEN
            found := bound_polygon (B, A, now, w, meet)
         ELSE
            found := BoundsMeet (A, B, now, w, meet)
         END ;
         IF NOT found THEN RETURN END
      END ;
      IF meet > 0.0 THEN
         now := now + meet              (* the next stage from there *)
      ELSE
         q := w ;
         IF (ta > 0.0) AND (tb > 0.0) THEN
            q := Alpha / (ta + tb)
         ELSIF ta > 0.0 THEN
            q := A^.window / ta         (* only A turns: its own lever's window *)
         ELSIF tb > 0.0 THEN
            q := B^.window / tb
         END ;
         IF q < w THEN w := q END ;     (* Python's min(w, q) *)
         clear := 0.0 ;
         IF (ta > 0.0) OR (tb > 0.0) THEN clear := clear_time (A, B, now) END ;
         IF ((ta > 0.0) OR (tb > 0.0)) AND (clear >= w) THEN
            (* apart all through the window, whatever the turns do: no roots
               to solve until they may come within the tolerance *)
            now := now + clear
         ELSE
            IF windowed THEN EXIT END ;   (* one Taylor window per prediction: the next at a horizon *)
            Features (A, B, now, w, best) ;
            IF best.found THEN
               push_collision (now + best.t, best.feat, ADR (Bodies^[best.a]), ADR (Bodies^[best.b]), best.i,
                               best.j) ;
               RETURN
            END ;
            IF (ta = 0.0) AND (tb = 0.0) THEN RETURN END ;   (* nothing turns: the window was the whole run *)
            now := now + w ;
            windowed := TRUE
         END
      END
   END ;
   IF now < EndT THEN push_horizon (now, A, B) END
END PredictPair ;


(* ---- per body -------------------------------------------------------------- *)

(* Predicts b against every other body o in the cells [xlo..xhi] x [ylo..yhi]
   (clipped to the grid) with o.idx > above and o.idx # skip, unless both
   are fixed. *)
PROCEDURE PredictCells (b: BodyRef; xlo, xhi, ylo, yhi, above, skip: INTEGER; now: REAL) ;
VAR
   jx, jy, c, k, oi: INTEGER ;
   o: BodyRef ;
BEGIN
   FOR jy := Max (ylo, 0) TO Min (yhi, GridNY - 1) DO
      FOR jx := Max (xlo, 0) TO Min (xhi, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Cells^[c].n - 1 DO
            oi := Cells^[c].items^[k] ;
            IF (oi # b^.idx) AND (oi > above) AND (oi # skip) THEN
               o := ADR (Bodies^[oi]) ;
               IF NOT (b^.fixed AND o^.fixed) THEN
                  PredictPair (b, o, now)
               END
            END
         END
      END
   END
END PredictCells ;


(* A large body into the grid's walls when it is fixed and does not move
   (v = a = 0): its box (a polygon that does not turn: its vertices at its
   time; else its centre +- bound) in cells, every cell from CellOf (the
   box's low corner) to CellOf (its high corner), each cell's list in the
   order bodies are placed; else into the large list. *)
PROCEDURE place_large (b: BodyRef) ;
VAR
   x0, y0, x1, y1, x, y: REAL ;
   k, i0, j0, i1, j1, jx, jy: INTEGER ;
BEGIN
   IF NOT (b^.fixed AND (b^.vx = 0.0) AND (b^.vy = 0.0) AND (b^.ax = 0.0) AND (b^.ay = 0.0)) THEN
      LargeAdd (b^.idx) ;
      RETURN
   END ;
   IF b^.polygon AND (b^.om = 0.0) THEN
      PointAt (b, b^.v0, b^.tb, x0, y0) ;
      x1 := x0 ;
      y1 := y0 ;
      FOR k := 0 TO b^.nv - 1 DO
         PointAt (b, b^.v0 + k, b^.tb, x, y) ;
         (* Python's min and max: the first unless the second is beyond it *)
         IF x < x0 THEN x0 := x END ;
         IF x > x1 THEN x1 := x END ;
         IF y < y0 THEN y0 := y END ;
         IF y > y1 THEN y1 := y END
      END
   ELSE
      x0 := b^.px - b^.bound ;
      x1 := b^.px + b^.bound ;
      y0 := b^.py - b^.bound ;
      y1 := b^.py + b^.bound
   END ;
   CellOf (x0, y0, i0, j0) ;
   CellOf (x1, y1, i1, j1) ;
   b^.placed := TRUE ;
   b^.wi0 := i0 ;
   b^.wi1 := i1 ;
   b^.wj0 := j0 ;
   b^.wj1 := j1 ;
   FOR jy := j0 TO j1 DO
      FOR jx := i0 TO i1 DO
         WallAdd (jy * GridNX + jx, b^.idx)
      END
   END
END place_large ;


(* A large body out of the walls of its cells, or out of the large list. *)
PROCEDURE unplace_large (b: BodyRef) ;
VAR
   jx, jy: INTEGER ;
BEGIN
   IF NOT b^.placed THEN
      LargeRemove (b^.idx) ;
      RETURN
   END ;
   FOR jy := b^.wj0 TO b^.wj1 DO
      FOR jx := b^.wi0 TO b^.wi1 DO
         WallRemove (jy * GridNX + jx, b^.idx)
      END
   END
END unplace_large ;


(* Appends body i to Near^[n], n + 1. *)
PROCEDURE NearAdd (VAR n: INTEGER; i: INTEGER) ;
BEGIN
   IF n >= CapNear THEN
      IF CapNear = 0 THEN CapNear := 16 ELSE CapNear := 2 * CapNear END ;
      Near := Grow (Near, CapNear, SIZE (INTEGER))
   END ;
   Near^[n] := i ;
   INC (n)
END NearAdd ;


(* The placed large bodies listed in the cells xlo..xhi, ylo..yhi (clamped
   to the grid, rows then columns), but b and those already carrying the
   current mark, are marked and (keep) appended to Near^[n..]. *)
PROCEDURE walls_in (b: BodyRef; xlo, xhi, ylo, yhi: INTEGER; keep: BOOLEAN; VAR n: INTEGER) ;
VAR
   jx, jy, c, k, oi: INTEGER ;
BEGIN
   FOR jy := Max (ylo, 0) TO Min (yhi, GridNY - 1) DO
      FOR jx := Max (xlo, 0) TO Min (xhi, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Walls^[c].n - 1 DO
            oi := Walls^[c].items^[k] ;
            IF (Bodies^[oi].seen # Mark) AND (oi # b^.idx) THEN
               Bodies^[oi].seen := Mark ;
               IF keep THEN NearAdd (n, oi) END
            END
         END
      END
   END
END walls_in ;


(* Near^[0 .. n - 1] in index order (the indices differ). *)
PROCEDURE SortNear (n: INTEGER) ;
VAR
   i, k, v: INTEGER ;
BEGIN
   FOR i := 1 TO n - 1 DO
      v := Near^[i] ;
      k := i ;
      WHILE (k > 0) AND (Near^[k - 1] > v) DO
         Near^[k] := Near^[k - 1] ;
         DEC (k)
      END ;
      Near^[k] := v
   END
END SortNear ;


(* The large bodies b predicts against, in Near^[0 .. n - 1]: those placed
   in its 3x3 cells and every one in the large list, each once, but b, in
   index order. *)
PROCEDURE large_near (b: BodyRef; VAR n: INTEGER) ;
VAR
   k: INTEGER ;
BEGIN
   INC (Mark) ;
   n := 0 ;
   walls_in (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, TRUE, n) ;
   FOR k := 0 TO NLarge - 1 DO
      IF Large^[k] # b^.idx THEN NearAdd (n, Large^[k]) END
   END ;
   SortNear (n)
END large_near ;


(* Predicts b against the large bodies near it (large_near) other than
   skip, unless both are fixed. *)
PROCEDURE PredictLarge (b: BodyRef; skip: INTEGER; now: REAL) ;
VAR
   k, n, oi: INTEGER ;
   o: BodyRef ;
BEGIN
   large_near (b, n) ;
   FOR k := 0 TO n - 1 DO
      oi := Near^[k] ;
      IF oi # skip THEN
         o := ADR (Bodies^[oi]) ;
         IF NOT (b^.fixed AND o^.fixed) THEN
            PredictPair (b, o, now)
         END
      END
   END
END PredictLarge ;


PROCEDURE PredictBody (b: BodyRef; now: REAL; skip: INTEGER) ;
BEGIN
   PredictCells (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, -1, skip, now) ;
   PredictLarge (b, skip, now) ;
   ScheduleCell (b, now) ;
   (* a carried body moves with its base: no stop, no leave of its own *)
   IF (b^.sup >= 0) AND Bodies^[b^.sup].fixed THEN schedule_support (b) END
END PredictBody ;


(* Schedules the first crossing of b's centre over a line a margin past a boundary of its cell. *)
PROCEDURE ScheduleCell (b: BodyRef; now: REAL) ;
VAR
   ulo, uhi, p, v, a, origin, size, bound, lo, u, bu, h, room: REAL ;
   c: ARRAY [0..2] OF REAL ;
   axis, dk, direction, i, n, it, baxis, bdir: INTEGER ;
   found, crossed: BOOLEAN ;
   ev: Event ;
BEGIN
   IF b^.large OR ((b^.vx = 0.0) AND (b^.vy = 0.0) AND (b^.ax = 0.0) AND (b^.ay = 0.0)) THEN
      RETURN
   END ;
   ulo := now - b^.tb ;
   uhi := EndT - b^.tb ;
   (* the margin, or what the cell leaves a body added live that is wider
      than the scene's widest (it must stay within half a cell of its cell) *)
   h := GridMargin ;
   room := HalfCell - b^.bound ;
   IF room < h THEN h := room END ;
   found := FALSE ;
   bu := 0.0 ;
   baxis := 0 ;
   bdir := 0 ;
   FOR axis := 0 TO 1 DO
      IF axis = 0 THEN
         p := b^.px ; v := b^.vx ; a := b^.ax ; i := b^.cx ; n := GridNX ; origin := GridX0 ; size := CellW
      ELSE
         p := b^.py ; v := b^.vy ; a := b^.ay ; i := b^.cy ; n := GridNY ; origin := GridY0 ; size := CellH
      END ;
      FOR dk := 0 TO 1 DO
         IF dk = 0 THEN direction := 1 ELSE direction := -1 END ;
         crossed := FALSE ;
         IF direction = 1 THEN
            IF i < n - 1 THEN
               bound := origin + VAL (REAL, i + 1) * size + h ;
               crossed := TRUE
            END
         ELSIF i > 0 THEN
            bound := origin + VAL (REAL, i) * size - h ;
            crossed := TRUE
         END ;
         IF crossed AND (ulo = 0.0) AND ((p - bound) * VAL (REAL, direction) >= 0.0)
            AND ((v * VAL (REAL, direction) > 0.0) OR ((v = 0.0) AND (a * VAL (REAL, direction) > 0.0))) THEN
            (* on the boundary now, or past it (CellOf's quotient and the
               boundary's sum origin + i size can round apart), and moving or
               accelerating across it: cross at once (the root finder reports
               no root at the interval's start, and none at all for a
               boundary already behind) *)
            IF (NOT found) OR (0.0 < bu) THEN
               found := TRUE ;
               bu := 0.0 ;
               baxis := axis ;
               bdir := direction
            END ;
            crossed := FALSE
         END ;
         IF crossed THEN
            c[0] := p - bound ;
            c[1] := v ;
            c[2] := 0.5 * a ;
            lo := ulo ;
            it := 0 ;
            WHILE (it < 3) AND SmallestRoot (c, 2, lo, uhi, u) DO
               IF (v + a * u) * VAL (REAL, direction) > 0.0 THEN
                  IF (NOT found) OR (u < bu) THEN
                     found := TRUE ;
                     bu := u ;
                     baxis := axis ;
                     bdir := direction
                  END ;
                  it := 3
               ELSE
                  lo := u ;
                  INC (it)
               END
            END
         END
      END
   END ;
   IF found THEN
      ev.t := b^.tb + bu ;
      ev.kind := KCell ;
      ev.cell.body := b^.idx ;
      ev.cell.axis := baxis ;
      ev.cell.direction := bdir ;
      ev.cell.stamp := b^.stamp ;
      push (ev)
   END
END ScheduleCell ;


(* ---- handling events --------------------------------------------------------- *)

PROCEDURE EmitState (b: BodyRef) ;
BEGIN
   Str ("S ") ;
   Int (b^.idx) ;
   SpReal (b^.tb) ;
   SpReal (b^.px) ;
   SpReal (b^.py) ;
   SpReal (b^.vx) ;
   SpReal (b^.vy) ;
   SpReal (b^.ang) ;
   SpReal (b^.om) ;
   SpReal (b^.ax) ;
   SpReal (b^.ay) ;
   Ln
END EmitState ;


(* Contact point (cx, cy) and unit normal (nx, ny) from A to B of a feature
   at t (both bodies advanced to t). *)
PROCEDURE contact_frame (t: REAL; feature: INTEGER; A, B: BodyRef; i, j: INTEGER; VAR cx, cy, nx, ny: REAL) ;
VAR
   vA, vB: INTEGER ;
   pax, pay, pbx, pby, dx, dy, dist, px, py, th, rad: REAL ;
BEGIN
   IF i >= 0 THEN vA := A^.v0 + i ELSE vA := -1 END ;
   IF feature = FeatCC THEN
      PointAt (A, -1, t, pax, pay) ;
      IF j >= 0 THEN vB := B^.v0 + j ELSE vB := -1 END ;
      PointAt (B, vB, t, pbx, pby) ;
      dx := pbx - pax ;
      dy := pby - pay ;
      dist := sqrt (dx * dx + dy * dy) ;
      IF dist > 0.0 THEN
         nx := dx / dist ;
         ny := dy / dist
      ELSE
         nx := 1.0 ;
         ny := 0.0
      END ;
      cx := pax + A^.r * nx ;
      cy := pay + A^.r * ny
   ELSE
      PointAt (A, vA, t, px, py) ;
      th := B^.ang + Verts^[B^.v0 + j].psi ;
      (* from A to B: against the edge's outward normal *)
      nx := -cos (th) ;
      ny := -sin (th) ;
      IF vA < 0 THEN rad := A^.r ELSE rad := 0.0 END ;
      cx := px + rad * nx ;
      cy := py + rad * ny
   END
END contact_frame ;


(* Normal relative velocity (B's against A's, along n from A to B) of the
   material points at the contact: negative when approaching. *)
PROCEDURE normal_speed (A, B: BodyRef; cx, cy, nx, ny: REAL) : REAL ;
VAR
   uax, uay, ubx, uby: REAL ;
BEGIN
   uax := A^.vx - A^.om * (cy - A^.py) ;
   uay := A^.vy + A^.om * (cx - A^.px) ;
   ubx := B^.vx - B^.om * (cy - B^.py) ;
   uby := B^.vy + B^.om * (cx - B^.px) ;
   RETURN (ubx - uax) * nx + (uby - uay) * ny
END normal_speed ;


(* ---- support: resting and sliding on a fixed body -------------------------------- *)

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
VAR
   tx, ty, ox, oy, load, q, u: REAL ;
BEGIN
   IF (feature # FeatPE) OR A^.fixed OR (NOT B^.fixed) OR (B^.om # 0.0) THEN RETURN FALSE END ;
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
END can_support ;


(* Acceleration of supported A with tangential speed u relative to its
   support B: the relative free acceleration along the edge less Coulomb
   friction mu |a_n| against the relative motion; at relative rest, none
   while friction can hold it; plus B's acceleration when B moves. *)
PROCEDURE slide_accel (A: BodyRef; u: REAL) ;
VAR
   f, a: REAL ;
   B: BodyRef ;
BEGIN
   B := ADR (Bodies^[A^.sup]) ;
   f := A^.mu * B^.mu * A^.load ;
   IF u > 0.0 THEN
      a := A^.at - f
   ELSIF u < 0.0 THEN
      a := A^.at + f
   ELSIF A^.at > f THEN
      a := A^.at - f
   ELSIF A^.at < -f THEN
      a := A^.at + f
   ELSE
      a := 0.0
   END ;
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


(* ---- carried: at rest on a movable body that does not turn ----------------------- *)

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


(* A leaves its support or carrier at t (E leave, its state: world velocity
   kept, free acceleration), then what A carries, depth-first (release);
   each appended to the bodies that left (LeftBody, LeftSkip) with the body
   its prediction skips (skip, -1: none; predict_released). *)
PROCEDURE leave (A: BodyRef; t: REAL; skip: INTEGER) ;
VAR
   sup, edge: INTEGER ;
BEGIN
   INC (Stats.leaves) ;
   rebase (A, t) ;
   sup := A^.sup ;
   edge := A^.sup_edge ;
   end_support (A) ;
   INC (A^.stamp) ;
   EmitSupportEnd ("leave", t, A^.idx, sup, edge) ;
   EmitState (A) ;
   IF NLeft >= CapLeft THEN
      IF CapLeft = 0 THEN CapLeft := 16 ELSE CapLeft := 2 * CapLeft END ;
      LeftBody := Grow (LeftBody, CapLeft, SIZE (INTEGER)) ;
      LeftSkip := Grow (LeftSkip, CapLeft, SIZE (INTEGER))
   END ;
   LeftBody^[NLeft] := A^.idx ;
   LeftSkip^[NLeft] := skip ;
   INC (NLeft) ;
   release (A, t)
END leave ;


(* B's motion changes at t: every body B carries leaves (by index, each
   with what it carries: leave), skipping B in its prediction. *)
PROCEDURE release (B: BodyRef; t: REAL) ;
VAR
   i: INTEGER ;
BEGIN
   IF B^.carry = 0 THEN RETURN END ;
   FOR i := 0 TO NBodies - 1 DO
      IF Bodies^[i].sup = B^.idx THEN leave (ADR (Bodies^[i]), t, B^.idx) END
   END
END release ;


(* Predicts the bodies that left (leave) since the list held n0 of them, in
   the order they left, each but against the body it skips (already
   predicted with it); the list is back to n0. *)
PROCEDURE predict_released (n0: INTEGER; t: REAL) ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := n0 TO NLeft - 1 DO
      PredictBody (ADR (Bodies^[LeftBody^[k]]), t, LeftSkip^[k])
   END ;
   NLeft := n0
END predict_released ;


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


(* The bodies' accelerations push them together along the normal (n from
   A to B): the relative normal acceleration of the centres is negative.
   (Centripetal terms of turning bodies are left out.) *)
PROCEDURE pressed (A, B: BodyRef; nx, ny: REAL) : BOOLEAN ;
BEGIN
   RETURN (B^.ax - A^.ax) * nx + (B^.ay - A^.ay) * ny < 0.0
END pressed ;


(* The gap polynomial of the contact's feature (feature, i, j as in a
   CollisionEvent: the one that predicted it), taken again at the contact
   (A's time: both advanced), predicts this contact now (touching_now:
   approaching, c1 < 0, or c2 < 0 and closing again before the gap exceeds
   its kappa).  Its second derivative has the centripetal terms of a turn,
   which pressed leaves out.  FALSE when the generated code leaves the
   effect out (the world has failed). *)
PROCEDURE closing (A, B: BodyRef; feature, i, j: INTEGER) : BOOLEAN ;
VAR
   now, rb, kappa: REAL ;
   pa, pb: CParams ;
   cc: ARRAY [0..CcMaxDegree] OF REAL ;
   pe: ARRAY [0..PeMaxDegree] OF REAL ;
   deg, vb: INTEGER ;
BEGIN
   now := A^.tb ;
   IF feature = FeatCC THEN
      IF j >= 0 THEN
         vb := B^.v0 + j ;
         rb := 0.0
      ELSE
         vb := -1 ;
         rb := B^.r
      END ;
      CircleParamsOf (A, now, -1, pa) ;
      CircleParamsOf (B, now, vb, pb) ;
      deg := circles_gap (pa, A^.r, pb, rb, cc) ;
      kappa := Tol * (2.0 * (A^.r + rb) + Tol) ;
      RETURN (deg >= 1) AND touching_now (cc, deg, kappa)
   END ;
   IF i >= 0 THEN
      deg := PeCoefficients (A, B, Verts^[A^.v0 + i].rho, Verts^[A^.v0 + i].beta, 0.0, j, now, pe)
   ELSE
      deg := PeCoefficients (A, B, A^.orbit, A^.ophase, A^.r, j, now, pe)
   END ;
   RETURN (deg >= 1) AND touching_now (pe, deg, Tol)
END closing ;


(* A hop at the floor speed adds dE = need / 2 to the pair's energy (need =
   (floor^2 - cap) / kn): it is paid from the pair's common motion, the
   velocity V of its centre of mass (mass M), which an equal change of both
   velocities scales by f = sqrt(1 - need / (M V^2)), leaving their relative
   motion, hence the hop, untouched.  Not when a body of the pair is held
   (fixed, or a sleeper held as fixed) or the common motion cannot pay it
   (M V^2 <= need): FALSE, the hop then adds dE (Unpaid). *)
PROCEDURE pay_floor (A, B: BodyRef; need: REAL) : BOOLEAN ;
VAR
   ma, mb, mass, vx, vy, e2, f, dx, dy: REAL ;
BEGIN
   IF (A^.invM = 0.0) OR (B^.invM = 0.0) THEN RETURN FALSE END ;
   ma := 1.0 / A^.invM ;
   mb := 1.0 / B^.invM ;
   mass := ma + mb ;
   vx := (ma * A^.vx + mb * B^.vx) / mass ;
   vy := (ma * A^.vy + mb * B^.vy) / mass ;
   e2 := mass * (vx * vx + vy * vy) ;
   IF NOT (e2 > need) THEN RETURN FALSE END ;
   f := sqrt (1.0 - need / e2) ;
   dx := vx * f - vx ;
   dy := vy * f - vy ;
   A^.vx := A^.vx + dx ;
   A^.vy := A^.vy + dy ;
   B^.vx := B^.vx + dx ;
   B^.vy := B^.vy + dy ;
   RETURN TRUE
END pay_floor ;


(* A slow pressed contact (pressed, -vn < rest_speed): the bodies separate
   at hop along n, paid from their relative motion at the contact, so the
   pair's energy stays what it was: hop = rest_speed when kn Q pays it, else
   sqrt(kn Q), but at least rest_speed / 32 (a pair nearly at rest on each
   other: the energy that adds is paid from the pair's common motion,
   pay_floor, else the hop sets Unpaid).  With
   u = (vn, vt) the relative velocity of the material points in the frame
   (n, t), t = (-ny, nx), and K the contact's 2x2 inverse mass matrix (kn,
   knt; knt, kt), the pair's energy relative to its centre is Q / 2,
   Q = u . K^-1 u; the new relative velocity is (hop, x) with the same Q (x
   on vt's side of knt hop / kn), through the impulse P = K^-1 (u' - u)
   (normal part jn, tangential jt).  Returns jn. *)
PROCEDURE hop (A, B: BodyRef; cx, cy, nx, ny, vn: REAL) : REAL ;
VAR
   tx, ty, uax, uay, ubx, uby, vt, ran, rbn, rat, rbt, m, kn, kt, knt, det, q, cap, h, d, root, mid, x,
   dn, dt, jn, jt, px, py, floor: REAL ;
BEGIN
   tx := -ny ;
   ty := nx ;
   uax := A^.vx - A^.om * (cy - A^.py) ;
   uay := A^.vy + A^.om * (cx - A^.px) ;
   ubx := B^.vx - B^.om * (cy - B^.py) ;
   uby := B^.vy + B^.om * (cx - B^.px) ;
   vt := (ubx - uax) * tx + (uby - uay) * ty ;
   ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
   rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
   rat := (cx - A^.px) * ty - (cy - A^.py) * tx ;
   rbt := (cx - B^.px) * ty - (cy - B^.py) * tx ;
   m := A^.invM + B^.invM ;
   kn := m + A^.invI * ran * ran + B^.invI * rbn * rbn ;
   kt := m + A^.invI * rat * rat + B^.invI * rbt * rbt ;
   knt := A^.invI * ran * rat + B^.invI * rbn * rbt ;
   det := kn * kt - knt * knt ;
   q := (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det ;
   cap := kn * q ;
   floor := 0.03125 * RestSpeed ;
   IF cap >= RestSpeed * RestSpeed THEN
      h := RestSpeed
   ELSIF cap >= floor * floor THEN
      h := sqrt (cap)
   ELSE
      h := floor
   END ;
   d := det * (cap - h * h) ;
   IF d > 0.0 THEN root := sqrt (d) ELSE root := 0.0 END ;
   mid := knt * h ;
   IF vt * kn >= mid THEN
      x := (mid + root) / kn
   ELSE
      x := (mid - root) / kn
   END ;
   dn := h - vn ;
   dt := x - vt ;
   jn := (kt * dn - knt * dt) / det ;
   jt := (kn * dt - knt * dn) / det ;
   px := jn * nx + jt * tx ;
   py := jn * ny + jt * ty ;
   A^.vx := A^.vx - px * A^.invM ;
   A^.vy := A^.vy - py * A^.invM ;
   A^.om := A^.om - (jn * ran + jt * rat) * A^.invI ;
   B^.vx := B^.vx + px * B^.invM ;
   B^.vy := B^.vy + py * B^.invM ;
   B^.om := B^.om + (jn * rbn + jt * rbt) * B^.invI ;
   IF (cap < floor * floor) AND NOT pay_floor (A, B, (floor * floor - cap) / kn) THEN
      Unpaid := TRUE
   END ;
   RETURN jn
END hop ;


(* The impulse of a contact of the feature (feature, i, j) at (cx, cy) with
   normal (nx, ny) from A to B (both advanced to the contact time): 0.0 when
   the material points do not approach and are not pressed together, else
   the normal impulse j (velocities changed).  A fast contact is
   frictionless and leaves at sep = max(e |vn|, min(|vn|, rest_speed)); a
   slow pressed one hops (hop).  When the material points do not approach,
   the centres' accelerations do not press them and a body of the pair
   turns, the feature's gap polynomial decides whether they are pressed
   (closing: the turn closes the gap, which would otherwise predict the same
   contact again at once).  Never adds energy (docs/simulator.md, Impulse). *)
PROCEDURE contact_impulse (A, B: BodyRef; cx, cy, nx, ny: REAL; feature, i, j: INTEGER) : REAL ;
VAR
   vn, imp, ran, rbn, k, e, sep, m1, mn, me: REAL ;
   press: BOOLEAN ;
BEGIN
   vn := normal_speed (A, B, cx, cy, nx, ny) ;
   press := pressed (A, B, nx, ny) ;
   IF (NOT press) AND (NOT (vn < 0.0)) AND ((TurnRate (A) > 0.0) OR (TurnRate (B) > 0.0)) THEN
      press := closing (A, B, feature, i, j)
   END ;
   IF press AND (-vn < RestSpeed) THEN
      RETURN hop (A, B, cx, cy, nx, ny, vn)
   END ;
   imp := 0.0 ;
   IF vn < 0.0 THEN
      ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
      rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
      k := A^.invM + B^.invM + A^.invI * ran * ran + B^.invI * rbn * rbn ;
      e := A^.e * B^.e ;
      (* sep = max(e * -vn, min(-vn, rest_speed)), as Python's min and max pick *)
      me := e * (-vn) ;
      m1 := -vn ;
      IF RestSpeed < m1 THEN mn := RestSpeed ELSE mn := m1 END ;
      IF mn > me THEN sep := mn ELSE sep := me END ;
      imp := (sep - vn) / k ;
      A^.vx := A^.vx - imp * A^.invM * nx ;
      A^.vy := A^.vy - imp * A^.invM * ny ;
      A^.om := A^.om - imp * A^.invI * ran ;
      B^.vx := B^.vx + imp * B^.invM * nx ;
      B^.vy := B^.vy + imp * B^.invM * ny ;
      B^.om := B^.om + imp * B^.invI * rbn
   END ;
   RETURN imp
END contact_impulse ;


(* n . t of a supported body's edge tangent t (0 for a body that is not
   supported: a fixed one). *)
PROCEDURE along (b: BodyRef; nx, ny: REAL) : REAL ;
BEGIN
   IF b^.sup < 0 THEN RETURN 0.0 END ;
   RETURN nx * b^.tx + ny * b^.ty
END along ;


(* A slow contact of bodies held on their supports: each supported (on a
   fixed body: a carried body is not) or fixed, approaching (vn < 0) slower than rest_speed, not pressed, and an impulse
   along their edges can change vn (kh > 0). *)
PROCEDURE held (A, B: BodyRef; nx, ny, vn: REAL) : BOOLEAN ;
VAR
   ka, kb: REAL ;
BEGIN
   IF NOT ((A^.fixed OR ((A^.sup >= 0) AND Bodies^[A^.sup].fixed))
           AND (B^.fixed OR ((B^.sup >= 0) AND Bodies^[B^.sup].fixed))) THEN
      RETURN FALSE
   END ;
   IF (NOT (vn < 0.0)) OR (NOT (-vn < RestSpeed)) OR pressed (A, B, nx, ny) THEN RETURN FALSE END ;
   ka := along (A, nx, ny) ;
   kb := along (B, nx, ny) ;
   RETURN A^.invM * ka * ka + B^.invM * kb * kb > 0.0
END held ;


(* The normal impulse j of a held contact (held): each supported body takes
   only its part along its support's edge, dv = -+ j (n . t) t / m, and
   keeps its support (the support's reaction takes the rest and does no
   work); the normal speed leaves at sep = max(e |vn|, min(|vn|,
   rest_speed)) through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.  The
   friction of each is set again for its new speed relative to its support
   (slide_accel; support_relative: the support may move). *)
PROCEDURE held_impulse (A, B: BodyRef; nx, ny, vn: REAL) : REAL ;
VAR
   ka, kb, k, e, sep, imp, d, m1, mn, me, q, u, a: REAL ;
BEGIN
   ka := along (A, nx, ny) ;
   kb := along (B, nx, ny) ;
   k := A^.invM * ka * ka + B^.invM * kb * kb ;
   e := A^.e * B^.e ;
   (* sep = max(e * -vn, min(-vn, rest_speed)), as Python's min and max pick *)
   me := e * (-vn) ;
   m1 := -vn ;
   IF RestSpeed < m1 THEN mn := RestSpeed ELSE mn := m1 END ;
   IF mn > me THEN sep := mn ELSE sep := me END ;
   imp := (sep - vn) / k ;
   IF A^.sup >= 0 THEN
      d := imp * A^.invM * ka ;
      A^.vx := A^.vx - d * A^.tx ;
      A^.vy := A^.vy - d * A^.ty ;
      support_relative (A, q, u, a) ;
      slide_accel (A, u)
   END ;
   IF B^.sup >= 0 THEN
      d := imp * B^.invM * kb ;
      B^.vx := B^.vx + d * B^.tx ;
      B^.vy := B^.vy + d * B^.ty ;
      support_relative (B, q, u, a) ;
      slide_accel (B, u)
   END ;
   RETURN imp
END held_impulse ;


PROCEDURE Stat (name: ARRAY OF CHAR; count: LONGINT) ;
BEGIN
   Str ("N ") ;
   Str (name) ;
   Str (" ") ;
   Int (count) ;
   Ln
END Stat ;


(* ---- sleeping islands ------------------------------------------------------------ *)

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


(* The impulse of a contact of A and B, one of them (S) asleep: first with
   S held as if fixed (its 1/m and 1/I zero); when that impulse would change
   the normal speed of S's material point by less than rest_speed,
   j (1/mS + (rS x n)^2 / IS) < rest_speed, and no hop of it was Unpaid, it stands (S stays asleep,
   unchanged: a gentle touch); else the other body's velocity is restored
   and the full impulse is applied (S moves: jolted, its island wakes).
   When the other body is fixed (it moves or turns: a sleeper is never
   predicted against an unmoving one) S cannot be held (the pair would have
   no mass): the full impulse at once.  Returns the impulse applied. *)
PROCEDURE sleeper_impulse (A, B: BodyRef; cx, cy, nx, ny: REAL; feature, i, j: INTEGER) : REAL ;
VAR
   S, M: BodyRef ;
   vx, vy, om, invM, invI, imp, rsn: REAL ;
BEGIN
   IF A^.asleep THEN
      S := A ;
      M := B
   ELSE
      S := B ;
      M := A
   END ;
   IF M^.fixed THEN RETURN contact_impulse (A, B, cx, cy, nx, ny, feature, i, j) END ;
   vx := M^.vx ;
   vy := M^.vy ;
   om := M^.om ;
   invM := S^.invM ;
   invI := S^.invI ;
   S^.invM := 0.0 ;
   S^.invI := 0.0 ;
   Unpaid := FALSE ;
   imp := contact_impulse (A, B, cx, cy, nx, ny, feature, i, j) ;
   S^.invM := invM ;
   S^.invI := invI ;
   rsn := (cx - S^.px) * ny - (cy - S^.py) * nx ;
   IF (imp * (S^.invM + S^.invI * rsn * rsn) < RestSpeed) AND NOT Unpaid THEN RETURN imp END ;
   M^.vx := vx ;
   M^.vy := vy ;
   M^.om := om ;
   RETURN contact_impulse (A, B, cx, cy, nx, ny, feature, i, j)
END sleeper_impulse ;


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


(* A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0) in
   G's island, or in a new one numbered A's index when G is fixed.  Its
   awake neighbours are predicted against it again. *)
PROCEDURE handle_sleep (A, G: BodyRef; t: REAL) ;
VAR
   n0: INTEGER ;
BEGIN
   INC (Stats.sleeps) ;
   IF A^.sup >= 0 THEN end_support (A) END ;
   A^.vx := 0.0 ;
   A^.vy := 0.0 ;
   A^.om := 0.0 ;
   A^.ax := 0.0 ;
   A^.ay := 0.0 ;
   A^.asleep := TRUE ;
   IF G^.asleep THEN A^.island := G^.island ELSE A^.island := A^.idx END ;
   INC (A^.stamp) ;
   EmitSupportEnd ("sleep", t, A^.idx, G^.idx, A^.island) ;
   EmitState (A) ;
   n0 := NLeft ;
   release (A, t) ;
   PredictBody (A, t, -1) ;
   predict_released (n0, t)
END handle_sleep ;


(* S's island wakes at t: every member (by index) gets its free
   acceleration back, then fresh predictions (a pair of members once). *)
PROCEDURE handle_wake (S: BodyRef; t: REAL) ;
VAR
   island, i: INTEGER ;
   b: BodyRef ;
BEGIN
   INC (Stats.wakes) ;
   island := S^.island ;
   Str ("E wake ") ;
   Real (t) ;
   Str (" ") ; Int (S^.idx) ;
   Str (" -1 -1 -1 ") ; Int (island) ;
   Str (" 0 0 0 0 0") ;
   Ln ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.asleep AND (b^.island = island) THEN
         rebase (b, t) ;
         b^.asleep := FALSE ;
         b^.ax := b^.fax ;
         b^.ay := b^.fay ;
         INC (b^.stamp) ;
         EmitState (b)
      END
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.island = island THEN predict_woken (b, t, island) END
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.island = island THEN b^.island := -1 END
   END
END handle_wake ;


(* PredictBody for a member of a waking island: a pair of two members is
   predicted by the one with the smaller index. *)
PROCEDURE predict_woken (b: BodyRef; now: REAL; island: INTEGER) ;
VAR
   jx, jy, c, k, oi, n: INTEGER ;
   o: BodyRef ;
BEGIN
   FOR jy := Max (b^.cy - 1, 0) TO Min (b^.cy + 1, GridNY - 1) DO
      FOR jx := Max (b^.cx - 1, 0) TO Min (b^.cx + 1, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Cells^[c].n - 1 DO
            oi := Cells^[c].items^[k] ;
            IF oi # b^.idx THEN
               o := ADR (Bodies^[oi]) ;
               IF (NOT ((o^.island = island) AND (o^.idx < b^.idx))) AND NOT (b^.fixed AND o^.fixed) THEN
                  PredictPair (b, o, now)
               END
            END
         END
      END
   END ;
   large_near (b, n) ;
   FOR k := 0 TO n - 1 DO
      oi := Near^[k] ;
      o := ADR (Bodies^[oi]) ;
      IF NOT ((o^.island = island) AND (o^.idx < b^.idx)) THEN
         PredictPair (b, o, now)
      END
   END ;
   ScheduleCell (b, now)
END predict_woken ;


(* ---- simultaneous contacts: a contact met again at one instant ---------- *)

(* Counts a contact handled at t (an E collision or E support line). *)
PROCEDURE touch (t: REAL; a, b, feature, i, j: INTEGER) ;
VAR
   k: INTEGER ;
BEGIN
   IF t # TouchedT THEN
      TouchedT := t ;
      NTouched := 0
   END ;
   FOR k := 0 TO NTouched - 1 DO
      IF (Touched^[k].a = a) AND (Touched^[k].b = b) AND (Touched^[k].feature = feature)
         AND (Touched^[k].i = i) AND (Touched^[k].j = j) THEN
         INC (Touched^[k].times) ;
         RETURN
      END
   END ;
   IF NTouched >= CapTouched THEN
      IF CapTouched = 0 THEN CapTouched := 16 ELSE CapTouched := 2 * CapTouched END ;
      Touched := Grow (Touched, CapTouched, SIZE (Touch))
   END ;
   Touched^[NTouched].a := a ;
   Touched^[NTouched].b := b ;
   Touched^[NTouched].feature := feature ;
   Touched^[NTouched].i := i ;
   Touched^[NTouched].j := j ;
   Touched^[NTouched].times := 1 ;
   INC (NTouched)
END touch ;


(* The collision's contact (a, b, feature, i, j) was handled ClusterRepeats
   times already at this instant: other contacts keep undoing its impulse (a
   settling pile meets one contact up to 32 times at one instant and goes
   on: ball-pit.json). *)
PROCEDURE repeated (t: REAL; ev: CollisionEvent) : BOOLEAN ;
VAR
   k: INTEGER ;
BEGIN
   IF t # TouchedT THEN RETURN FALSE END ;
   FOR k := 0 TO NTouched - 1 DO
      IF (Touched^[k].a = ev.a) AND (Touched^[k].b = ev.b) AND (Touched^[k].feature = ev.feature)
         AND (Touched^[k].i = ev.i) AND (Touched^[k].j = ev.j) THEN
         RETURN Touched^[k].times >= ClusterRepeats
      END
   END ;
   RETURN FALSE
END repeated ;


(* A body that links a cluster's contacts: movable and awake (fixed bodies
   and sleepers are held: the cluster ends at them). *)
PROCEDURE joins (b: BodyRef) : BOOLEAN ;
BEGIN
   RETURN (NOT b^.fixed) AND NOT b^.asleep
END joins ;


(* x is one of the n first items of list. *)
PROCEDURE Listed (list: IntList; n, x: INTEGER) : BOOLEAN ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := 0 TO n - 1 DO
      IF list^[k] = x THEN RETURN TRUE END
   END ;
   RETURN FALSE
END Listed ;


(* Appends x to list (n items, room for cap). *)
PROCEDURE Append1 (VAR list: IntList; VAR n, cap: INTEGER; x: INTEGER) ;
BEGIN
   IF n >= cap THEN
      IF cap = 0 THEN cap := 16 ELSE cap := 2 * cap END ;
      list := Grow (list, cap, SIZE (INTEGER))
   END ;
   list^[n] := x ;
   INC (n)
END Append1 ;


(* Room for n rows and n movers. *)
PROCEDURE RoomRows (n: INTEGER) ;
BEGIN
   IF n > CapRows THEN
      CapRows := n ;
      Rows := Grow (Rows, CapRows, SIZE (Row)) ;
      Movers := Grow (Movers, 2 * CapRows, SIZE (Mover)) ;
      Pushes := Grow (Pushes, 2 * CapRows + 1, SIZE (Direction))
   END
END RoomRows ;


(* The contacts handled at this instant (Touched, in the order first
   handled) that reach the collision's bodies through bodies that join:
   Rows^[0 .. NRows - 1] (a, b, feature, i, j). *)
PROCEDURE cluster (ev: CollisionEvent) ;
VAR
   k, x, y: INTEGER ;
   grow: BOOLEAN ;
BEGIN
   NJoined := 0 ;
   x := ev.a ;
   IF joins (ADR (Bodies^[x])) THEN Append1 (Joined, NJoined, CapJoined, x) END ;
   x := ev.b ;
   IF joins (ADR (Bodies^[x])) THEN Append1 (Joined, NJoined, CapJoined, x) END ;
   grow := TRUE ;
   WHILE grow DO
      grow := FALSE ;
      FOR k := 0 TO NTouched - 1 DO
         x := Touched^[k].a ;
         y := Touched^[k].b ;
         IF Listed (Joined, NJoined, x) OR Listed (Joined, NJoined, y) THEN
            IF (NOT Listed (Joined, NJoined, x)) AND joins (ADR (Bodies^[x])) THEN
               Append1 (Joined, NJoined, CapJoined, x) ;
               grow := TRUE
            END ;
            IF (NOT Listed (Joined, NJoined, y)) AND joins (ADR (Bodies^[y])) THEN
               Append1 (Joined, NJoined, CapJoined, y) ;
               grow := TRUE
            END
         END
      END
   END ;
   RoomRows (NTouched) ;
   NRows := 0 ;
   FOR k := 0 TO NTouched - 1 DO
      IF Listed (Joined, NJoined, Touched^[k].a) OR Listed (Joined, NJoined, Touched^[k].b) THEN
         Rows^[NRows].a := Touched^[k].a ;
         Rows^[NRows].b := Touched^[k].b ;
         Rows^[NRows].feature := Touched^[k].feature ;
         Rows^[NRows].i := Touched^[k].i ;
         Rows^[NRows].j := Touched^[k].j ;
         INC (NRows)
      END
   END
END cluster ;


(* b's part in a cluster's solve: Held (fixed or asleep), Slider
   (supported on a fixed body: it moves along the edge only, as in
   held_impulse) or Free. *)
PROCEDURE part (b: BodyRef) : INTEGER ;
BEGIN
   IF b^.fixed OR b^.asleep THEN RETURN Held END ;
   IF (b^.sup >= 0) AND Bodies^[b^.sup].fixed THEN RETURN Slider END ;
   RETURN Free
END part ;


(* How much a unit impulse along n at the contact (rn: the contact's arm
   across n) changes b's normal speed there. *)
PROCEDURE give (b: BodyRef; nx, ny, rn: REAL) : REAL ;
VAR
   p: INTEGER ;
   k: REAL ;
BEGIN
   p := part (b) ;
   IF p = Held THEN RETURN 0.0 END ;
   IF p = Slider THEN
      k := nx * b^.tx + ny * b^.ty ;
      RETURN b^.invM * k * k
   END ;
   RETURN b^.invM + b^.invI * rn * rn
END give ;


(* An impulse j along n on b at the contact (rn its arm across n). *)
PROCEDURE nudge (b: BodyRef; j, nx, ny, rn: REAL) ;
VAR
   p: INTEGER ;
   d: REAL ;
BEGIN
   p := part (b) ;
   IF p = Held THEN RETURN END ;
   IF p = Slider THEN
      d := j * b^.invM * (nx * b^.tx + ny * b^.ty) ;
      b^.vx := b^.vx + d * b^.tx ;
      b^.vy := b^.vy + d * b^.ty ;
      RETURN
   END ;
   b^.vx := b^.vx + j * b^.invM * nx ;
   b^.vy := b^.vy + j * b^.invM * ny ;
   b^.om := b^.om + j * b^.invI * rn
END nudge ;


(* Sequential impulses over the cluster's contacts (Rows, in order): each
   contact's accumulated normal impulse acc moves so that its normal speed
   becomes its target, but never below zero (a contact only pushes); sweep
   after sweep until no impulse of a sweep changed a normal speed by more
   than ClusterTol rest_speed, at most ClusterSweeps sweeps. *)
PROCEDURE sweeps ;
VAR
   tol, big, vn, new, dj, ch: REAL ;
   s, k: INTEGER ;
   A, B: BodyRef ;
BEGIN
   tol := ClusterTol * RestSpeed ;
   FOR s := 1 TO ClusterSweeps DO
      big := 0.0 ;
      FOR k := 0 TO NRows - 1 DO
         WITH Rows^[k] DO
            IF kn > 0.0 THEN
               A := ADR (Bodies^[a]) ;
               B := ADR (Bodies^[b]) ;
               vn := normal_speed (A, B, cx, cy, nx, ny) ;
               new := acc + (target - vn) / kn ;
               IF new < 0.0 THEN new := 0.0 END ;
               dj := new - acc ;
               acc := new ;
               nudge (A, -dj, nx, ny, ran) ;
               nudge (B, dj, nx, ny, rbn) ;
               ch := ABS (dj) * kn ;
               IF ch > big THEN big := ch END
            END
         END
      END ;
      IF big <= tol THEN RETURN END
   END
END sweeps ;


(* The kinetic energy of the movers (linear, and turning where 1/I > 0). *)
PROCEDURE kinetic () : REAL ;
VAR
   e: REAL ;
   k: INTEGER ;
   b: BodyRef ;
BEGIN
   e := 0.0 ;
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      e := e + 0.5 * (b^.vx * b^.vx + b^.vy * b^.vy) / b^.invM ;
      IF b^.invI > 0.0 THEN
         e := e + 0.5 * b^.om * b^.om / b^.invI
      END
   END ;
   RETURN e
END kinetic ;


(* The largest mu in [0, 1] for which the movers' velocities v1 + mu (v -
   v1) (v: theirs now, v1 their vs; the kinetic energy at v1 at most budget)
   have a kinetic energy at most budget: with a the energy of the change, b
   the cross term and e1 the energy at v1, a mu^2 + b mu <= budget - e1. *)
PROCEDURE mix (budget: REAL) : REAL ;
VAR
   a, b, e1, vx, vy, om, dx, dy, dw, spare, root, mu: REAL ;
   k: INTEGER ;
   m: BodyRef ;
BEGIN
   a := 0.0 ;
   b := 0.0 ;
   e1 := 0.0 ;
   FOR k := 0 TO NMovers - 1 DO
      m := ADR (Bodies^[Movers^[k].idx]) ;
      vx := Movers^[k].vsx ;
      vy := Movers^[k].vsy ;
      om := Movers^[k].vsom ;
      dx := m^.vx - vx ;
      dy := m^.vy - vy ;
      a := a + 0.5 * (dx * dx + dy * dy) / m^.invM ;
      b := b + (vx * dx + vy * dy) / m^.invM ;
      e1 := e1 + 0.5 * (vx * vx + vy * vy) / m^.invM ;
      IF m^.invI > 0.0 THEN
         dw := m^.om - om ;
         a := a + 0.5 * dw * dw / m^.invI ;
         b := b + om * dw / m^.invI ;
         e1 := e1 + 0.5 * om * om / m^.invI
      END
   END ;
   IF NOT (a > 0.0) THEN RETURN 1.0 END ;
   spare := budget - e1 ;
   IF spare < 0.0 THEN spare := 0.0 END ;
   root := sqrt (b * b + 4.0 * a * spare) ;
   IF b > 0.0 THEN
      mu := 2.0 * spare / (b + root)
   ELSE
      mu := (root - b) / (2.0 * a)
   END ;
   IF mu < 1.0 THEN RETURN mu END ;
   RETURN 1.0
END mix ;


(* A contact of the cluster (row k) that must separate: its bodies'
   accelerations press them together (pressed) or, a body turning, its gap
   closes now (closing), as contact_impulse decides. *)
PROCEDURE pressing_contact (k: INTEGER) : BOOLEAN ;
VAR
   A, B: BodyRef ;
BEGIN
   WITH Rows^[k] DO
      A := ADR (Bodies^[a]) ;
      B := ADR (Bodies^[b]) ;
      IF pressed (A, B, nx, ny) THEN RETURN TRUE END ;
      IF (TurnRate (A) > 0.0) OR (TurnRate (B) > 0.0) THEN
         RETURN closing (A, B, feature, i, j)
      END
   END ;
   RETURN FALSE
END pressing_contact ;


(* Stores the movers' velocities now in their saved (which = 0), v2
   (which = 1) or vs (which = 2) velocities. *)
PROCEDURE velocities (which: INTEGER) ;
VAR
   k: INTEGER ;
   b: BodyRef ;
BEGIN
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      WITH Movers^[k] DO
         IF which = 0 THEN
            sx := b^.vx ; sy := b^.vy ; som := b^.om
         ELSIF which = 1 THEN
            v2x := b^.vx ; v2y := b^.vy ; v2om := b^.om
         ELSE
            vsx := b^.vx ; vsy := b^.vy ; vsom := b^.om
         END
      END
   END
END velocities ;


(* Gives the movers back their saved (which = 0) or v2 (which = 1) velocities. *)
PROCEDURE set_velocities (which: INTEGER) ;
VAR
   k: INTEGER ;
   b: BodyRef ;
BEGIN
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      WITH Movers^[k] DO
         IF which = 0 THEN
            b^.vx := sx ; b^.vy := sy ; b^.om := som
         ELSE
            b^.vx := v2x ; b^.vy := v2y ; b^.om := v2om
         END
      END
   END
END set_velocities ;


(* The cluster's joint impulses (docs/simulator.md, "Contact model:
   simultaneous contacts"): inelastic sequential impulses (target normal
   speed 0: kinetic energy e1); then the pressed contacts separate at
   rest_speed (the others at ClusterApart rest_speed): sequential impulses
   from v1 (v2), taken when they cost no more than e1; else the same from
   the movers at rest (vs, energy es), mixed towards v2 as far as e1 pays
   (mix) when es <= e1, else vs scaled to energy e1.  Leaves each row's
   frame and normal impulse (acc) in Rows, the bodies that move in Movers
   with their velocities before (saved). *)
PROCEDURE solve_cluster (t: REAL) ;
VAR
   k, q, n: INTEGER ;
   A, B, b: BodyRef ;
   e1, es, mu, f, q0, u, a0: REAL ;
   found: BOOLEAN ;
BEGIN
   FOR k := 0 TO NRows - 1 DO
      WITH Rows^[k] DO
         A := ADR (Bodies^[a]) ;
         B := ADR (Bodies^[b]) ;
         contact_frame (t, feature, A, B, i, j, cx, cy, nx, ny) ;
         ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
         rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
         kn := give (A, nx, ny, ran) + give (B, nx, ny, rbn)
      END
   END ;
   NMovers := 0 ;
   FOR k := 0 TO NRows - 1 DO
      FOR n := 0 TO 1 DO
         IF n = 0 THEN b := ADR (Bodies^[Rows^[k].a]) ELSE b := ADR (Bodies^[Rows^[k].b]) END ;
         IF part (b) # Held THEN
            found := FALSE ;
            FOR q := 0 TO NMovers - 1 DO
               IF Movers^[q].idx = b^.idx THEN found := TRUE END
            END ;
            IF NOT found THEN
               Movers^[NMovers].idx := b^.idx ;
               INC (NMovers)
            END
         END
      END
   END ;
   velocities (0) ;
   FOR k := 0 TO NRows - 1 DO
      Rows^[k].acc := 0.0 ;
      Rows^[k].target := 0.0
   END ;
   sweeps ;
   e1 := kinetic () ;
   FOR k := 0 TO NRows - 1 DO
      IF pressing_contact (k) THEN
         Rows^[k].target := RestSpeed
      ELSE
         Rows^[k].target := ClusterApart * RestSpeed
      END
   END ;
   sweeps ;
   IF kinetic () <= e1 THEN RETURN END ;
   velocities (1) ;
   FOR k := 0 TO NRows - 1 DO
      Rows^[k].acc2 := Rows^[k].acc
   END ;
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      IF (b^.sup >= 0) AND Bodies^[b^.sup].fixed THEN
         support_relative (b, q0, u, a0) ;
         b^.vx := b^.vx - u * b^.tx ;
         b^.vy := b^.vy - u * b^.ty
      ELSE
         b^.vx := 0.0 ;
         b^.vy := 0.0
      END ;
      b^.om := 0.0
   END ;
   FOR k := 0 TO NRows - 1 DO
      Rows^[k].acc := 0.0
   END ;
   sweeps ;
   es := kinetic () ;
   IF es <= e1 THEN
      velocities (2) ;
      set_velocities (1) ;
      mu := mix (e1) ;
      FOR k := 0 TO NMovers - 1 DO
         b := ADR (Bodies^[Movers^[k].idx]) ;
         WITH Movers^[k] DO
            b^.vx := vsx + mu * (b^.vx - vsx) ;
            b^.vy := vsy + mu * (b^.vy - vsy) ;
            b^.om := vsom + mu * (b^.om - vsom)
         END
      END ;
      FOR k := 0 TO NRows - 1 DO
         WITH Rows^[k] DO
            acc := acc + mu * (acc2 - acc)
         END
      END ;
      RETURN
   END ;
   f := sqrt (e1 / es) ;
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      b^.vx := f * b^.vx ;
      b^.vy := f * b^.vy ;
      b^.om := f * b^.om
   END ;
   FOR k := 0 TO NRows - 1 DO
      Rows^[k].acc := f * Rows^[k].acc
   END
END solve_cluster ;


(* The first sleeper (in the contacts' order) whose held impulses, summed,
   would change its material points' normal speed by at least rest_speed
   (as a touch that is not gentle, sleeper_impulse); -1: none. *)
PROCEDURE jolted_sleeper () : INTEGER ;
VAR
   k, q, n, s: INTEGER ;
   S: BodyRef ;
   total, rsn: REAL ;
BEGIN
   FOR k := 0 TO NRows - 1 DO
      FOR n := 0 TO 1 DO
         IF n = 0 THEN s := Rows^[k].a ELSE s := Rows^[k].b END ;
         S := ADR (Bodies^[s]) ;
         IF S^.asleep THEN
            total := 0.0 ;
            FOR q := 0 TO NRows - 1 DO
               WITH Rows^[q] DO
                  IF (a = s) OR (b = s) THEN
                     IF a = s THEN rsn := ran ELSE rsn := rbn END ;
                     total := total + acc * (S^.invM + S^.invI * rsn * rsn)
                  END
               END
            END ;
            IF total >= RestSpeed THEN RETURN s END
         END
      END
   END ;
   RETURN -1
END jolted_sleeper ;


(* The grounded body awake M falls asleep on after its cluster's solve, or
   -1: M slower than rest_speed (a polygon also turning slower than
   rest_speed / bound) and its free acceleration held by what it rests on
   (holds): the outward normal of its support when it is supported on an
   unmoving fixed body, and each contact of the cluster with a grounded body
   (pushing M along -m, m the contact's normal from M).  It falls asleep on
   its support, else on the first grounded body of those contacts. *)
PROCEDURE wedged (M: BodyRef) : INTEGER ;
VAR
   k, n, g: INTEGER ;
   tx, ty, ox, oy: REAL ;
   S: BodyRef ;
BEGIN
   IF NOT (M^.vx * M^.vx + M^.vy * M^.vy < RestSpeed * RestSpeed) THEN RETURN -1 END ;
   IF M^.polygon AND NOT (ABS (M^.om) * M^.bound < RestSpeed) THEN RETURN -1 END ;
   n := 0 ;
   g := -1 ;
   IF M^.sup >= 0 THEN
      S := ADR (Bodies^[M^.sup]) ;
      IF NOT (S^.fixed AND grounded (S)) THEN RETURN -1 END ;
      support_frame (S, M^.sup_edge, tx, ty, ox, oy) ;
      Pushes^[n].x := ox ;
      Pushes^[n].y := oy ;
      INC (n) ;
      g := S^.idx
   END ;
   FOR k := 0 TO NRows - 1 DO
      WITH Rows^[k] DO
         IF (a = M^.idx) AND grounded (ADR (Bodies^[b])) THEN
            Pushes^[n].x := -nx ;
            Pushes^[n].y := -ny ;
            INC (n) ;
            IF g < 0 THEN g := b END
         END ;
         IF (b = M^.idx) AND grounded (ADR (Bodies^[a])) THEN
            Pushes^[n].x := nx ;
            Pushes^[n].y := ny ;
            INC (n) ;
            IF g < 0 THEN g := a END
         END
      END
   END ;
   IF (g < 0) OR NOT holds (n, -M^.fax, -M^.fay) THEN RETURN -1 END ;
   RETURN g
END wedged ;


(* The pushes (unit directions Pushes^[0 .. n - 1]) can make (dx, dy) with
   non-negative weights through one push (its direction within HoldTol rad
   of d) or two: d = a p + b q, a >= 0, b >= 0 (Cramer, p x q # 0), pairs in
   order.  (dx, dy) = (0, 0) needs nothing. *)
PROCEDURE holds (n: INTEGER; dx, dy: REAL) : BOOLEAN ;
VAR
   k, q: INTEGER ;
   px, py, qx, qy, dot, det, a, b: REAL ;
BEGIN
   IF (dx = 0.0) AND (dy = 0.0) THEN RETURN TRUE END ;
   FOR k := 0 TO n - 1 DO
      px := Pushes^[k].x ;
      py := Pushes^[k].y ;
      dot := px * dx + py * dy ;
      IF (dot > 0.0) AND (ABS (px * dy - py * dx) <= HoldTol * dot) THEN RETURN TRUE END
   END ;
   FOR k := 0 TO n - 1 DO
      px := Pushes^[k].x ;
      py := Pushes^[k].y ;
      FOR q := k + 1 TO n - 1 DO
         qx := Pushes^[q].x ;
         qy := Pushes^[q].y ;
         det := px * qy - py * qx ;
         IF det # 0.0 THEN
            a := (dx * qy - dy * qx) / det ;
            b := (px * dy - py * dx) / det ;
            IF (a >= 0.0) AND (b >= 0.0) THEN RETURN TRUE END
         END
      END
   END ;
   RETURN FALSE
END holds ;


(* A body of a solved cluster after its impulses: one sliding on a fixed
   body gets its friction again for its new speed (as held_impulse), a
   carried one leaves its base's motion (end_support: it is not held); a
   new stamp, its state. *)
PROCEDURE settle (b: BodyRef) ;
VAR
   q, u, a: REAL ;
BEGIN
   IF b^.sup >= 0 THEN
      IF Bodies^[b^.sup].fixed THEN
         support_relative (b, q, u, a) ;
         slide_accel (b, u)
      ELSE
         end_support (b)
      END
   END ;
   INC (b^.stamp) ;
   EmitState (b)
END settle ;


(* PredictBody for a body of a solved cluster, but against the bodies in
   Finished (predicted already, or fallen asleep and predicted against it by
   handle_sleep). *)
PROCEDURE predict_apart (b: BodyRef; now: REAL) ;
VAR
   jx, jy, c, k, oi, n: INTEGER ;
   o: BodyRef ;
BEGIN
   FOR jy := Max (b^.cy - 1, 0) TO Min (b^.cy + 1, GridNY - 1) DO
      FOR jx := Max (b^.cx - 1, 0) TO Min (b^.cx + 1, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Cells^[c].n - 1 DO
            oi := Cells^[c].items^[k] ;
            IF (oi # b^.idx) AND NOT Listed (Finished, NFinished, oi) THEN
               o := ADR (Bodies^[oi]) ;
               IF NOT (b^.fixed AND o^.fixed) THEN PredictPair (b, o, now) END
            END
         END
      END
   END ;
   large_near (b, n) ;
   FOR k := 0 TO n - 1 DO
      oi := Near^[k] ;
      IF NOT Listed (Finished, NFinished, oi) THEN
         o := ADR (Bodies^[oi]) ;
         IF NOT (b^.fixed AND o^.fixed) THEN PredictPair (b, o, now) END
      END
   END ;
   ScheduleCell (b, now) ;
   IF (b^.sup >= 0) AND Bodies^[b^.sup].fixed THEN schedule_support (b) END
END predict_apart ;


(* A contact met again at the instant it was handled (repeated): the
   contacts handled at this instant that reach it (cluster) are solved
   together (solve_cluster); a sleeper the solve would jolt wakes and the
   solve is made again with it moving.  Then an E collision line per
   contact (its normal impulse), each followed by the states of its moving
   bodies not written yet (settle); what a body whose velocity changed
   carries leaves; those slow enough fall asleep (wedged), and the others
   are predicted again. *)
PROCEDURE handle_cluster (t: REAL; ev: CollisionEvent) ;
VAR
   k, m, s, g, n0, nw: INTEGER ;
   A, B, b: BodyRef ;
   grow: BOOLEAN ;
BEGIN
   touch (t, ev.a, ev.b, ev.feature, ev.i, ev.j) ;
   LOOP
      cluster (ev) ;
      FOR k := 0 TO NRows - 1 DO
         rebase (ADR (Bodies^[Rows^[k].a]), t) ;
         rebase (ADR (Bodies^[Rows^[k].b]), t)
      END ;
      solve_cluster (t) ;
      s := jolted_sleeper () ;
      IF s < 0 THEN EXIT END ;
      set_velocities (0) ;
      handle_wake (ADR (Bodies^[s]), t)
   END ;
   NFinished := 0 ;    (* first the bodies written (settle), then those done *)
   nw := 0 ;
   FOR k := 0 TO NRows - 1 DO
      WITH Rows^[k] DO
         A := ADR (Bodies^[a]) ;
         B := ADR (Bodies^[b]) ;
         INC (Stats.collisions) ;
         EmitContact ("collision", t, a, b, feature, i, j, cx, cy, nx, ny, acc) ;
         AddContact (t, a, b, feature, i, j, cx, cy, nx, ny, acc, FALSE)
      END ;
      FOR m := 0 TO 1 DO
         IF m = 0 THEN b := A ELSE b := B END ;
         IF IsMover (b^.idx) AND NOT Listed (Written, nw, b^.idx) THEN
            Append1 (Written, nw, CapWritten, b^.idx) ;
            settle (b)
         END
      END
   END ;
   n0 := NLeft ;
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      WITH Movers^[k] DO
         IF (b^.vx # sx) OR (b^.vy # sy) OR (b^.om # som) THEN release (b, t) END
      END
   END ;
   grow := TRUE ;
   WHILE grow DO
      grow := FALSE ;
      FOR k := 0 TO NMovers - 1 DO
         b := ADR (Bodies^[Movers^[k].idx]) ;
         IF NOT b^.asleep THEN
            g := wedged (b) ;
            IF g >= 0 THEN
               handle_sleep (b, ADR (Bodies^[g]), t) ;
               Append1 (Finished, NFinished, CapFinished, b^.idx) ;
               grow := TRUE
            END
         END
      END
   END ;
   FOR k := 0 TO NMovers - 1 DO
      b := ADR (Bodies^[Movers^[k].idx]) ;
      IF NOT b^.asleep THEN
         predict_apart (b, t) ;
         Append1 (Finished, NFinished, CapFinished, b^.idx)
      END
   END ;
   predict_released (n0, t)
END handle_cluster ;


(* b is one of the cluster's movers. *)
PROCEDURE IsMover (x: INTEGER) : BOOLEAN ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := 0 TO NMovers - 1 DO
      IF Movers^[k].idx = x THEN RETURN TRUE END
   END ;
   RETURN FALSE
END IsMover ;


(* ---- event handlers: one per kind --------------------------------------------- *)

PROCEDURE handle_collision (t: REAL; ev: CollisionEvent) ;
VAR
   A, B: BodyRef ;
   cx, cy, nx, ny, vn, imp: REAL ;
   isheld: BOOLEAN ;
   n0: INTEGER ;
BEGIN
   A := ADR (Bodies^[ev.a]) ;
   B := ADR (Bodies^[ev.b]) ;
   IF repeated (t, ev) THEN
      handle_cluster (t, ev) ;
      RETURN
   END ;
   rebase (A, t) ;
   rebase (B, t) ;
   contact_frame (t, ev.feature, A, B, ev.i, ev.j, cx, cy, nx, ny) ;
   vn := normal_speed (A, B, cx, cy, nx, ny) ;
   IF can_support (A, B, ev.feature, ev.i, ev.j, vn) OR can_carry (A, B, ev.feature, ev.i, ev.j, vn) THEN
      handle_support (t, ev, A, B, cx, cy, nx, ny, vn) ;
      RETURN
   END ;
   IF can_sleep (A, B, ev, nx, ny, vn) THEN
      handle_sleep (A, B, t) ;
      RETURN
   END ;
   IF can_sleep (B, A, ev, nx, ny, vn) THEN
      handle_sleep (B, A, t) ;
      RETURN
   END ;
   INC (Stats.collisions) ;
   (* a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
      on it); a gentle touch leaves it asleep, a real impulse wakes its island;
      a slow contact of bodies held on their supports keeps them there *)
   isheld := held (A, B, nx, ny, vn) ;
   IF isheld THEN
      imp := held_impulse (A, B, nx, ny, vn)
   ELSIF A^.asleep OR B^.asleep THEN
      imp := sleeper_impulse (A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
   ELSE
      imp := contact_impulse (A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
   END ;
   IF (imp # 0.0) AND NOT isheld THEN
      IF A^.asleep AND jolted (A) THEN handle_wake (A, t) END ;
      IF B^.asleep AND jolted (B) THEN handle_wake (B, t) END ;
      IF A^.sup >= 0 THEN end_support (A) END ;
      IF B^.sup >= 0 THEN end_support (B) END
   END ;
   EmitContact ("collision", t, A^.idx, B^.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp) ;
   AddContact (t, A^.idx, B^.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, FALSE) ;
   touch (t, ev.a, ev.b, ev.feature, ev.i, ev.j) ;
   (* a sleeper still asleep (zero impulse: the bodies graze, the other not
      pressed onto it) is unchanged; the other is predicted again without it
      (so the graze is not found again at once): only a later change of the
      other's motion predicts the pair again *)
   IF (NOT A^.fixed) AND (NOT A^.asleep) THEN
      INC (A^.stamp) ;
      EmitState (A)
   END ;
   IF (NOT B^.fixed) AND (NOT B^.asleep) THEN
      INC (B^.stamp) ;
      EmitState (B)
   END ;
   (* an impulse changes the motion of what it hit: what they carried leaves *)
   n0 := NLeft ;
   IF imp # 0.0 THEN
      IF NOT A^.fixed THEN release (A, t) END ;
      IF NOT B^.fixed THEN release (B, t) END
   END ;
   IF (NOT A^.fixed) AND (NOT A^.asleep) THEN
      IF B^.asleep AND (imp = 0.0) THEN PredictBody (A, t, B^.idx) ELSE PredictBody (A, t, -1) END
   END ;
   IF (NOT B^.fixed) AND (NOT B^.asleep) THEN
      IF ((NOT A^.fixed) AND (NOT A^.asleep)) OR (A^.asleep AND (imp = 0.0)) THEN
         PredictBody (B, t, A^.idx)
      ELSE
         PredictBody (B, t, -1)
      END
   END ;
   predict_released (n0, t)
END handle_collision ;


(* The contact line of a collision, support or the like: "E KIND t a b
   feature i j cx cy nx ny impulse". *)
PROCEDURE EmitContact (kind: ARRAY OF CHAR; t: REAL; a, b, feature, i, j: INTEGER; cx, cy, nx, ny, imp: REAL) ;
BEGIN
   Str ("E ") ;
   Str (kind) ;
   Str (" ") ;
   Real (t) ;
   Str (" ") ; Int (a) ;
   Str (" ") ; Int (b) ;
   Str (" ") ; Int (feature) ;
   Str (" ") ; Int (i) ;
   Str (" ") ; Int (j) ;
   SpReal (cx) ;
   SpReal (cy) ;
   SpReal (nx) ;
   SpReal (ny) ;
   SpReal (imp) ;
   Ln
END EmitContact ;


(* Keeps a contact for the next report (Advance, Finish). *)
PROCEDURE AddContact (t: REAL; a, b, feature, i, j: INTEGER; px, py, nx, ny, imp: REAL; support: BOOLEAN) ;
VAR
   c: Contact ;
BEGIN
   IF NContacts = CapContacts THEN
      IF CapContacts = 0 THEN CapContacts := 64 ELSE CapContacts := 2 * CapContacts END ;
      Contacts := realloc (Contacts, VAL (LONGCARD, CapContacts) * VAL (LONGCARD, SIZE (Contact))) ;
      IF Contacts = NIL THEN
         CapContacts := 0 ;
         NContacts := 0 ;
         Fails ("out of memory (contacts)") ;
         RETURN
      END
   END ;
   c.t := t ;
   c.a := a ;
   c.b := b ;
   c.feature := feature ;
   c.i := i ;
   c.j := j ;
   c.px := px ;
   c.py := py ;
   c.nx := nx ;
   c.ny := ny ;
   c.impulse := imp ;
   c.support := support ;
   Contacts^[NContacts] := c ;
   INC (NContacts)
END AddContact ;


(* A collision that ends in support (called by handle_collision). *)
PROCEDURE handle_support (t: REAL; ev: CollisionEvent; A, B: BodyRef; cx, cy, nx, ny, vn: REAL) ;
VAR
   imp: REAL ;
   n0: INTEGER ;
BEGIN
   INC (Stats.supports) ;
   imp := (-vn) / A^.invM ;
   IF B^.fixed THEN enter_support (A, B, ev.j) ELSE enter_carried (A, B, ev.j) END ;
   EmitContact ("support", t, A^.idx, B^.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp) ;
   AddContact (t, A^.idx, B^.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, TRUE) ;
   touch (t, ev.a, ev.b, ev.feature, ev.i, ev.j) ;
   IF at_rest (A) THEN
      handle_sleep (A, B, t) ;
      RETURN
   END ;
   INC (A^.stamp) ;
   EmitState (A) ;
   n0 := NLeft ;
   release (A, t) ;
   PredictBody (A, t, -1) ;
   predict_released (n0, t)
END handle_support ;


(* The line of a stop or leave event: "E KIND t body sup -1 -1 edge 0 0 0 0 0". *)
PROCEDURE EmitSupportEnd (kind: ARRAY OF CHAR; t: REAL; body, sup, edge: INTEGER) ;
BEGIN
   Str ("E ") ;
   Str (kind) ;
   Str (" ") ;
   Real (t) ;
   Str (" ") ; Int (body) ;
   Str (" ") ; Int (sup) ;
   Str (" -1 -1 ") ; Int (edge) ;
   Str (" 0 0 0 0 0") ;
   Ln
END EmitSupportEnd ;


(* Sliding stops: velocity exactly the support's (zero when it does not
   move), then rest or slide back. *)
PROCEDURE handle_stop (t: REAL; ev: StopEvent) ;
VAR
   A, B: BodyRef ;
   bx, by, bang: REAL ;
   n0: INTEGER ;
BEGIN
   INC (Stats.stops) ;
   A := ADR (Bodies^[ev.body]) ;
   rebase (A, t) ;
   B := ADR (Bodies^[A^.sup]) ;
   IF static (B) THEN
      A^.vx := 0.0 ;
      A^.vy := 0.0
   ELSE
      StateAt (B, t, bx, by, A^.vx, A^.vy, bang)
   END ;
   slide_accel (A, 0.0) ;
   EmitSupportEnd ("stop", t, A^.idx, A^.sup, A^.sup_edge) ;
   IF at_rest (A) THEN
      handle_sleep (A, ADR (Bodies^[A^.sup]), t) ;
      RETURN
   END ;
   INC (A^.stamp) ;
   EmitState (A) ;
   n0 := NLeft ;
   release (A, t) ;
   PredictBody (A, t, -1) ;
   predict_released (n0, t)
END handle_stop ;


(* The support's edge ends under the body: free motion again. *)
PROCEDURE handle_leave (t: REAL; ev: LeaveEvent) ;
VAR
   n0: INTEGER ;
BEGIN
   n0 := NLeft ;
   leave (ADR (Bodies^[ev.body]), t, -1) ;
   predict_released (n0, t)
END handle_leave ;


PROCEDURE handle_input (t: REAL; ev: InputEvent) ;
VAR
   b: BodyRef ;
   inp: Input ;
   o, n0: INTEGER ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   INC (Stats.inputs) ;
   inp := Inputs^[ev.k] ;
   b := ADR (Bodies^[inp.body]) ;
   IF b^.gone THEN
      m := "input " ;
      AppendInt (m, ev.k) ;
      Append (m, ": body ") ;
      AppendInt (m, b^.idx) ;
      Append (m, " was removed before t = ") ;
      AppendReal (m, t) ;
      Fails (m) ;
      RETURN
   END ;
   IF b^.asleep THEN handle_wake (b, t) END ;
   rebase (b, t) ;
   IF inp.mode = RemoveMode THEN
      remove (b, ev.k, t) ;
      RETURN
   END ;
   IF b^.fixed THEN
      drive (b, ev.k, t, inp.vx, inp.vy) ;
      RETURN
   END ;
   IF inp.mode = TeleportMode THEN
      o := overlapping (b, inp.vx, inp.vy, t) ;
      IF o >= 0 THEN
         m := "input " ;
         AppendInt (m, ev.k) ;
         Append (m, ": body ") ;
         AppendInt (m, b^.idx) ;
         Append (m, " teleported to (") ;
         AppendReal (m, inp.vx) ;
         Append (m, ", ") ;
         AppendReal (m, inp.vy) ;
         Append (m, ") at t = ") ;
         AppendReal (m, t) ;
         Append (m, " would overlap body ") ;
         AppendInt (m, o) ;
         Fails (m) ;
         RETURN
      END
   END ;
   IF b^.sup >= 0 THEN end_support (b) END ;
   IF inp.mode = SetVelocityMode THEN
      b^.vx := inp.vx ;
      b^.vy := inp.vy
   ELSIF inp.mode = AddVelocityMode THEN
      b^.vx := b^.vx + inp.vx ;
      b^.vy := b^.vy + inp.vy
   ELSIF inp.mode = ImpulseMode THEN
      b^.vx := b^.vx + inp.vx * b^.invM ;
      b^.vy := b^.vy + inp.vy * b^.invM
   ELSE
      b^.px := inp.vx ;
      b^.py := inp.vy ;
      IF NOT b^.large THEN   (* a large body is in no cell: every body checks it *)
         CellRemove (b) ;
         CellOf (b^.px, b^.py, b^.cx, b^.cy) ;
         CellAdd (b)
      END
   END ;
   INC (b^.stamp) ;
   Str ("E input ") ;
   Real (t) ;
   Str (" ") ;
   Int (b^.idx) ;
   Str (" -1 -1 ") ;
   Int (ev.k) ;
   Str (" -1 0 0 0 0 0") ;
   Ln ;
   EmitState (b) ;
   n0 := NLeft ;
   release (b, t) ;
   PredictBody (b, t, -1) ;
   predict_released (n0, t)
END handle_input ;


(* Input k removes the body (based at t): it stops where it is (v, a, w
   zero), leaves the grid, its stamp changes (its queued events go stale)
   and it is never predicted again; bodies it supported leave. *)
PROCEDURE remove (b: BodyRef; k: INTEGER; t: REAL) ;
VAR
   i, n0: INTEGER ;
BEGIN
   b^.vx := 0.0 ; b^.vy := 0.0 ; b^.ax := 0.0 ; b^.ay := 0.0 ; b^.fax := 0.0 ; b^.fay := 0.0 ; b^.om := 0.0 ;
   IF b^.sup >= 0 THEN end_support (b) END ;
   b^.gone := TRUE ;
   INC (b^.stamp) ;
   IF b^.large THEN unplace_large (b) ELSE CellRemove (b) END ;
   Str ("E input ") ;
   Real (t) ;
   Str (" ") ;
   Int (b^.idx) ;
   Str (" -1 -1 ") ;
   Int (k) ;
   Str (" -1 0 0 0 0 0") ;
   Ln ;
   FOR i := 0 TO NBodies - 1 DO
      IF Bodies^[i].sup = b^.idx THEN
         n0 := NLeft ;
         leave (ADR (Bodies^[i]), t, -1) ;
         predict_released (n0, t)
      END
   END ;
   wake_touching (b, t)
END remove ;


(* Input k sets the velocity of fixed polygon B (based at t, it does not
   turn): a large one placed in grid cells moves to the large list for
   good; every body it supported leaves (E leave, free motion: it meets B
   again at once and is supported again relative to B's new motion, or
   bounces, or falls); B is predicted against every body again (a large B:
   each small one that is not fixed or removed, in index order; a small one:
   PredictBody), the bodies that left against the others; last the islands
   touching B wake (wake_touching: B may have held them, or carries them
   into others). *)
PROCEDURE drive (B: BodyRef; k: INTEGER; t, vx, vy: REAL) ;
VAR
   i, n0: INTEGER ;
   o: BodyRef ;
BEGIN
   B^.vx := vx ;
   B^.vy := vy ;
   INC (B^.stamp) ;
   IF B^.placed THEN
      unplace_large (B) ;
      B^.placed := FALSE ;
      LargeAdd (B^.idx)
   END ;
   Str ("E input ") ;
   Real (t) ;
   Str (" ") ;
   Int (B^.idx) ;
   Str (" -1 -1 ") ;
   Int (k) ;
   Str (" -1 0 0 0 0 0") ;
   Ln ;
   EmitState (B) ;
   n0 := NLeft ;
   FOR i := 0 TO NBodies - 1 DO
      IF Bodies^[i].sup = B^.idx THEN leave (ADR (Bodies^[i]), t, B^.idx) END
   END ;
   IF B^.large THEN
      FOR i := 0 TO NBodies - 1 DO
         o := ADR (Bodies^[i]) ;
         IF (NOT o^.large) AND (NOT o^.gone) AND (NOT o^.fixed) THEN PredictPair (o, B, t) END
      END
   ELSE
      PredictBody (B, t, -1)
   END ;
   predict_released (n0, t) ;
   wake_touching (B, t)
END drive ;


(* The islands of the sleepers whose bounding circles reach the body's
   (within the tolerance; a body removed, or a fixed one whose velocity an
   input set) wake: it may have held them (by index; a woken island's other
   members are awake already). *)
PROCEDURE wake_touching (b: BodyRef; t: REAL) ;
VAR
   i: INTEGER ;
   o: BodyRef ;
   dx, dy, reach: REAL ;
BEGIN
   FOR i := 0 TO NBodies - 1 DO
      o := ADR (Bodies^[i]) ;
      IF o^.asleep THEN
         dx := o^.px - b^.px ;
         dy := o^.py - b^.py ;
         reach := o^.bound + b^.bound + Tol ;
         IF dx * dx + dy * dy <= reach * reach THEN handle_wake (o, t) END
      END
   END
END wake_touching ;


(* ---- overlap (a teleport's check) -------------------------------------------- *)

(* The first body (by index) that A, with its centre moved to (x, y) at time
   t, would overlap by more than the tolerance; -1 when none. *)
PROCEDURE overlapping (A: BodyRef; x, y, t: REAL) : INTEGER ;
VAR
   spx, spy, svx, svy, sang, stb: REAL ;
   ax, ay, vx, vy, ang, bx, by, bvx, bvy, bang, dx, dy, reach: REAL ;
   k, found: INTEGER ;
   B: BodyRef ;
BEGIN
   spx := A^.px ; spy := A^.py ; svx := A^.vx ; svy := A^.vy ; sang := A^.ang ; stb := A^.tb ;
   StateAt (A, t, ax, ay, vx, vy, ang) ;
   (* A at t, moved (restored below) *)
   A^.px := x ; A^.py := y ; A^.vx := vx ; A^.vy := vy ; A^.ang := ang ; A^.tb := t ;
   found := -1 ;
   k := 0 ;
   WHILE (found < 0) AND (k < NBodies) DO
      B := ADR (Bodies^[k]) ;
      IF (B # A) AND NOT B^.gone THEN
         StateAt (B, t, bx, by, bvx, bvy, bang) ;
         dx := bx - x ;
         dy := by - y ;
         reach := A^.bound + B^.bound + Tol ;
         IF (NOT (dx * dx + dy * dy > reach * reach)) AND (separation (A, B, t) < -Tol) THEN
            found := B^.idx
         END
      END ;
      INC (k)
   END ;
   A^.px := spx ; A^.py := spy ; A^.vx := svx ; A^.vy := svy ; A^.ang := sang ; A^.tb := stb ;
   RETURN found
END overlapping ;


(* The largest gap between A and B at t along a separating axis: negative
   by the depth they overlap (edge normals of either polygon, and for a
   circle the line from the nearest vertex; circles: the distance of the
   centres less the radii). *)
PROCEDURE separation (A, B: BodyRef; t: REAL) : REAL ;
VAR
   ax, ay, bx, by, s1, s2: REAL ;
BEGIN
   IF (NOT A^.polygon) AND (NOT B^.polygon) THEN
      PointAt (A, -1, t, ax, ay) ;
      PointAt (B, -1, t, bx, by) ;
      RETURN sqrt ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A^.r + B^.r)
   END ;
   IF NOT A^.polygon THEN RETURN circle_separation (A, B, t) END ;
   IF NOT B^.polygon THEN RETURN circle_separation (B, A, t) END ;
   s1 := edges_separation (A, B, t) ;
   s2 := edges_separation (B, A, t) ;
   IF s2 > s1 THEN RETURN s2 END ;     (* Python's max: the first unless the second is larger *)
   RETURN s1
END separation ;


(* Outward unit normal (ox, oy) of edge j of P at t and the offset of its
   line, (ox, oy) . point = off. *)
PROCEDURE edge_line (P: BodyRef; j: INTEGER; t: REAL; VAR ox, oy, off: REAL) ;
VAR
   px, py, vx, vy, ang, c, s, enx, eny: REAL ;
BEGIN
   enx := Verts^[P^.v0 + j].nx ;
   eny := Verts^[P^.v0 + j].ny ;
   StateAt (P, t, px, py, vx, vy, ang) ;
   c := cos (ang) ;
   s := sin (ang) ;
   ox := c * enx - s * eny ;
   oy := s * enx + c * eny ;
   off := ox * px + oy * py + Verts^[P^.v0 + j].h
END edge_line ;


(* Along the edge normals of P: the largest over P's edges of the smallest
   distance of Q's vertices beyond the edge's line. *)
PROCEDURE edges_separation (P, Q: BodyRef; t: REAL) : REAL ;
VAR
   best, lo, d, ox, oy, off, qx, qy: REAL ;
   j, v: INTEGER ;
BEGIN
   best := -Inf ;
   FOR j := 0 TO P^.nv - 1 DO
      edge_line (P, j, t, ox, oy, off) ;
      lo := Inf ;
      FOR v := 0 TO Q^.nv - 1 DO
         PointAt (Q, Q^.v0 + v, t, qx, qy) ;
         d := ox * qx + oy * qy - off ;
         IF d < lo THEN lo := d END
      END ;
      IF lo > best THEN best := lo END
   END ;
   RETURN best
END edges_separation ;


(* Circle C against polygon P: along P's edge normals and the line from
   P's nearest vertex to C's centre. *)
PROCEDURE circle_separation (C, P: BodyRef; t: REAL) : REAL ;
VAR
   cx, cy, best, ox, oy, off, g, qx, qy, e2, d2, d, ux, uy, hi, nqx, nqy: REAL ;
   j, k: INTEGER ;
BEGIN
   PointAt (C, -1, t, cx, cy) ;
   best := -Inf ;
   FOR j := 0 TO P^.nv - 1 DO
      edge_line (P, j, t, ox, oy, off) ;
      g := ox * cx + oy * cy - off - C^.r ;
      IF g > best THEN best := g END
   END ;
   d2 := Inf ;
   PointAt (P, P^.v0, t, nqx, nqy) ;    (* vertex 0 unless a nearer one is found *)
   FOR k := 0 TO P^.nv - 1 DO
      PointAt (P, P^.v0 + k, t, qx, qy) ;
      e2 := (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy) ;
      IF e2 < d2 THEN
         d2 := e2 ;
         nqx := qx ;
         nqy := qy
      END
   END ;
   IF d2 > 0.0 THEN
      d := sqrt (d2) ;
      ux := (cx - nqx) / d ;
      uy := (cy - nqy) / d ;
      hi := -Inf ;
      FOR k := 0 TO P^.nv - 1 DO
         PointAt (P, P^.v0 + k, t, qx, qy) ;
         g := ux * qx + uy * qy ;
         IF g > hi THEN hi := g END
      END ;
      g := ux * cx + uy * cy - C^.r - hi ;
      IF g > best THEN best := g END
   END ;
   RETURN best
END circle_separation ;


(* The body's centre went the grid's margin past its cell's edge along an axis: it
   moves to the next cell and is predicted against the row or column it now neighbours. *)
PROCEDURE handle_cell (t: REAL; ev: CellEvent) ;
VAR
   b: BodyRef ;
   d, col, row, lo, n, k: INTEGER ;
BEGIN
   INC (Stats.cells) ;
   b := ADR (Bodies^[ev.body]) ;
   d := ev.direction ;
   CellRemove (b) ;
   IF ev.axis = 0 THEN
      b^.cx := b^.cx + d ;
      col := b^.cx + d ;
      CellAdd (b) ;
      PredictCells (b, col, col, b^.cy - 1, b^.cy + 1, -1, -1, t)
   ELSE
      b^.cy := b^.cy + d ;
      row := b^.cy + d ;
      CellAdd (b) ;
      PredictCells (b, b^.cx - 1, b^.cx + 1, row, row, -1, -1, t)
   END ;
   (* the walls of the new row or column but those also listed in the two
      it shares with the old neighbourhood (predicted at its last change) *)
   INC (Mark) ;
   n := 0 ;
   IF ev.axis = 0 THEN
      IF d > 0 THEN lo := b^.cx - 1 ELSE lo := b^.cx END ;
      walls_in (b, lo, lo + 1, b^.cy - 1, b^.cy + 1, FALSE, n) ;
      walls_in (b, col, col, b^.cy - 1, b^.cy + 1, TRUE, n)
   ELSE
      IF d > 0 THEN lo := b^.cy - 1 ELSE lo := b^.cy END ;
      walls_in (b, b^.cx - 1, b^.cx + 1, lo, lo + 1, FALSE, n) ;
      walls_in (b, b^.cx - 1, b^.cx + 1, row, row, TRUE, n)
   END ;
   SortNear (n) ;
   IF NOT b^.fixed THEN
      FOR k := 0 TO n - 1 DO
         PredictPair (b, ADR (Bodies^[Near^[k]]), t)
      END
   END ;
   ScheduleCell (b, t)
END handle_cell ;


(* The pair is predicted again from here (its bounding circles meet, or its
   Taylor window ended). *)
PROCEDURE handle_horizon (t: REAL; ev: HorizonEvent) ;
BEGIN
   INC (Stats.horizons) ;
   PredictPair (ADR (Bodies^[ev.a]), ADR (Bodies^[ev.b]), t)
END handle_horizon ;


(* Frame k: written, and frame k + 1 scheduled. *)
PROCEDURE handle_frame (t: REAL; ev: FrameEvent) ;
VAR
   nxt: REAL ;
BEGIN
   INC (Stats.frames) ;
   Str ("E frame ") ;
   Real (t) ;
   Str (" -1 -1 -1 -1 -1 0 0 0 0 0") ;
   Ln ;
   nxt := VAL (REAL, ev.k + 1) * FrameDt ;
   IF nxt <= EndT THEN
      push_frame (nxt, ev.k + 1)
   END
END handle_frame ;


(* ---- the run ------------------------------------------------------------------ *)

(* An event whose bodies' motion changed since it was scheduled.  Inputs are
   scripted, not predicted, and frames have no bodies: never. *)
PROCEDURE is_stale (ev: Event) : BOOLEAN ;
BEGIN
   CASE ev.kind OF
      KCollision:
         RETURN (Bodies^[ev.collision.a].stamp # ev.collision.stamp_a)
                OR (Bodies^[ev.collision.b].stamp # ev.collision.stamp_b)
    | KHorizon:
         RETURN (Bodies^[ev.horizon.a].stamp # ev.horizon.stamp_a)
                OR (Bodies^[ev.horizon.b].stamp # ev.horizon.stamp_b)
    | KCell:
         RETURN Bodies^[ev.cell.body].stamp # ev.cell.stamp
    | KStop:
         RETURN Bodies^[ev.stop.body].stamp # ev.stop.stamp
    | KLeave:
         RETURN Bodies^[ev.leave.body].stamp # ev.leave.stamp
   ELSE
      RETURN FALSE
   END
END is_stale ;


(* The grid, the inputs, the first frame and the first prediction of every
   pair. *)
PROCEDURE start ;
VAR
   i, k: INTEGER ;
   b: BodyRef ;
   ev: Event ;
BEGIN
   InitGrid ;
   Mark := 0 ;
   FOR i := 0 TO NBodies - 1 DO
      IF Bodies^[i].large THEN place_large (ADR (Bodies^[i])) END
   END ;
   Clear ;
   Seq := 0 ;
   Stats.collisions := 0 ;
   Stats.inputs := 0 ;
   Stats.frames := 0 ;
   Stats.cells := 0 ;
   Stats.horizons := 0 ;
   Stats.stale := 0 ;
   Stats.pairs := 0 ;
   Stats.features := 0 ;
   Stats.supports := 0 ;
   Stats.stops := 0 ;
   Stats.leaves := 0 ;
   Stats.sleeps := 0 ;
   Stats.wakes := 0 ;
   FOR k := 0 TO CcVariants - 1 DO CcCounts[k] := 0 END ;
   FOR k := 0 TO PeVariants - 1 DO PeCounts[k] := 0 END ;
   WorldT := 0.0 ;
   LastT := -1.0 ;
   Same := 0 ;
   TouchedT := -1.0 ;
   NTouched := 0 ;
   NContacts := 0 ;
   NAdded := 0 ;
   Unpaid := FALSE ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF NOT b^.large THEN
         CellOf (b^.px, b^.py, b^.cx, b^.cy) ;
         CellAdd (b)
      END
   END ;
   FOR k := 0 TO NInputs - 1 DO
      ev.t := Inputs^[k].t ;
      ev.kind := KInput ;
      ev.input.k := k ;
      push (ev)
   END ;
   IF (FrameDt > 0.0) AND (FrameDt <= EndT) THEN
      push_frame (FrameDt, 1)
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF NOT b^.large THEN
         PredictCells (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, b^.idx, -1, 0.0) ;
         PredictLarge (b, -1, 0.0) ;
         ScheduleCell (b, 0.0)
      END
   END
END start ;


(* Handles one event taken from the queue: dropped when stale, counted at
   its instant (max_same_time: more is "stuck"), then its kind's handler. *)
PROCEDURE dispatch (ev: Event) ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF is_stale (ev) THEN
      INC (Stats.stale) ;
      RETURN
   END ;
   IF ev.t = LastT THEN
      INC (Same) ;
      IF Same > MaxSame THEN
         m := "more than " ;
         AppendInt (m, MaxSame) ;
         Append (m, " events at t = ") ;
         AppendReal (m, ev.t) ;
         Append (m, ": the scene is stuck") ;
         Fails (m) ;
         RETURN
      END
   ELSE
      LastT := ev.t ;
      Same := 0
   END ;
   CASE ev.kind OF
      KInput: handle_input (ev.t, ev.input)
    | KCollision: handle_collision (ev.t, ev.collision)
    | KStop: handle_stop (ev.t, ev.stop)
    | KLeave: handle_leave (ev.t, ev.leave)
    | KCell: handle_cell (ev.t, ev.cell)
    | KHorizon: handle_horizon (ev.t, ev.horizon)
    | KFrame: handle_frame (ev.t, ev.frame)
   END
END dispatch ;


(* Handles every queued event before t (inclusive: at t too), in (t, kind,
   seq) order, the events that handling schedules included; stops at a
   failure. *)
PROCEDURE process (t: REAL; inclusive: BOOLEAN) ;
VAR
   ev: Event ;
BEGIN
   WHILE (NOT Failed) AND Top (ev) AND ((ev.t < t) OR ((ev.t = t) AND inclusive)) DO
      IF Pop (ev) THEN dispatch (ev) END
   END
END process ;


(* Calls report with each contact kept since the last report, in order. *)
PROCEDURE TakeContacts (report: ContactProc) ;
VAR
   k, n: INTEGER ;
BEGIN
   n := NContacts ;
   NContacts := 0 ;
   Reporting := TRUE ;
   FOR k := 0 TO n - 1 DO report (Contacts^[k]) END ;
   Reporting := FALSE
END TakeContacts ;


(* Every body at the end time, the statistics and the predictions served
   per variant. *)
PROCEDURE WriteFinal ;
VAR
   i, k: INTEGER ;
   b: BodyRef ;
BEGIN
   FOR i := 0 TO NBodies - 1 DO
      rebase (ADR (Bodies^[i]), EndT)
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      Str ("F ") ;
      Int (i) ;
      SpReal (b^.px) ;
      SpReal (b^.py) ;
      SpReal (b^.vx) ;
      SpReal (b^.vy) ;
      SpReal (b^.ang) ;
      SpReal (b^.om) ;
      Ln
   END ;
   Stat ("collisions", Stats.collisions) ;
   Stat ("inputs", Stats.inputs) ;
   Stat ("frames", Stats.frames) ;
   Stat ("cells", Stats.cells) ;
   Stat ("horizons", Stats.horizons) ;
   Stat ("stale", Stats.stale) ;
   Stat ("pairs", Stats.pairs) ;
   Stat ("features", Stats.features) ;
   Stat ("supports", Stats.supports) ;
   Stat ("stops", Stats.stops) ;
   Stat ("leaves", Stats.leaves) ;
   Stat ("sleeps", Stats.sleeps) ;
   Stat ("wakes", Stats.wakes) ;
   FOR k := 0 TO CcVariants - 1 DO
      Str ("V circle_circle ") ;
      Int (k) ;
      Str (" ") ;
      Int (CcCounts[k]) ;
      Ln
   END ;
   FOR k := 0 TO PeVariants - 1 DO
      Str ("V point_edge ") ;
      Int (k) ;
      Str (" ") ;
      Int (PeCounts[k]) ;
      Ln
   END
END WriteFinal ;


(* ---- the live API (docs/engine-api.md) ------------------------------------------ *)

(* A world from the scene just read (ok), or the reading's failure. *)
PROCEDURE Begin (ok, trace: BOOLEAN) : BOOLEAN ;
BEGIN
   Loaded := FALSE ;
   Failed := FALSE ;
   Reporting := FALSE ;
   NLeft := 0 ;                (* a world that failed in a handler may have left some listed *)
   IF NOT ok THEN
      ReadError (ErrMsg) ;
      RETURN FALSE
   END ;
   ErrMsg[0] := 0C ;
   SetOn (trace) ;
   start ;
   Loaded := NOT Failed ;
   RETURN Loaded
END Begin ;


PROCEDURE New (VAR text: ARRAY OF CHAR; trace: BOOLEAN) : BOOLEAN ;
BEGIN
   RETURN Begin (ReadText (ADR (text), HIGH (text) + 1), trace)
END New ;


PROCEDURE FromFile (path: ARRAY OF CHAR; trace: BOOLEAN) : BOOLEAN ;
BEGIN
   RETURN Begin (ReadFile (path), trace)
END FromFile ;


PROCEDURE FromStdin (trace: BOOLEAN) : BOOLEAN ;
BEGIN
   RETURN Begin (ReadStdin (), trace)
END FromStdin ;


PROCEDURE Time () : REAL ;
BEGIN
   RETURN WorldT
END Time ;


PROCEDURE EndTime () : REAL ;
BEGIN
   RETURN EndT
END EndTime ;


PROCEDURE BodyCount () : INTEGER ;
BEGIN
   RETURN NBodies
END BodyCount ;


PROCEDURE Advance (t: REAL; report: ContactProc) : BOOLEAN ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF NOT Usable () THEN RETURN FALSE END ;
   IF NOT ((t >= WorldT) AND (t <= EndT)) THEN
      m := "advance: t = " ;
      AppendReal (m, t) ;
      Append (m, " is outside [") ;
      AppendReal (m, WorldT) ;
      Append (m, ", ") ;
      AppendReal (m, EndT) ;
      Append (m, "] (the world's time .. the scene's end)") ;
      RETURN Refuse (m)
   END ;
   process (t, FALSE) ;
   IF Failed THEN RETURN FALSE END ;
   WorldT := t ;
   TakeContacts (report) ;
   RETURN TRUE
END Advance ;


PROCEDURE NextEventTime () : REAL ;
VAR
   ev: Event ;
BEGIN
   IF NOT Usable () THEN RETURN Inf END ;
   WHILE Top (ev) AND (ev.t <= EndT) DO
      IF NOT is_stale (ev) THEN RETURN ev.t END ;
      IF Pop (ev) THEN INC (Stats.stale) END
   END ;
   RETURN Inf
END NextEventTime ;


PROCEDURE State (body: INTEGER; t: REAL; VAR px, py, vx, vy, ang, om: REAL) : BOOLEAN ;
VAR
   nxt: REAL ;
   b: BodyRef ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF NOT Usable () THEN RETURN FALSE END ;
   IF NOT BodyOk (body) THEN RETURN FALSE END ;
   b := ADR (Bodies^[body]) ;
   nxt := NextEventTime () ;
   IF NOT ((t >= WorldT) AND (t <= nxt) AND (t <= EndT)) THEN
      m := "state: t = " ;
      AppendReal (m, t) ;
      Append (m, " is outside [") ;
      AppendReal (m, WorldT) ;
      Append (m, ", ") ;
      AppendReal (m, nxt) ;
      Append (m, "] (the world's time .. the next event)") ;
      RETURN Refuse (m)
   END ;
   StateAt (b, t, px, py, vx, vy, ang) ;
   om := b^.om ;
   RETURN TRUE
END State ;


PROCEDURE States (t: REAL; VAR px, py, vx, vy, ang, om: ARRAY OF REAL) : BOOLEAN ;
VAR
   k: INTEGER ;
   room: CARDINAL ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF NOT Usable () THEN RETURN FALSE END ;
   room := HIGH (px) ;
   IF HIGH (py) < room THEN room := HIGH (py) END ;
   IF HIGH (vx) < room THEN room := HIGH (vx) END ;
   IF HIGH (vy) < room THEN room := HIGH (vy) END ;
   IF HIGH (ang) < room THEN room := HIGH (ang) END ;
   IF HIGH (om) < room THEN room := HIGH (om) END ;
   IF VAL (INTEGER, room) + 1 < NBodies THEN
      m := "states: room for " ;
      AppendInt (m, VAL (INTEGER, room) + 1) ;
      Append (m, " bodies, the world has ") ;
      AppendInt (m, NBodies) ;
      RETURN Refuse (m)
   END ;
   IF NBodies = 0 THEN RETURN TRUE END ;
   (* body 0 through State: its checks of t and its message *)
   IF NOT State (0, t, px[0], py[0], vx[0], vy[0], ang[0], om[0]) THEN RETURN FALSE END ;
   FOR k := 1 TO NBodies - 1 DO
      StateAt (ADR (Bodies^[k]), t, px[k], py[k], vx[k], vy[k], ang[k]) ;
      om[k] := Bodies^[k].om
   END ;
   RETURN TRUE
END States ;


(* FALSE (refused) when k is not a body of the world. *)
PROCEDURE BodyOk (k: INTEGER) : BOOLEAN ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF (k >= 0) AND (k < NBodies) THEN RETURN TRUE END ;
   m := "no body " ;
   AppendInt (m, k) ;
   Append (m, " (the world has ") ;
   AppendInt (m, NBodies) ;
   Append (m, ")") ;
   RETURN Refuse (m)
END BodyOk ;


(* ---- live inputs: at the world's time, recorded in the input list ---------------- *)

(* Handles the input events queued at exactly the world's time. *)
PROCEDURE inputs_now ;
VAR
   ev: Event ;
BEGIN
   WHILE (NOT Failed) AND Top (ev) AND (ev.t = WorldT) AND (ev.kind = KInput) DO
      IF Pop (ev) THEN dispatch (ev) END
   END
END inputs_now ;


(* An input at the world's time T, handled as the same input scripted at T
   and listed after the scene's would be: the scene's inputs at T first,
   then this one, before any other event at T (docs/engine-api.md, "Live
   inputs").  It is appended to the input list, which is the recording.
   done: FALSE when a teleport is refused (nothing changed). *)
(* An input of this mode may act on b: any on a movable body; on a fixed
   one, removal, or set_velocity when it is a polygon that does not turn
   (its edges then translate: docs/simulator.md, Contact model). *)
PROCEDURE drivable (b: BodyRef; mode: INTEGER) : BOOLEAN ;
BEGIN
   IF (NOT b^.fixed) OR (mode = RemoveMode) THEN RETURN TRUE END ;
   RETURN (mode = SetVelocityMode) AND b^.polygon AND (b^.om = 0.0)
END drivable ;


PROCEDURE live_input (body, mode: INTEGER; x, y: REAL; VAR done: BOOLEAN) : BOOLEAN ;
VAR
   b: BodyRef ;
   ev: Event ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   done := FALSE ;
   IF (NOT Usable ()) OR (NOT BodyOk (body)) THEN RETURN FALSE END ;
   b := ADR (Bodies^[body]) ;
   IF b^.gone THEN
      m := "body " ;
      AppendInt (m, body) ;
      Append (m, " was removed") ;
      RETURN Refuse (m)
   END ;
   IF NOT drivable (b, mode) THEN
      m := "body " ;
      AppendInt (m, body) ;
      Append (m, " is fixed: inputs move movable bodies only (or set the velocity of a fixed polygon that does ") ;
      Append (m, "not turn, or remove a fixed body)") ;
      RETURN Refuse (m)
   END ;
   IF (x - x # 0.0) OR (y - y # 0.0) THEN       (* not finite: inf - inf and nan - nan are nan *)
      m := "input on body " ;
      AppendInt (m, body) ;
      Append (m, ": (") ;
      AppendReal (m, x) ;
      Append (m, ", ") ;
      AppendReal (m, y) ;
      Append (m, ") is not finite") ;
      RETURN Refuse (m)
   END ;
   inputs_now ;
   IF Failed THEN RETURN FALSE END ;
   IF (mode = TeleportMode) AND (overlapping (b, x, y, WorldT) >= 0) THEN RETURN TRUE END ;
   ev.t := WorldT ;
   ev.kind := KInput ;
   ev.input.k := AddInput (WorldT, body, mode, x, y) ;
   push (ev) ;
   inputs_now ;
   IF Failed THEN RETURN FALSE END ;
   done := TRUE ;
   RETURN TRUE
END live_input ;


PROCEDURE SetVelocity (body: INTEGER; vx, vy: REAL) : BOOLEAN ;
VAR
   done: BOOLEAN ;
BEGIN
   RETURN live_input (body, SetVelocityMode, vx, vy, done)
END SetVelocity ;


PROCEDURE AddVelocity (body: INTEGER; dvx, dvy: REAL) : BOOLEAN ;
VAR
   done: BOOLEAN ;
BEGIN
   RETURN live_input (body, AddVelocityMode, dvx, dvy, done)
END AddVelocity ;


PROCEDURE ApplyImpulse (body: INTEGER; jx, jy: REAL) : BOOLEAN ;
VAR
   done: BOOLEAN ;
BEGIN
   RETURN live_input (body, ImpulseMode, jx, jy, done)
END ApplyImpulse ;


PROCEDURE Teleport (body: INTEGER; x, y: REAL; VAR moved: BOOLEAN) : BOOLEAN ;
BEGIN
   RETURN live_input (body, TeleportMode, x, y, moved)
END Teleport ;


PROCEDURE RemoveBody (body: INTEGER) : BOOLEAN ;
VAR
   done: BOOLEAN ;
BEGIN
   RETURN live_input (body, RemoveMode, 0.0, 0.0, done)
END RemoveBody ;


PROCEDURE AddBody (VAR text: ARRAY OF CHAR; VAR index: INTEGER) : BOOLEAN ;
VAR
   b, o: BodyRef ;
   nv, i: INTEGER ;
   t, lim: REAL ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   index := -1 ;
   IF NOT Usable () THEN RETURN FALSE END ;
   IF NOT ReadBodyText (ADR (text), HIGH (text) + 1, NBodies, NVerts, nv) THEN
      ReadError (ErrMsg) ;
      RETURN FALSE
   END ;
   b := ADR (Bodies^[NBodies]) ;      (* read, not yet in the world *)
   b^.idx := NBodies ;
   lim := CellW ;
   IF CellH < lim THEN lim := CellH END ;     (* Python's min (cw, ch) *)
   b^.large := 2.0 * b^.bound > lim ;
   IF b^.large AND NOT b^.fixed THEN
      m := "add_body: a movable body of bound " ;
      AppendReal (m, b^.bound) ;
      Append (m, " m does not fit the grid's cells (") ;
      AppendReal (m, CellW) ;
      Append (m, " x ") ;
      AppendReal (m, CellH) ;
      Append (m, " m): put such a body in the scene") ;
      RETURN Refuse (m)
   END ;
   t := WorldT ;
   b^.tb := t ;
   inputs_now ;
   IF Failed THEN RETURN FALSE END ;
   b := ADR (Bodies^[NBodies]) ;
   IF overlapping (b, b^.px, b^.py, t) >= 0 THEN RETURN TRUE END ;
   INC (NBodies) ;
   NVerts := NVerts + nv ;
   INC (NAdded) ;
   index := b^.idx ;
   Str ("E add ") ;
   Real (t) ;
   Str (" ") ;
   Int (b^.idx) ;
   Str (" -1 -1 -1 -1 0 0 0 0 0") ;
   Ln ;
   IF b^.large THEN
      place_large (b) ;
      FOR i := 0 TO NBodies - 1 DO
         o := ADR (Bodies^[i]) ;
         IF (NOT o^.large) AND (NOT o^.gone) AND NOT (o^.fixed AND b^.fixed) THEN
            PredictPair (o, b, t)
         END
      END
   ELSE
      CellOf (b^.px, b^.py, b^.cx, b^.cy) ;
      CellAdd (b) ;
      IF NOT b^.fixed THEN EmitState (b) END ;
      PredictBody (b, t, -1)
   END ;
   IF Failed THEN RETURN FALSE END ;
   RETURN TRUE
END AddBody ;


(* ---- the input log (recordings) ------------------------------------------------ *)

PROCEDURE InputLogLength () : INTEGER ;
BEGIN
   RETURN NInputs
END InputLogLength ;


PROCEDURE InputLog (k: INTEGER; VAR t: REAL; VAR body, mode: INTEGER; VAR x, y: REAL) : BOOLEAN ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF (k < 0) OR (k >= NInputs) THEN
      m := "no input " ;
      AppendInt (m, k) ;
      Append (m, " (the log has ") ;
      AppendInt (m, NInputs) ;
      Append (m, ")") ;
      RETURN Refuse (m)
   END ;
   t := Inputs^[k].t ;
   body := Inputs^[k].body ;
   mode := Inputs^[k].mode ;
   x := Inputs^[k].vx ;
   y := Inputs^[k].vy ;
   RETURN TRUE
END InputLog ;


PROCEDURE Added () : INTEGER ;
BEGIN
   RETURN NAdded
END Added ;


PROCEDURE Finish (report: ContactProc) : BOOLEAN ;
BEGIN
   IF NOT Usable () THEN RETURN FALSE END ;
   process (EndT, TRUE) ;
   IF Failed THEN RETURN FALSE END ;
   WorldT := EndT ;
   WriteFinal ;
   Flush ;
   TakeContacts (report) ;
   RETURN TRUE
END Finish ;


PROCEDURE Run () : BOOLEAN ;
BEGIN
   IF NOT Usable () THEN RETURN FALSE END ;
   process (EndT, FALSE) ;     (* Advance (EndT) and Finish, without the reports *)
   IF NOT Failed THEN
      WorldT := EndT ;
      process (EndT, TRUE)
   END ;
   IF Failed THEN RETURN FALSE END ;
   WriteFinal ;
   Flush ;
   NContacts := 0 ;
   RETURN TRUE
END Run ;


VAR
   endp: ADDRESS ;
BEGIN
   Loaded := FALSE ;
   Failed := FALSE ;
   Reporting := FALSE ;
   ErrMsg[0] := 0C ;
   WorldT := 0.0 ;
   Contacts := NIL ;
   NContacts := 0 ;
   CapContacts := 0 ;
   EdgePolys := NIL ;
   CapEdgePolys := 0 ;
   Near := NIL ;
   CapNear := 0 ;
   LeftBody := NIL ;
   LeftSkip := NIL ;
   NLeft := 0 ;
   CapLeft := 0 ;
   TouchedT := -1.0 ;
   Touched := NIL ;
   NTouched := 0 ;
   CapTouched := 0 ;
   Rows := NIL ;
   NRows := 0 ;
   CapRows := 0 ;
   Movers := NIL ;
   NMovers := 0 ;
   Pushes := NIL ;
   Joined := NIL ;
   NJoined := 0 ;
   CapJoined := 0 ;
   Written := NIL ;
   CapWritten := 0 ;
   Finished := NIL ;
   NFinished := 0 ;
   CapFinished := 0 ;
   Mark := 0 ;
   endp := NIL ;
   Inf := strtod ("inf", endp)
END SimWorld.
