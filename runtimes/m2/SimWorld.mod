IMPLEMENTATION MODULE SimWorld ;

(* The world's state (SimWorld.def) and the procedures that change it
   directly. *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM SimC IMPORT realloc, snprintf, strtod ;
FROM SimScene IMPORT Bodies, BodyRef, Grow ;
FROM SimQueue IMPORT Event, KCell, KCollision, KFrame, KHorizon, KLeave, KStop, Push ;
FROM SimOut IMPORT Int, Ln, SetOn, SpReal, Str ;
FROM SimLive IMPORT Contact ;

VAR
   CapContacts: INTEGER ;      (* Contacts' room *)
   CapLeft: INTEGER ;          (* LeftBody's and LeftSkip's room *)
   CapJammed: INTEGER ;        (* Jammed's room *)
   endp: ADDRESS ;


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


PROCEDURE AddLeft (i, skip: INTEGER) ;
BEGIN
   IF NLeft >= CapLeft THEN
      IF CapLeft = 0 THEN CapLeft := 16 ELSE CapLeft := 2 * CapLeft END ;
      LeftBody := Grow (LeftBody, CapLeft, SIZE (INTEGER)) ;
      LeftSkip := Grow (LeftSkip, CapLeft, SIZE (INTEGER))
   END ;
   LeftBody^[NLeft] := i ;
   LeftSkip^[NLeft] := skip ;
   INC (NLeft)
END AddLeft ;


PROCEDURE AddJammed (t: REAL; i: INTEGER) ;
BEGIN
   IF JammedT # t THEN
      JammedT := t ;
      NJammed := 0
   END ;
   IF NJammed >= CapJammed THEN
      IF CapJammed = 0 THEN CapJammed := 16 ELSE CapJammed := 2 * CapJammed END ;
      Jammed := Grow (Jammed, CapJammed, SIZE (INTEGER))
   END ;
   Jammed^[NJammed] := i ;
   INC (NJammed)
END AddJammed ;


PROCEDURE HeldNow (S: BodyRef) : BOOLEAN ;
VAR
   k: INTEGER ;
BEGIN
   IF JammedT # LastT THEN RETURN FALSE END ;
   FOR k := 0 TO NJammed - 1 DO
      IF Jammed^[k] = S^.idx THEN RETURN TRUE END
   END ;
   RETURN FALSE
END HeldNow ;


BEGIN
   Loaded := FALSE ;
   Failed := FALSE ;
   ErrMsg[0] := 0C ;
   WorldT := 0.0 ;
   Contacts := NIL ;
   NContacts := 0 ;
   CapContacts := 0 ;
   CcCounts := NIL ;
   PeCounts := NIL ;
   NCc := 0 ;
   NPe := 0 ;
   LeftBody := NIL ;
   LeftSkip := NIL ;
   NLeft := 0 ;
   CapLeft := 0 ;
   JammedT := -1.0 ;
   Jammed := NIL ;
   NJammed := 0 ;
   CapJammed := 0 ;
   endp := NIL ;
   Inf := strtod ("inf", endp)
END SimWorld.
