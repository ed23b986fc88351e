MODULE SimMain ;

(* The batch simulator (docs/simulator.md): reads a compiled scene on
   standard input and writes the flat trace on standard output; a thin
   user of the live world SimLive.  On a stuck or bad scene it writes
   "X message" and ends with status 1.

   sim --step DT [--live] drives the world in steps instead
   (docs/engine-api.md, "Checking a port"): Advance (k DT) for k = 1, 2, ...
   while k DT < end, then Finish; after each advance it writes on standard
   error "P T BODY PX PY VX VY ANGLE OMEGA" (States of every body at T,
   each checked against State) and
   "C T COUNT" (the contacts that advance reported), numbers as "%.17g".
   With --live, the scene's input lines are taken out (the world is made
   from the text with "inputs 0") and each, in order, is made live: before
   the step to k DT, every input at a time T <= k DT (after the last step:
   every one left) is applied by Advance (T) and the operation of its MODE;
   a refused teleport is an error. *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM UnixArgs IMPORT ArgC, ArgV ;
FROM CMath IMPORT getchar ;
FROM SimC IMPORT strtod, snprintf, write, exit, realloc ;
FROM SimLive IMPORT Contact, New, FromStdin, Run, Advance, State, States, Finish, EndTime, BodyCount, Error,
                    SetVelocity, AddVelocity, ApplyImpulse, Teleport, RemoveBody ;
FROM SimOut IMPORT SetOn, Str, Ln, Fail, FailMsg ;

CONST
   ProbeSize = 65536 ;
   MaxProbed = 4096 ;           (* bodies whose States a --step run checks *)
   MaxText = 1073741824 ;       (* bound of the array type only: storage grows *)

TYPE
   CharPtr = POINTER TO ARRAY [0..255] OF CHAR ;
   ArgArray = POINTER TO ARRAY [0..255] OF CharPtr ;
   Text = POINTER TO ARRAY [0..MaxText] OF CHAR ;     (* the text and its 0C *)
   LiveInput = RECORD
      t: REAL ;
      body, mode: INTEGER ;
      x, y: REAL ;
   END ;
   LiveInputs = POINTER TO ARRAY [0..16777215] OF LiveInput ;

VAR
   probe: ARRAY [0..ProbeSize - 1] OF CHAR ;   (* standard error's buffer *)
   ppos: INTEGER ;
   counting: BOOLEAN ;          (* the contacts reported are the step's *)
   count: INTEGER ;             (* contacts reported by the last step's advance *)
   lastT, stepT: REAL ;         (* the last contact's time, the step's *)
   text: Text ;                 (* the scene (--live) *)
   live: LiveInputs ;           (* its inputs (--live) *)
   nLive: INTEGER ;
   sx, sy, svx, svy, sang, som: ARRAY [0..MaxProbed - 1] OF REAL ;   (* States of a step *)


(* Argument k (up to HIGH (s) characters). *)
PROCEDURE Arg (k: CARDINAL; VAR s: ARRAY OF CHAR) ;
VAR
   a: ArgArray ;
   n: CARDINAL ;
BEGIN
   a := ArgV ;
   n := 0 ;
   WHILE (n < HIGH (s)) AND (n < 255) AND (a^[k]^[n] # 0C) DO
      s[n] := a^[k]^[n] ;
      INC (n)
   END ;
   s[n] := 0C
END Arg ;


PROCEDURE Same (a, b: ARRAY OF CHAR) : BOOLEAN ;
VAR
   k: CARDINAL ;
BEGIN
   k := 0 ;
   WHILE (k <= HIGH (a)) AND (k <= HIGH (b)) AND (a[k] = b[k]) AND (a[k] # 0C) DO INC (k) END ;
   RETURN ((k > HIGH (a)) OR (a[k] = 0C)) AND ((k > HIGH (b)) OR (b[k] = 0C))
END Same ;


PROCEDURE ProbeFlush ;
BEGIN
   IF (ppos > 0) AND (write (2, ADR (probe), VAL (LONGCARD, ppos)) # VAL (LONGINT, ppos)) THEN END ;
   ppos := 0
END ProbeFlush ;


(* The probe's buffered lines out to stderr, then the X line of msg and exit
   1: a run that stops writes every state line it made before its X line,
   as the other ports do. *)
PROCEDURE ProbeFail (msg: ARRAY OF CHAR) ;
BEGIN
   ProbeFlush ;
   FailMsg (msg)
END ProbeFail ;


(* Appends " " and x as "%.17g" writes it (first: no space). *)
PROCEDURE ProbeReal (x: REAL; first: BOOLEAN) ;
VAR
   n: INTEGER ;
BEGIN
   IF ppos > ProbeSize - 64 THEN ProbeFlush END ;
   IF NOT first THEN
      probe[ppos] := ' ' ;
      INC (ppos)
   END ;
   n := snprintf (ADR (probe[ppos]), 40, "%.17g", x) ;
   IF n > 0 THEN ppos := ppos + n END
END ProbeReal ;


PROCEDURE ProbeInt (v: INTEGER) ;
VAR
   n: INTEGER ;
BEGIN
   IF ppos > ProbeSize - 64 THEN ProbeFlush END ;
   n := snprintf (ADR (probe[ppos]), 40, " %d", v) ;
   IF n > 0 THEN ppos := ppos + n END
END ProbeInt ;


PROCEDURE ProbeLine (c: CHAR; t: REAL) ;
BEGIN
   IF ppos > ProbeSize - 64 THEN ProbeFlush END ;
   probe[ppos] := c ;
   probe[ppos + 1] := ' ' ;
   ppos := ppos + 2 ;
   ProbeReal (t, TRUE)
END ProbeLine ;


PROCEDURE ProbeLn ;
BEGIN
   IF ppos > ProbeSize - 64 THEN ProbeFlush END ;
   probe[ppos] := 12C ;
   INC (ppos)
END ProbeLn ;


(* Counts a reported contact of a step; one later than the step, or out of
   time order, is a bug of the world (checked: the probe's count becomes -1). *)
PROCEDURE Counted (c: Contact) ;
BEGIN
   IF NOT counting THEN RETURN END ;
   IF (count >= 0) AND (c.t >= lastT) AND (c.t <= stepT) THEN
      INC (count) ;
      lastT := c.t
   ELSE
      count := -1
   END
END Counted ;


(* The live input k: Advance to its time, then its operation. *)
PROCEDURE ApplyLive (k: INTEGER) : BOOLEAN ;
VAR
   ok, moved: BOOLEAN ;
   m: ARRAY [0..127] OF CHAR ;
BEGIN
   counting := FALSE ;
   IF NOT Advance (live^[k].t, Counted) THEN RETURN FALSE END ;
   moved := TRUE ;
   CASE live^[k].mode OF
      0: ok := SetVelocity (live^[k].body, live^[k].x, live^[k].y)
    | 1: ok := AddVelocity (live^[k].body, live^[k].x, live^[k].y)
    | 2: ok := ApplyImpulse (live^[k].body, live^[k].x, live^[k].y)
    | 3: ok := Teleport (live^[k].body, live^[k].x, live^[k].y, moved)
    | 4: ok := RemoveBody (live^[k].body)
   ELSE
      ProbeFail ("live input: unknown mode")
   END ;
   IF ok AND NOT moved THEN
      m[0] := 0C ;
      IF snprintf (ADR (m), 128, "live input %d: teleport refused (the body would overlap another)", k) > 0 THEN END ;
      ProbeFail (m)
   END ;
   RETURN ok
END ApplyLive ;


(* The world in steps of dt, probed after each (the ports' check), with the
   live inputs (nLive of them) made at their times. *)
PROCEDURE Stepped (dt: REAL) : BOOLEAN ;
VAR
   k: CARDINAL ;
   b, nxt: INTEGER ;
   t, px, py, vx, vy, ang, om: REAL ;
BEGIN
   lastT := 0.0 ;
   nxt := 0 ;
   k := 1 ;
   LOOP
      t := VAL (REAL, k) * dt ;
      WHILE (nxt < nLive) AND ((NOT (t < EndTime ())) OR (live^[nxt].t <= t)) DO
         IF NOT ApplyLive (nxt) THEN RETURN FALSE END ;
         INC (nxt)
      END ;
      IF NOT (t < EndTime ()) THEN EXIT END ;
      count := 0 ;
      stepT := t ;
      counting := TRUE ;
      IF NOT Advance (t, Counted) THEN RETURN FALSE END ;
      IF BodyCount () > MaxProbed THEN ProbeFail ("--step: more bodies than the probe's States arrays hold") END ;
      IF NOT States (t, sx, sy, svx, svy, sang, som) THEN RETURN FALSE END ;
      FOR b := 0 TO BodyCount () - 1 DO
         IF NOT State (b, t, px, py, vx, vy, ang, om) THEN RETURN FALSE END ;
         IF (px # sx[b]) OR (py # sy[b]) OR (vx # svx[b]) OR (vy # svy[b]) OR (ang # sang[b]) OR (om # som[b]) THEN
            ProbeFail ("--step: States gives a body another state than State")
         END ;
         ProbeLine ('P', t) ;
         ProbeInt (b) ;
         ProbeReal (px, FALSE) ;
         ProbeReal (py, FALSE) ;
         ProbeReal (vx, FALSE) ;
         ProbeReal (vy, FALSE) ;
         ProbeReal (ang, FALSE) ;
         ProbeReal (om, FALSE) ;
         ProbeLn
      END ;
      ProbeLine ('C', t) ;
      ProbeInt (count) ;
      ProbeLn ;
      INC (k)
   END ;
   counting := FALSE ;
   RETURN Finish (Counted)
END Stepped ;


(* Standard input into text (0C-terminated); a text longer than MaxText
   bytes is refused as the scene's check refuses it (docs/simulator.md,
   "Flat scene checks", rule 1), after reading one byte more. *)
PROCEDURE ReadAll ;
VAR
   n, cap, ch: INTEGER ;
BEGIN
   n := 0 ;
   cap := 0 ;
   text := NIL ;
   REPEAT
      IF n + 1 >= cap THEN
         IF cap = 0 THEN
            cap := 65536
         ELSIF cap > MaxText DIV 2 THEN
            cap := MaxText + 1
         ELSE
            cap := 2 * cap
         END ;
         text := realloc (text, VAL (LONGCARD, cap)) ;
         IF text = NIL THEN ProbeFail ("out of memory") END
      END ;
      ch := getchar () ;
      IF ch >= 0 THEN
         IF n = MaxText THEN ProbeFail ("scene: longer than 1073741824 bytes") END ;
         text^[n] := CHR (ch) ;
         INC (n)
      END
   UNTIL ch < 0 ;
   text^[n] := 0C
END ReadAll ;


(* The next whitespace-delimited token of text from pos into tok. *)
PROCEDURE Token (VAR pos: INTEGER; VAR tok: ARRAY OF CHAR) ;
VAR
   k: CARDINAL ;
BEGIN
   WHILE (text^[pos] # 0C) AND (text^[pos] <= ' ') DO INC (pos) END ;
   k := 0 ;
   WHILE (text^[pos] > ' ') AND (k < HIGH (tok)) DO
      tok[k] := text^[pos] ;
      INC (k) ;
      INC (pos)
   END ;
   tok[k] := 0C
END Token ;


PROCEDURE TokenReal (VAR pos: INTEGER) : REAL ;
VAR
   tok: ARRAY [0..255] OF CHAR ;
   endp: ADDRESS ;
BEGIN
   Token (pos, tok) ;
   endp := NIL ;
   RETURN strtod (tok, endp)
END TokenReal ;


PROCEDURE TokenInt (VAR pos: INTEGER) : INTEGER ;
BEGIN
   RETURN VAL (INTEGER, TokenReal (pos))
END TokenInt ;


(* Takes the input lines out of text ("inputs 0" instead) into live. *)
PROCEDURE SplitInputs ;
VAR
   pos, cut, k: INTEGER ;
   tok: ARRAY [0..255] OF CHAR ;
BEGIN
   pos := 0 ;
   LOOP
      IF text^[pos] = 0C THEN ProbeFail ("scene: expected 'inputs'") END ;
      IF (text^[pos] = 12C) AND (text^[pos + 1] = 'i') AND (text^[pos + 2] = 'n') AND (text^[pos + 3] = 'p')
         AND (text^[pos + 4] = 'u') AND (text^[pos + 5] = 't') AND (text^[pos + 6] = 's')
         AND (text^[pos + 7] = ' ') THEN
         EXIT
      END ;
      INC (pos)
   END ;
   cut := pos + 1 ;
   pos := pos + 8 ;
   nLive := TokenInt (pos) ;
   live := realloc (NIL, VAL (LONGCARD, nLive + 1) * VAL (LONGCARD, SIZE (LiveInput))) ;
   IF live = NIL THEN ProbeFail ("out of memory") END ;
   FOR k := 0 TO nLive - 1 DO
      Token (pos, tok) ;          (* "input" *)
      live^[k].t := TokenReal (pos) ;
      live^[k].body := TokenInt (pos) ;
      live^[k].mode := TokenInt (pos) ;
      live^[k].x := TokenReal (pos) ;
      live^[k].y := TokenReal (pos)
   END ;
   tok := "inputs 0" ;
   FOR k := 0 TO 7 DO text^[cut + k] := tok[k] END ;
   text^[cut + 8] := 12C ;
   text^[cut + 9] := 'e' ;
   text^[cut + 10] := 'n' ;
   text^[cut + 11] := 'd' ;
   text^[cut + 12] := 12C ;
   text^[cut + 13] := 0C
END SplitInputs ;


VAR
   msg: ARRAY [0..511] OF CHAR ;
   a: ARRAY [0..255] OF CHAR ;
   endp: ADDRESS ;
   dt: REAL ;
   ok, isLive, usage: BOOLEAN ;
   k: CARDINAL ;
   nargs: INTEGER ;
BEGIN
   ppos := 0 ;
   nLive := 0 ;
   counting := FALSE ;
   dt := 0.0 ;
   isLive := FALSE ;
   usage := FALSE ;
   nargs := 0 ;
   k := 1 ;
   WHILE k < ArgC DO
      Arg (k, a) ;
      IF Same (a, "--live") THEN
         isLive := TRUE
      ELSIF Same (a, "--step") AND (k + 1 < ArgC) AND (nargs = 0) THEN
         INC (k) ;
         Arg (k, a) ;
         endp := NIL ;
         dt := strtod (a, endp) ;
         IF NOT (dt > 0.0) THEN usage := TRUE END ;
         INC (nargs)
      ELSE
         usage := TRUE
      END ;
      INC (k)
   END ;
   IF usage OR (isLive AND (nargs = 0)) THEN
      msg := "usage: sim [--step DT [--live]] < scene (DT > 0)" ;
      msg[48] := 12C ;
      IF write (2, ADR (msg), 49) # 49 THEN END ;
      exit (2)
   END ;
   IF isLive THEN
      ReadAll ;
      SplitInputs ;
      ok := New (text^, TRUE) AND Stepped (dt)
   ELSIF dt > 0.0 THEN
      ok := FromStdin (TRUE) AND Stepped (dt)
   ELSE
      ok := FromStdin (TRUE) AND Run ()
   END ;
   ProbeFlush ;
   IF NOT ok THEN
      Error (msg) ;
      SetOn (TRUE) ;
      Str ("X ") ;
      Str (msg) ;
      Ln ;
      Fail
   END
END SimMain.
