IMPLEMENTATION MODULE SimScene ;

(* Reading the flat scene: whitespace-separated tokens from a text in
   memory, a file or standard input, numbers through the C library's strtod (the scene's shortest round-trip
   decimals are read exactly), whole numbers digit by digit. *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM SimC IMPORT strtod, realloc, fopen, fdopen, fclose, fgetc ;
FROM SimOut IMPORT FailMsg ;

CONST
   TokLen = 255 ;

TYPE
   Token = ARRAY [0..TokLen] OF CHAR ;
   Chars = POINTER TO ARRAY [0..MAX (INTEGER)] OF CHAR ;

VAR
   Pending: INTEGER ;          (* a character read ahead, or -2 *)
   Tok: Token ;                (* the last token read *)
   Failed: BOOLEAN ;           (* the reading failed: Message says why *)
   What: ARRAY [0..15] OF CHAR ;   (* what is read, for the messages: "scene" or "add_body" *)
   Message: ARRAY [0..TokLen + 128] OF CHAR ;
   FromFile: BOOLEAN ;         (* the source: Src, else SrcText^[SrcPos .. SrcLen - 1] *)
   Src: ADDRESS ;              (* a C FILE * *)
   SrcText: Chars ;
   SrcLen, SrcPos: CARDINAL ;
   CapBodies, CapVerts, CapInputs: INTEGER ;   (* the arrays' room *)


PROCEDURE Grow (p: ADDRESS; count, size: INTEGER) : ADDRESS ;
VAR
   q: ADDRESS ;
BEGIN
   IF (count < 0) OR (count > MaxItems) THEN
      FailMsg ("scene: too many items") 
   END ;
   IF count = 0 THEN count := 1 END ;
   q := realloc (p, VAL (LONGCARD, count) * VAL (LONGCARD, size)) ;
   IF q = NIL THEN FailMsg ("out of memory") END ;
   RETURN q
END Grow ;


(* The first error of this reading: What, ": ", msg, then extra and "'"
   when extra is not empty. *)
PROCEDURE Error (msg, extra: ARRAY OF CHAR) ;
BEGIN
   IF Failed THEN RETURN END ;
   Failed := TRUE ;
   Message[0] := 0C ;
   Append (Message, What) ;
   Append (Message, ": ") ;
   Append (Message, msg) ;
   IF extra[0] # 0C THEN
      Append (Message, extra) ;
      Append (Message, "'")
   END
END Error ;


(* s with the decimal digits of v (and its sign) appended. *)
PROCEDURE AppendWhole (VAR s: ARRAY OF CHAR; v: INTEGER) ;
VAR
   d: ARRAY [0..23] OF CHAR ;
   r: ARRAY [0..23] OF CHAR ;
   n, k: CARDINAL ;
   neg: BOOLEAN ;
   u: LONGINT ;
BEGIN
   u := VAL (LONGINT, v) ;
   neg := u < 0 ;
   IF neg THEN u := -u END ;
   n := 0 ;
   REPEAT
      d[n] := CHR (ORD ('0') + VAL (CARDINAL, u MOD 10)) ;
      u := u DIV 10 ;
      INC (n)
   UNTIL u = 0 ;
   k := 0 ;
   IF neg THEN r[0] := '-' ; k := 1 END ;
   WHILE n > 0 DO
      DEC (n) ;
      r[k] := d[n] ;
      INC (k)
   END ;
   r[k] := 0C ;
   Append (s, r)
END AppendWhole ;


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


PROCEDURE NextChar () : INTEGER ;
VAR
   ch: INTEGER ;
BEGIN
   IF Pending # -2 THEN
      ch := Pending ;
      Pending := -2 ;
      RETURN ch
   END ;
   IF FromFile THEN
      RETURN fgetc (Src)
   ELSIF SrcPos >= SrcLen THEN
      RETURN -1
   END ;
   ch := ORD (SrcText^[SrcPos]) ;
   INC (SrcPos) ;
   IF ch = 0 THEN RETURN -1 END ;
   RETURN ch
END NextChar ;


(* The next whitespace-delimited token into Tok; its length (0 and an empty
   Tok after an error).  expect: the token wanted, for the message when the
   text ends early ("" for any). *)
PROCEDURE Word (expect: ARRAY OF CHAR) : INTEGER ;
VAR
   ch, k: INTEGER ;
   msg: ARRAY [0..TokLen + 64] OF CHAR ;
BEGIN
   Tok[0] := 0C ;
   IF Failed THEN RETURN 0 END ;
   REPEAT
      ch := NextChar ()
   UNTIL (ch < 0) OR (ch > 32) ;
   IF ch < 0 THEN
      IF expect[0] = 0C THEN
         Error ("ends early", "")
      ELSE
         msg := "ends early (expected '" ;
         Append (msg, expect) ;
         Append (msg, "')") ;
         Error (msg, "")
      END ;
      RETURN 0
   END ;
   k := 0 ;
   WHILE ch > 32 DO
      IF k >= TokLen THEN
         Tok[0] := 0C ;
         Error ("token too long", "") ;
         RETURN 0
      END ;
      Tok[k] := CHR (ch) ;
      INC (k) ;
      ch := NextChar ()
   END ;
   Tok[k] := 0C ;
   Pending := ch ;
   RETURN k
END Word ;


(* Reads the next token, which must be expect. *)
PROCEDURE Expect (expect: ARRAY OF CHAR) ;
VAR
   k, n: INTEGER ;
   same: BOOLEAN ;
   msg: ARRAY [0..TokLen + 64] OF CHAR ;
BEGIN
   n := Word (expect) ;
   IF Failed THEN RETURN END ;
   same := TRUE ;
   k := 0 ;
   WHILE same AND (k <= n) DO
      IF (VAL (CARDINAL, k) > HIGH (expect)) THEN
         same := Tok[k] = 0C
      ELSIF Tok[k] # expect[k] THEN
         same := FALSE
      ELSIF expect[k] = 0C THEN
         k := n
      END ;
      INC (k)
   END ;
   IF NOT same THEN
      msg := "expected '" ;
      Append (msg, expect) ;
      Append (msg, "', found '") ;
      Error (msg, Tok)
   END
END Expect ;


PROCEDURE Num () : REAL ;
VAR
   n: INTEGER ;
   x: REAL ;
   endp: ADDRESS ;
BEGIN
   n := Word ("") ;
   IF Failed THEN RETURN 0.0 END ;
   endp := NIL ;
   x := strtod (Tok, endp) ;
   IF endp # ADR (Tok[n]) THEN
      Error ("expected a number, found '", Tok) ;
      RETURN 0.0
   END ;
   RETURN x
END Num ;


(* The next token as a whole number (up to 18 digits). *)
PROCEDURE ReadLongInt () : LONGINT ;
VAR
   n, k: INTEGER ;
   v: LONGINT ;
   neg, ok: BOOLEAN ;
BEGIN
   n := Word ("") ;
   IF Failed THEN RETURN 0 END ;
   k := 0 ;
   neg := FALSE ;
   IF (Tok[0] = '-') OR (Tok[0] = '+') THEN
      neg := Tok[0] = '-' ;
      k := 1
   END ;
   ok := (k < n) AND (n - k <= 18) ;
   v := 0 ;
   WHILE ok AND (k < n) DO
      IF (Tok[k] >= '0') AND (Tok[k] <= '9') THEN
         v := v * 10 + VAL (LONGINT, ORD (Tok[k]) - ORD ('0'))
      ELSE
         ok := FALSE
      END ;
      INC (k)
   END ;
   IF NOT ok THEN
      Error ("expected an integer, found '", Tok) ;
      RETURN 0
   END ;
   IF neg THEN RETURN -v END ;
   RETURN v
END ReadLongInt ;


(* The next token as a count or index (INTEGER range). *)
PROCEDURE ReadInt () : INTEGER ;
VAR
   v: LONGINT ;
BEGIN
   v := ReadLongInt () ;
   IF Failed THEN RETURN 0 END ;
   IF (v > VAL (LONGINT, MAX (INTEGER))) OR (v < VAL (LONGINT, MIN (INTEGER))) THEN
      Error ("integer out of range: '", Tok) ;
      RETURN 0
   END ;
   RETURN VAL (INTEGER, v)
END ReadInt ;


(* A count of items read from the scene: 0 .. MaxItems. *)
PROCEDURE ReadCount () : INTEGER ;
VAR
   n: INTEGER ;
BEGIN
   n := ReadInt () ;
   IF (n < 0) OR (n > MaxItems) THEN
      Error ("bad count: '", Tok) ;
      RETURN 0
   END ;
   RETURN n
END ReadCount ;


(* A "body ..." line and its "v" lines into Bodies^[i], its vertices from
   Verts^[v0] on (room is made); the number of vertices. *)
PROCEDURE ReadBody (i, v0: INTEGER) : INTEGER ;
VAR
   k, nv: INTEGER ;
   b: BodyRef ;
   v: Vertex ;
BEGIN
   Expect ("body") ;
   IF Failed THEN RETURN 0 END ;
   b := ADR (Bodies^[i]) ;
   b^.idx := i ;
   b^.polygon := ReadInt () = 1 ;
   b^.fixed := ReadInt () = 1 ;
   b^.invM := Num () ; b^.invI := Num () ; b^.e := Num () ; b^.mu := Num () ;
   b^.px := Num () ; b^.py := Num () ; b^.vx := Num () ; b^.vy := Num () ;
   b^.ax := Num () ; b^.ay := Num () ;
   b^.fax := b^.ax ; b^.fay := b^.ay ;
   b^.sup := -1 ; b^.sup_edge := -1 ;
   b^.tx := 0.0 ; b^.ty := 0.0 ; b^.load := 0.0 ; b^.at := 0.0 ;
   b^.ang := Num () ; b^.om := Num () ;
   b^.r := Num () ; b^.orbit := Num () ; b^.ophase := Num () ; b^.bound := Num () ; b^.window := Num () ;
   b^.large := ReadInt () = 1 ;
   nv := ReadCount () ;
   IF Failed THEN RETURN 0 END ;
   b^.v0 := v0 ;
   b^.nv := nv ;
   ReserveVerts (v0 + nv) ;
   FOR k := 0 TO nv - 1 DO
      Expect ("v") ;
      IF Failed THEN RETURN 0 END ;
      v.lx := Num () ; v.ly := Num () ; v.rho := Num () ; v.beta := Num () ;
      v.psi := Num () ; v.h := Num () ; v.s1 := Num () ; v.s2 := Num () ;
      v.nx := Num () ; v.ny := Num () ; v.cover := ReadInt () ;
      Verts^[v0 + k] := v
   END ;
   b^.tb := 0.0 ;
   b^.stamp := 0 ;
   b^.cx := 0 ;
   b^.cy := 0 ;
   b^.gone := FALSE ;
   b^.asleep := FALSE ;
   b^.island := -1 ;
   b^.placed := FALSE ;
   b^.seen := 0 ;
   b^.carry := 0 ;
   RETURN nv
END ReadBody ;


(* Reads the scene from the current source (text or file). *)
PROCEDURE Read ;
VAR
   i: INTEGER ;
   m: ARRAY [0..127] OF CHAR ;
BEGIN
   Expect ("m2c-scene") ;
   IF ReadInt () # 1 THEN Error ("unknown version", "") END ;
   Expect ("end") ; EndT := Num () ;
   Expect ("frame") ; FrameDt := Num () ;
   Expect ("tolerance") ; Tol := Num () ;
   Expect ("rest_speed") ; RestSpeed := Num () ;
   Expect ("window_angle") ; Alpha := Num () ;
   Expect ("max_same_time") ; MaxSame := ReadLongInt () ;
   Expect ("grid") ;
   GridX0 := Num () ; GridY0 := Num () ; CellW := Num () ; CellH := Num () ;
   GridNX := ReadInt () ; GridNY := ReadInt () ; GridMargin := Num () ;
   IF Failed THEN RETURN END ;
   IF (GridNX < 1) OR (GridNY < 1) OR (GridNX > MaxItems DIV GridNY) THEN Error ("bad grid", "") ; RETURN END ;
   IF CellH < CellW THEN HalfCell := 0.5 * CellH ELSE HalfCell := 0.5 * CellW END ;
   IF NOT ((0.0 <= GridMargin) AND (GridMargin < HalfCell)) THEN
      Error ("grid margin outside [0, half a cell)", "") ; RETURN
   END ;
   Expect ("bodies") ;
   NBodies := ReadCount () ;
   IF Failed THEN RETURN END ;
   Reserve (NBodies) ;
   NVerts := 0 ;
   FOR i := 0 TO NBodies - 1 DO
      NVerts := NVerts + ReadBody (i, NVerts) ;
      IF Failed THEN RETURN END
   END ;
   Expect ("inputs") ;
   NInputs := ReadCount () ;
   IF Failed THEN RETURN END ;
   ReserveInputs (NInputs) ;
   FOR i := 0 TO NInputs - 1 DO
      Expect ("input") ;
      IF Failed THEN RETURN END ;
      Inputs^[i].t := Num () ;
      Inputs^[i].body := ReadInt () ;
      Inputs^[i].mode := ReadInt () ;
      Inputs^[i].vx := Num () ;
      Inputs^[i].vy := Num () ;
      IF (NOT Failed) AND ((Inputs^[i].body < 0) OR (Inputs^[i].body >= NBodies)) THEN
         m := "input on body " ;
         AppendWhole (m, Inputs^[i].body) ;
         Append (m, ", which does not exist") ;
         Error (m, "")
      ELSIF (NOT Failed) AND ((Inputs^[i].mode < 0) OR (Inputs^[i].mode > 4)) THEN
         m := "unknown input mode " ;
         AppendWhole (m, Inputs^[i].mode) ;
         Error (m, "")
      ELSIF (NOT Failed) AND Bodies^[Inputs^[i].body].fixed AND (Inputs^[i].mode # 4)
            AND NOT ((Inputs^[i].mode = 0) AND Bodies^[Inputs^[i].body].polygon
                     AND (Bodies^[Inputs^[i].body].om = 0.0)) THEN
         (* a fixed body takes removal (4), or set_velocity (0) when it is a
            polygon that does not turn *)
         m := "input " ;
         AppendWhole (m, i) ;
         Append (m, " on fixed body ") ;
         AppendWhole (m, Inputs^[i].body) ;
         Append (m, ": only set_velocity (on a polygon that does not turn) or remove") ;
         Error (m, "")
      END
   END ;
   Expect ("end")
END Read ;


(* Reads from the current source; afterwards, no source. *)
PROCEDURE Load () : BOOLEAN ;
BEGIN
   What := "scene" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   Pending := -2 ;
   NBodies := 0 ;
   NVerts := 0 ;
   NInputs := 0 ;
   Read ;
   SrcText := NIL ;
   SrcLen := 0 ;
   SrcPos := 0 ;
   RETURN NOT Failed
END Load ;


PROCEDURE ReadText (text: ADDRESS; len: CARDINAL) : BOOLEAN ;
BEGIN
   FromFile := FALSE ;
   SrcText := text ;
   SrcLen := len ;
   SrcPos := 0 ;
   RETURN Load ()
END ReadText ;


PROCEDURE ReadFile (path: ARRAY OF CHAR) : BOOLEAN ;
VAR
   ok: BOOLEAN ;
BEGIN
   Src := fopen (path, "r") ;
   IF Src = NIL THEN
      Failed := TRUE ;
      Message := "cannot open the scene file '" ;
      Append (Message, path) ;
      Append (Message, "'") ;
      RETURN FALSE
   END ;
   FromFile := TRUE ;
   ok := Load () ;
   IF fclose (Src) # 0 THEN END ;
   FromFile := FALSE ;
   RETURN ok
END ReadFile ;


PROCEDURE ReadStdin () : BOOLEAN ;
BEGIN
   Src := fdopen (0, "r") ;
   IF Src = NIL THEN
      Failed := TRUE ;
      Message := "cannot read standard input" ;
      RETURN FALSE
   END ;
   FromFile := TRUE ;
   RETURN Load ()
END ReadStdin ;


PROCEDURE ReadBodyText (text: ADDRESS; len: CARDINAL; i, v0: INTEGER; VAR nv: INTEGER) : BOOLEAN ;
VAR
   n: INTEGER ;
BEGIN
   What := "add_body" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   Pending := -2 ;
   FromFile := FALSE ;
   SrcText := text ;
   SrcLen := len ;
   SrcPos := 0 ;
   Reserve (i + 1) ;
   nv := ReadBody (i, v0) ;
   IF NOT Failed THEN
      (* nothing may follow: a word there is an error, the end is not *)
      REPEAT
         n := NextChar ()
      UNTIL (n < 0) OR (n > 32) ;
      IF n >= 0 THEN
         Pending := n ;
         n := Word ("") ;
         Error ("unexpected '", Tok) ;
         Append (Message, " after the body")
      END
   END ;
   SrcText := NIL ;
   SrcLen := 0 ;
   RETURN NOT Failed
END ReadBodyText ;


PROCEDURE ReadError (VAR msg: ARRAY OF CHAR) ;
VAR
   k: CARDINAL ;
BEGIN
   k := 0 ;
   WHILE (k < HIGH (msg)) AND (k <= HIGH (Message)) AND (Message[k] # 0C) DO
      msg[k] := Message[k] ;
      INC (k)
   END ;
   msg[k] := 0C
END ReadError ;


PROCEDURE AddInput (t: REAL; body, mode: INTEGER; x, y: REAL) : INTEGER ;
BEGIN
   ReserveInputs (NInputs + 1) ;
   Inputs^[NInputs].t := t ;
   Inputs^[NInputs].body := body ;
   Inputs^[NInputs].mode := mode ;
   Inputs^[NInputs].vx := x ;
   Inputs^[NInputs].vy := y ;
   INC (NInputs) ;
   RETURN NInputs - 1
END AddInput ;


PROCEDURE Reserve (n: INTEGER) ;
BEGIN
   IF n > CapBodies THEN
      IF CapBodies = 0 THEN CapBodies := 16 END ;
      WHILE CapBodies < n DO CapBodies := 2 * CapBodies END ;
      Bodies := Grow (Bodies, CapBodies, SIZE (Body))
   END
END Reserve ;


PROCEDURE ReserveVerts (n: INTEGER) ;
BEGIN
   IF n > CapVerts THEN
      IF CapVerts = 0 THEN CapVerts := 16 END ;
      WHILE CapVerts < n DO CapVerts := 2 * CapVerts END ;
      Verts := Grow (Verts, CapVerts, SIZE (Vertex))
   END
END ReserveVerts ;


PROCEDURE ReserveInputs (n: INTEGER) ;
BEGIN
   IF n > CapInputs THEN
      IF CapInputs = 0 THEN CapInputs := 16 END ;
      WHILE CapInputs < n DO CapInputs := 2 * CapInputs END ;
      Inputs := Grow (Inputs, CapInputs, SIZE (Input))
   END
END ReserveInputs ;


BEGIN
   Pending := -2 ;
   What := "scene" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   FromFile := FALSE ;
   Src := NIL ;
   SrcText := NIL ;
   SrcLen := 0 ;
   SrcPos := 0 ;
   NBodies := 0 ;
   NVerts := 0 ;
   NInputs := 0 ;
   CapBodies := 0 ;
   CapVerts := 0 ;
   CapInputs := 0 ;
   Bodies := NIL ;
   Verts := NIL ;
   Inputs := NIL
END SimScene.
