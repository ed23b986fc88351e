MODULE SimMain ;

(* The batch simulator (docs/simulator.md): reads a compiled scene on
   standard input and writes the flat trace on standard output; a thin
   user of the live world SimWorld.  On a stuck or bad scene it writes
   "X message" and ends with status 1.

   sim --step DT drives the world in steps instead (docs/engine-api.md,
   "Checking a port"): Advance (k DT) for k = 1, 2, ... while k DT < end,
   then Finish; after each advance it writes on standard error
   "P T BODY PX PY VX VY ANGLE OMEGA" (State of every body at T) and
   "C T COUNT" (the contacts that advance reported), numbers as "%.17g". *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM UnixArgs IMPORT ArgC, ArgV ;
FROM SimC IMPORT strtod, snprintf, write, exit ;
FROM SimWorld IMPORT Contact, FromStdin, Run, Advance, State, Finish, EndTime, BodyCount, Error ;
FROM SimOut IMPORT SetOn, Str, Ln, Fail ;

CONST
   ProbeSize = 65536 ;

TYPE
   CharPtr = POINTER TO ARRAY [0..255] OF CHAR ;
   ArgArray = POINTER TO ARRAY [0..255] OF CharPtr ;

VAR
   probe: ARRAY [0..ProbeSize - 1] OF CHAR ;   (* standard error's buffer *)
   ppos: INTEGER ;
   count: INTEGER ;             (* contacts reported by the last advance *)
   lastT, stepT: REAL ;         (* the last contact's time, the step's *)


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


PROCEDURE ProbeFlush ;
BEGIN
   IF (ppos > 0) AND (write (2, ADR (probe), VAL (LONGCARD, ppos)) # VAL (LONGINT, ppos)) THEN END ;
   ppos := 0
END ProbeFlush ;


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


(* Counts a reported contact; one later than the step, or out of time
   order, is a bug of the world (checked, the probe's count becomes -1). *)
PROCEDURE Counted (c: Contact) ;
BEGIN
   IF (count >= 0) AND (c.t >= lastT) AND (c.t <= stepT) THEN
      INC (count) ;
      lastT := c.t
   ELSE
      count := -1
   END
END Counted ;


(* The world in steps of dt, probed after each (the ports' check). *)
PROCEDURE Stepped (dt: REAL) : BOOLEAN ;
VAR
   k: CARDINAL ;
   b: INTEGER ;
   t, px, py, vx, vy, ang, om: REAL ;
BEGIN
   lastT := 0.0 ;
   k := 1 ;
   WHILE VAL (REAL, k) * dt < EndTime () DO
      t := VAL (REAL, k) * dt ;
      count := 0 ;
      stepT := t ;
      IF NOT Advance (t, Counted) THEN RETURN FALSE END ;
      FOR b := 0 TO BodyCount () - 1 DO
         IF NOT State (b, t, px, py, vx, vy, ang, om) THEN RETURN FALSE END ;
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
   count := 0 ;
   stepT := EndTime () ;
   RETURN Finish (Counted)
END Stepped ;


VAR
   msg: ARRAY [0..511] OF CHAR ;
   a: ARRAY [0..255] OF CHAR ;
   endp: ADDRESS ;
   dt: REAL ;
   ok: BOOLEAN ;
BEGIN
   ppos := 0 ;
   dt := 0.0 ;
   IF ArgC = 3 THEN
      Arg (1, a) ;
      IF (a[0] = '-') AND (a[1] = '-') AND (a[2] = 's') AND (a[3] = 't') AND (a[4] = 'e') AND (a[5] = 'p')
         AND (a[6] = 0C) THEN
         Arg (2, a) ;
         endp := NIL ;
         dt := strtod (a, endp) ;
         IF NOT (dt > 0.0) THEN dt := -1.0 END
      ELSE
         dt := -1.0
      END
   ELSIF ArgC # 1 THEN
      dt := -1.0
   END ;
   IF dt < 0.0 THEN
      msg := "usage: sim [--step DT] < scene (DT > 0)" ;
      msg[39] := 12C ;
      IF write (2, ADR (msg), 40) # 40 THEN END ;
      exit (2)
   END ;
   IF dt > 0.0 THEN
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
