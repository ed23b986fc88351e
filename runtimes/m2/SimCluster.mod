IMPLEMENTATION MODULE SimCluster ;

(* Simultaneous contacts: the Python reference's touch, repeated, cluster,
   joins, part, give, nudge, sweeps, kinetic, velocities, set_velocities,
   mix, pressing_contact, solve_cluster, jolted_sleeper, wedged, holds,
   settle, predict_apart and handle_cluster (its touched and touched_t are
   Touched and TouchedT; its rows, movers and pushes are Rows, Movers and
   Pushes). *)

FROM SYSTEM IMPORT ADR ;
FROM CMath IMPORT sqrt ;
FROM SimScene IMPORT Bodies, BodyRef, GridNX, GridNY, Grow, MaxItems, RestSpeed ;
FROM SimQueue IMPORT CollisionEvent ;
FROM SimGrid IMPORT Cells, IntList, large_near, Max, Min, Near ;
FROM SimOut IMPORT EmitContact ;
FROM SimWorld IMPORT AddContact, AddJammed, EmitState, HeldNow, NLeft, Stats ;
FROM SimMotion IMPORT rebase, TurnRate ;
FROM SimPredict IMPORT closing, PredictPair, ScheduleCell ;
FROM SimContact IMPORT contact_frame, normal_speed, pressed ;
FROM SimSupport IMPORT end_support, schedule_support, slide_accel, support_frame, support_relative ;
FROM SimSleep IMPORT grounded ;
FROM SimHandlers IMPORT handle_sleep, handle_wake, predict_released, release ;

CONST
   (* simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
      contacts"): how many times one contact is handled at one instant
      before it and the contacts it touches are solved together; the most
      sweeps of the cluster's sequential impulses, and the sweep that ends
      them: no impulse in it changed a normal speed by more than ClusterTol
      rest_speed *)
   ClusterRepeats = 64 ;
   (* a contact met ClusterRepeats + ClusterJam times at one instant (its
      cluster solved ClusterJam times there and met again) jams its
      cluster: the movers come to rest and fall asleep, held until the
      instant ends *)
   ClusterJam = 4 ;
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

TYPE
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
   (* the contacts handled at the instant TouchedT (touch): Touched^[0 .. NTouched - 1] *)
   Touched: TouchArray ;
   CapTouched: INTEGER ;
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
         IF S^.asleep AND NOT HeldNow (S) THEN
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
(* How many times the collision's contact was handled at this instant. *)
PROCEDURE jam_count (t: REAL; ev: CollisionEvent) : INTEGER ;
VAR
   k: INTEGER ;
BEGIN
   IF t # TouchedT THEN RETURN 0 END ;
   FOR k := 0 TO NTouched - 1 DO
      IF (Touched^[k].a = ev.a) AND (Touched^[k].b = ev.b) AND (Touched^[k].feature = ev.feature)
         AND (Touched^[k].i = ev.i) AND (Touched^[k].j = ev.j) THEN
         RETURN Touched^[k].times
      END
   END ;
   RETURN 0
END jam_count ;


(* A cluster its solves do not settle (met again after ClusterJam solves at
   one instant): inelastic collapse, resolved as in Luding's TC model with
   a contact time of zero: contacts met again at once lose all restitution
   and all sliding.  An E collision line per contact of the cluster
   (impulse 0), then each mover (a body of the cluster that is not held, in
   the contacts' order) falls asleep, at rest, on its support when that is
   fixed, else on the first body it touches in the cluster that is fixed or
   asleep, else on the other body of its first contact; it is held until
   the instant ends (SimWorld.HeldNow).  Kinetic energy only falls. *)
PROCEDURE jam (t: REAL; ev: CollisionEvent) ;
VAR
   k, q, n, m, o, g: INTEGER ;
   A, B, b: BodyRef ;
   found: BOOLEAN ;
BEGIN
   touch (t, ev.a, ev.b, ev.feature, ev.i, ev.j) ;
   cluster (ev) ;
   FOR k := 0 TO NRows - 1 DO
      rebase (ADR (Bodies^[Rows^[k].a]), t) ;
      rebase (ADR (Bodies^[Rows^[k].b]), t)
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
   FOR k := 0 TO NRows - 1 DO
      WITH Rows^[k] DO
         A := ADR (Bodies^[a]) ;
         B := ADR (Bodies^[b]) ;
         contact_frame (t, feature, A, B, i, j, cx, cy, nx, ny) ;
         INC (Stats.collisions) ;
         EmitContact ("collision", t, a, b, feature, i, j, cx, cy, nx, ny, 0.0) ;
         AddContact (t, a, b, feature, i, j, cx, cy, nx, ny, 0.0, FALSE)
      END
   END ;
   FOR k := 0 TO NMovers - 1 DO
      m := Movers^[k].idx ;
      b := ADR (Bodies^[m]) ;
      IF NOT b^.asleep THEN
         g := -1 ;
         IF (b^.sup >= 0) AND Bodies^[b^.sup].fixed THEN
            g := b^.sup
         ELSE
            q := 0 ;
            WHILE (g < 0) AND (q < NRows) DO
               o := -1 ;
               IF Rows^[q].a = m THEN o := Rows^[q].b ELSIF Rows^[q].b = m THEN o := Rows^[q].a END ;
               IF (o >= 0) AND (Bodies^[o].fixed OR Bodies^[o].asleep) THEN g := o END ;
               INC (q)
            END ;
            q := 0 ;
            WHILE (g < 0) AND (q < NRows) DO
               IF Rows^[q].a = m THEN g := Rows^[q].b ELSIF Rows^[q].b = m THEN g := Rows^[q].a END ;
               INC (q)
            END
         END ;
         AddJammed (t, m) ;
         handle_sleep (b, ADR (Bodies^[g]), t)
      END
   END
END jam ;


PROCEDURE handle_cluster (t: REAL; ev: CollisionEvent) ;
VAR
   k, m, s, g, n0, nw: INTEGER ;
   A, B, b: BodyRef ;
   grow: BOOLEAN ;
BEGIN
   IF jam_count (t, ev) >= ClusterRepeats + ClusterJam THEN
      jam (t, ev) ;
      RETURN
   END ;
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


BEGIN
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
   CapFinished := 0
END SimCluster.
