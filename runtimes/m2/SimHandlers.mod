IMPLEMENTATION MODULE SimHandlers ;

(* The handlers: a transcription of the Python reference's handle_input,
   handle_collision, handle_support, handle_stop, handle_leave,
   handle_cell, handle_horizon, handle_frame, leave, release,
   predict_released, handle_sleep, handle_wake, predict_woken, remove,
   drive, wake_touching, start, dispatch and process, with the same IEEE
   double operations in the same order. *)

FROM SYSTEM IMPORT ADR ;
FROM SimScene IMPORT Bodies, BodyRef, RestSlots, EndT, FrameDt, GridNX, GridNY, Input, Inputs, LENGTH_MAX, MaxEvents, MaxSame,
                     NBodies, NInputs, Tol ;
FROM SimQueue IMPORT CellEvent, Clear, CollisionEvent, Event, FrameEvent, HorizonEvent, InputEvent, KCell,
                     KCollision, KFrame, KHorizon, KInput, KLeave, KStop, LeaveEvent, Pop, StopEvent, Top ;
FROM SimGrid IMPORT CellAdd, CellOf, CellRemove, Cells, InitGrid, large_near, LargeAdd, Mark, Max, Min, Near,
                    place_large, SortNear, unplace_large, walls_in ;
FROM SimOut IMPORT EmitContact, EmitSupportEnd, Int, Ln, Real, SpReal, Stat, Str ;
FROM SimWorld IMPORT AddContact, AddLeft, AddVelocityMode, Append, AppendInt, AppendReal, CcCounts,
                     EmitState, Failed, Fails, Handled, ImpulseMode, JammedT, NJammed, is_stale, LastT, LeftBody, LeftSkip, MsgLen,
                     NAdded, NCc, NContacts, NLeft, NPe, PeCounts, push, push_frame, RemoveMode, Same, Seq,
                     SetVelocityMode, Stats, TeleportMode, Unpaid, WorldT ;
FROM SimMotion IMPORT rebase, StateAt ;
FROM SimPredict IMPORT ClearCounts, PredictBody, PredictCells, PredictLarge, PredictPair, ScheduleCell ;
FROM SimContact IMPORT contact_frame, contact_impulse, held, held_impulse, normal_speed, sleeper_impulse ;
FROM SimSupport IMPORT base_holds, can_carry, can_ride, can_support, end_support, enter_carried, enter_support,
                       slide_accel, static ;
FROM SimSleep IMPORT at_rest, can_sleep, can_sleep_many, holding, jolted, note_rest, rest_ftol, slow_touch ;
FROM SimOverlap IMPORT overlapping ;
FROM SimCluster IMPORT handle_cluster, NTouched, repeated, touch, TouchedT ;

CONST
   Waking = -2 ;               (* island of the sleepers handle_wake is waking *)


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
   AddLeft (A^.idx, skip) ;
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


(* A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0) in
   G's island, or in a new one numbered A's index when G is fixed.  Its
   awake neighbours are predicted against it again. *)
PROCEDURE handle_sleep (A, G: BodyRef; t: REAL) ;
VAR
   n0: INTEGER ;
BEGIN
   INC (Stats.sleeps) ;
   IF (A^.sup >= 0) AND Bodies^[A^.sup].fixed THEN A^.rest := A^.sup ELSE A^.rest := -1 END ;
   IF A^.sup >= 0 THEN end_support (A) END ;
   A^.vx := 0.0 ;
   A^.vy := 0.0 ;
   A^.om := 0.0 ;
   A^.ax := 0.0 ;
   A^.ay := 0.0 ;
   A^.asleep := TRUE ;
   IF G^.asleep THEN A^.island := G^.island ELSE A^.island := A^.idx END ;
   A^.on[0] := G^.idx ;
   A^.non := 1 ;
   INC (A^.stamp) ;
   EmitSupportEnd ("sleep", t, A^.idx, G^.idx, A^.island) ;
   EmitState (A) ;
   n0 := NLeft ;
   release (A, t) ;
   PredictBody (A, t, -1) ;
   predict_released (n0, t)
END handle_sleep ;


(* A falls asleep on G (handle_sleep); then the body of each noted contact
   that still holds (in slot order) is added to what A rests on, so a jolt
   on any of them wakes A. *)
PROCEDURE handle_sleep_many (A, G: BodyRef; ev: CollisionEvent; t: REAL) ;
VAR
   held, others: ARRAY [0..RestSlots - 1] OF INTEGER ;
   nh, h: INTEGER ;
   fa, ftol: REAL ;
BEGIN
   ftol := rest_ftol (A, fa) ;
   nh := holding (A, ev, ftol, held) ;
   FOR h := 0 TO nh - 1 DO others[h] := A^.rc[held[h]].other1 - 1 END ;
   handle_sleep (A, G, t) ;
   FOR h := 0 TO nh - 1 DO
      A^.on[A^.non] := others[h] ;
      INC (A^.non)
   END
END handle_sleep_many ;


(* Sleeper S wakes at t, and with it every sleeper that rests on a woken
   body (the upward closure, marked island Waking): each (by index) gets its
   free acceleration back, then fresh predictions (a pair of woken bodies
   once). *)
PROCEDURE handle_wake (S: BodyRef; t: REAL) ;
CONST
   island = Waking ;
VAR
   i, g, n0: INTEGER ;
   grown: BOOLEAN ;
   b: BodyRef ;
BEGIN
   INC (Stats.wakes) ;
   Str ("E wake ") ;
   Real (t) ;
   Str (" ") ; Int (S^.idx) ;
   Str (" -1 -1 -1 ") ; Int (S^.island) ;
   Str (" 0 0 0 0 0") ;
   Ln ;
   S^.island := island ;
   grown := TRUE ;
   WHILE grown DO
      grown := FALSE ;
      FOR i := 0 TO NBodies - 1 DO
         b := ADR (Bodies^[i]) ;
         IF b^.asleep AND (b^.island # island) THEN
            g := 0 ;
            WHILE g < b^.non DO
               IF Bodies^[b^.on[g]].island = island THEN
                  b^.island := island ;
                  grown := TRUE ;
                  g := b^.non
               ELSE
                  INC (g)
               END
            END
         END
      END
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.asleep AND (b^.island = island) THEN
         rebase (b, t) ;
         b^.asleep := FALSE ;
         b^.rest := -1 ;
         b^.ax := b^.fax ;
         b^.ay := b^.fay ;
         INC (b^.stamp) ;
         EmitState (b)
      END
   END ;
   n0 := NLeft ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.island = island THEN release (b, t) END     (* bodies sliding on a woken body leave it: it may move *)
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF b^.island = island THEN predict_woken (b, t, island) END
   END ;
   predict_released (n0, t) ;
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


PROCEDURE handle_collision (t: REAL; ev: CollisionEvent) ;
VAR
   A, B: BodyRef ;
   cx, cy, nx, ny, vn, imp: REAL ;
   isheld, pressA, pressB: BOOLEAN ;
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
   IF can_sleep_many (A, B, ev, cx, cy, nx, ny, vn) THEN
      handle_sleep_many (A, B, ev, t) ;
      RETURN
   END ;
   IF can_sleep_many (B, A, ev, cx, cy, nx, ny, vn) THEN
      handle_sleep_many (B, A, ev, t) ;
      RETURN
   END ;
   IF can_ride (A, B, ev.feature, ev.i, ev.j, vn) THEN
      handle_support (t, ev, A, B, cx, cy, nx, ny, vn) ;
      RETURN
   END ;
   pressA := slow_touch (A, B, ev, nx, ny, vn) ;
   pressB := slow_touch (B, A, ev, nx, ny, vn) ;
   INC (Stats.collisions) ;
   (* a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
      on it); a gentle touch leaves it asleep, a real impulse wakes it and what rests on it;
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
   IF pressA AND NOT A^.asleep THEN note_rest (A, B, ev, cx, cy, nx, ny) END ;
   IF pressB AND NOT B^.asleep THEN note_rest (B, A, ev, cx, cy, nx, ny) END ;
   (* an impulse changes the motion of what it hit: what they carried leaves
      (a sleeper a gentle touch left asleep has not moved: what slides on it stays) *)
   n0 := NLeft ;
   IF imp # 0.0 THEN
      IF (NOT A^.fixed) AND (NOT A^.asleep) THEN release (A, t) END ;
      IF (NOT B^.fixed) AND (NOT B^.asleep) THEN release (B, t) END
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


(* A collision that ends in support (called by handle_collision). *)
PROCEDURE handle_support (t: REAL; ev: CollisionEvent; A, B: BodyRef; cx, cy, nx, ny, vn: REAL) ;
VAR
   imp: REAL ;
   n0: INTEGER ;
BEGIN
   INC (Stats.supports) ;
   imp := (-vn) / A^.invM ;
   IF B^.fixed OR B^.asleep THEN enter_support (A, B, ev.j) ELSE enter_carried (A, B, ev.j) END ;
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
   IF B^.asleep AND (NOT base_holds (B, 0.0, 0.0)) THEN
      (* sliding back, its friction turned: the sleeping base no longer holds it *)
      n0 := NLeft ;
      leave (A, t, -1) ;
      predict_released (n0, t) ;
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


(* Input k (not a removal) on the body, based at t: the run fails (TRUE)
   when the body's motion after it would reach more than 2 LENGTH_MAX from
   the origin by the end (the live inputs' rule, from the state at t, left
   to right in doubles; a velocity or position that is not finite fails it
   too). *)
PROCEDURE TooFar (b: BodyRef; k: INTEGER; t: REAL; inp: Input) : BOOLEAN ;
VAR
   px, py, vx, vy, reach: REAL ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   px := b^.px ; py := b^.py ; vx := b^.vx ; vy := b^.vy ;
   IF inp.mode = SetVelocityMode THEN
      vx := inp.vx ; vy := inp.vy
   ELSIF inp.mode = AddVelocityMode THEN
      vx := b^.vx + inp.vx ; vy := b^.vy + inp.vy
   ELSIF inp.mode = ImpulseMode THEN
      vx := b^.vx + inp.vx * b^.invM ; vy := b^.vy + inp.vy * b^.invM
   ELSE
      px := inp.vx ; py := inp.vy
   END ;
   reach := (ABS (px) + ABS (py)) + (ABS (vx) + ABS (vy)) * EndT
            + (ABS (b^.ax) + ABS (b^.ay)) * EndT * EndT / 2.0 + b^.bound ;
   IF reach <= 2.0 * LENGTH_MAX THEN RETURN FALSE END ;
   m := "input " ;
   AppendInt (m, k) ;
   Append (m, ": body ") ;
   AppendInt (m, b^.idx) ;
   Append (m, " at t = ") ;
   AppendReal (m, t) ;
   Append (m, ": reaches more than 2e150 m from the origin by the end") ;
   Fails (m) ;
   RETURN TRUE
END TooFar ;


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
   IF (inp.mode # RemoveMode) AND TooFar (b, ev.k, t, inp) THEN RETURN END ;
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
   PredictBody), the bodies that left against the others; last the sleepers
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


(* The sleepers whose bounding circles reach the body's (within the
   tolerance; a body removed, or a fixed one whose velocity an input set)
   wake, each with what rests on it: it may have held them (by index; one
   woken with an earlier one is awake already). *)
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
   ClearCounts ;
   WorldT := 0.0 ;
   LastT := -1.0 ;
   Same := 0 ;
   Handled := 0 ;
   JammedT := -1.0 ;
   NJammed := 0 ;
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


(* Handles one event taken from the queue: dropped when stale, counted
   against max_events (every kind: cell crossings and horizons too) and at
   its instant (max_same_time: more is "stuck"), then its kind's handler. *)
PROCEDURE dispatch (ev: Event) ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF is_stale (ev) THEN
      INC (Stats.stale) ;
      RETURN
   END ;
   INC (Handled) ;
   IF Handled > MaxEvents THEN
      m := "more than " ;
      AppendInt (m, MaxEvents) ;
      Append (m, " events (collisions, inputs, frames, cell crossings, horizons) at t = ") ;
      AppendReal (m, ev.t) ;
      Append (m, ": the run was stopped; raise max_events in the scene or --max-events, or shorten end_time") ;
      Fails (m) ;
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
   FOR k := 0 TO NCc - 1 DO
      Str ("V circle_circle ") ;
      Int (k) ;
      Str (" ") ;
      Int (CcCounts^[k]) ;
      Ln
   END ;
   FOR k := 0 TO NPe - 1 DO
      Str ("V point_edge ") ;
      Int (k) ;
      Str (" ") ;
      Int (PeCounts^[k]) ;
      Ln
   END
END WriteFinal ;


END SimHandlers.
