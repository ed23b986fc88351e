IMPLEMENTATION MODULE SimLive ;

(* The live world's API (SimLive.def, docs/engine-api.md) over the
   world's state (SimWorld, SimScene) and its handlers (SimHandlers). *)

FROM SYSTEM IMPORT ADR, CAST ;
FROM SimScene IMPORT AddInput, Bodies, BodyRef, CellH, CellW, EndT, Inputs, LENGTH_MAX, MAX_BODIES, NBodies, NInputs,
                     NVerts, ReadBodyText, ReadError, ReadFile, ReadStdin, ReadText ;
FROM SimQueue IMPORT Event, KInput, Pop, Top ;
FROM SimGrid IMPORT CellAdd, CellOf, place_large ;
FROM SimOut IMPORT Flush, Int, Ln, Real, SetOn, Str ;
FROM SimWorld IMPORT AddVelocityMode, Append, AppendInt, AppendReal, Contacts, EmitState, ErrMsg, Failed,
                     ImpulseMode, Inf, is_stale, Loaded, MsgLen, NAdded, NContacts, NLeft, push, RemoveMode,
                     SetVelocityMode, Stats, TeleportMode, WorldT ;
FROM SimMotion IMPORT StateAt ;
FROM SimPredict IMPORT PredictBody, PredictPair ;
FROM SimOverlap IMPORT overlapping ;
FROM SimHandlers IMPORT dispatch, process, start, WriteFinal ;

CONST
   SignBit = VAL (LONGCARD, 9223372036854775808) ;  (* 2^63: a REAL's sign bit *)
   InfBits = VAL (LONGCARD, 9218868437227405312) ;  (* the bits of infinity; NaNs lie above *)

VAR
   Reporting: BOOLEAN ;        (* a ContactProc is being called *)
   Finished: BOOLEAN ;         (* Finish or Run was called: no more inputs or bodies *)


(* x is neither infinite nor a NaN (from its bits: no comparison of a NaN). *)
PROCEDURE Finite (x: REAL) : BOOLEAN ;
BEGIN
   RETURN CAST (LONGCARD, x) MOD SignBit < InfBits
END Finite ;


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


(* A world from the scene just read (ok), or the reading's failure. *)
PROCEDURE Begin (ok, trace: BOOLEAN) : BOOLEAN ;
BEGIN
   Loaded := FALSE ;
   Failed := FALSE ;
   Reporting := FALSE ;
   Finished := FALSE ;
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
   IF NOT BodyOk (body, FALSE) THEN RETURN FALSE END ;
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


(* FALSE (refused) when k is not a body of the world: a live input's
   words ("live input: body K does not exist") or State's ("no body K (the
   world has N)"), as the other engines say them. *)
PROCEDURE BodyOk (k: INTEGER; live: BOOLEAN) : BOOLEAN ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF (k >= 0) AND (k < NBodies) THEN RETURN TRUE END ;
   IF live THEN
      m := "live input: body " ;
      AppendInt (m, k) ;
      Append (m, " does not exist")
   ELSE
      m := "no body " ;
      AppendInt (m, k) ;
      Append (m, " (the world has ") ;
      AppendInt (m, NBodies) ;
      Append (m, ")")
   END ;
   RETURN Refuse (m)
END BodyOk ;


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


(* FALSE (refused) after Finish or Run. *)
PROCEDURE NotFinished () : BOOLEAN ;
BEGIN
   IF Finished THEN RETURN Refuse ("live input: the world is finished") END ;
   RETURN TRUE
END NotFinished ;


(* FALSE (refused) when body b (index body) was removed. *)
PROCEDURE NotGone (b: BodyRef; body: INTEGER) : BOOLEAN ;
VAR
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   IF NOT b^.gone THEN RETURN TRUE END ;
   m := "body " ;
   AppendInt (m, body) ;
   Append (m, " was removed") ;
   RETURN Refuse (m)
END NotGone ;


(* Refused after Finish, on a body that does not exist or was removed, one
   an input of this mode may not drive, or when the velocity or position
   it gives would not be finite (a teleport: beyond LENGTH_MAX); the
   scene's inputs at the world's time are handled before the result is
   computed from the body's velocity then. *)
PROCEDURE live_input (body, mode: INTEGER; x, y: REAL; VAR done: BOOLEAN) : BOOLEAN ;
VAR
   b: BodyRef ;
   ev: Event ;
   px, py, vx, vy, ang, rx, ry, reach: REAL ;
   m: ARRAY [0..MsgLen] OF CHAR ;
BEGIN
   done := FALSE ;
   IF (NOT Usable ()) OR (NOT NotFinished ()) OR (NOT BodyOk (body, TRUE)) THEN RETURN FALSE END ;
   b := ADR (Bodies^[body]) ;
   IF NOT NotGone (b, body) THEN RETURN FALSE END ;
   IF NOT drivable (b, mode) THEN
      m := "body " ;
      AppendInt (m, body) ;
      Append (m, " is fixed: inputs move movable bodies only (or set the velocity of a fixed polygon that does ") ;
      Append (m, "not turn, or remove a fixed body)") ;
      RETURN Refuse (m)
   END ;
   inputs_now ;
   IF Failed THEN RETURN FALSE END ;
   b := ADR (Bodies^[body]) ;
   IF NOT NotGone (b, body) THEN RETURN FALSE END ;
   StateAt (b, WorldT, px, py, vx, vy, ang) ;
   IF mode = SetVelocityMode THEN
      rx := x ; ry := y
   ELSIF mode = AddVelocityMode THEN
      rx := vx + x ; ry := vy + y
   ELSIF mode = ImpulseMode THEN
      rx := vx + x * b^.invM ; ry := vy + y * b^.invM
   ELSE
      rx := x ; ry := y
   END ;
   IF NOT (Finite (rx) AND Finite (ry)) THEN
      m := "live input: body " ;
      AppendInt (m, body) ;
      IF (mode = TeleportMode) OR (mode = RemoveMode) THEN
         Append (m, ": position would not be finite")
      ELSE
         Append (m, ": velocity would not be finite")
      END ;
      RETURN Refuse (m)
   END ;
   IF (mode = TeleportMode) AND NOT (ABS (x) + ABS (y) <= LENGTH_MAX) THEN
      m := "live input: body " ;
      AppendInt (m, body) ;
      Append (m, ": teleport beyond 1e150 m") ;
      RETURN Refuse (m)
   END ;
   (* the motion after the input stays within the scene's reach by the end (rule 8, left to right) *)
   IF mode = TeleportMode THEN
      px := x ; py := y ; rx := vx ; ry := vy
   END ;
   reach := (ABS (px) + ABS (py)) + (ABS (rx) + ABS (ry)) * EndT
            + (ABS (b^.ax) + ABS (b^.ay)) * EndT * EndT / 2.0 + b^.bound ;
   IF (mode # RemoveMode) AND NOT (reach <= 2.0 * LENGTH_MAX) THEN
      m := "live input: body " ;
      AppendInt (m, body) ;
      Append (m, ": reaches more than 2e150 m from the origin by the end") ;
      RETURN Refuse (m)
   END ;
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
   IF (NOT Usable ()) OR (NOT NotFinished ()) THEN RETURN FALSE END ;
   IF NBodies >= MAX_BODIES THEN        (* a scene's limit holds for a world too *)
      m := "add_body: the world has " ;
      AppendInt (m, NBodies) ;
      Append (m, " bodies (at most 1000000)") ;
      RETURN Refuse (m)
   END ;
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
   Finished := TRUE ;
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
   Finished := TRUE ;
   WriteFinal ;
   Flush ;
   NContacts := 0 ;
   RETURN TRUE
END Run ;


BEGIN
   Reporting := FALSE ;
   Finished := FALSE
END SimLive.
