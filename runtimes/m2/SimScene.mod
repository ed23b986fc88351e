IMPLEMENTATION MODULE SimScene ;

(* Reading the flat scene: whitespace-separated tokens from standard input,
   numbers through the C library's strtod (the scene's shortest round-trip
   decimals are read exactly), whole numbers digit by digit. *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM CMath IMPORT getchar ;
FROM SimC IMPORT strtod, realloc ;
FROM SimOut IMPORT Str, Ln, Fail, FailMsg ;

CONST
   TokLen = 255 ;

TYPE
   Token = ARRAY [0..TokLen] OF CHAR ;

VAR
   Pending: INTEGER ;          (* a character read ahead, or -2 *)
   Tok: Token ;                (* the last token read *)


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


PROCEDURE NextChar () : INTEGER ;
VAR
   ch: INTEGER ;
BEGIN
   IF Pending # -2 THEN
      ch := Pending ;
      Pending := -2 ;
      RETURN ch
   END ;
   RETURN getchar ()
END NextChar ;


(* The next whitespace-delimited token into Tok; its length. *)
PROCEDURE Word () : INTEGER ;
VAR
   ch, k: INTEGER ;
BEGIN
   REPEAT
      ch := NextChar ()
   UNTIL (ch < 0) OR (ch > 32) ;
   IF ch < 0 THEN FailMsg ("scene: unexpected end of input") END ;
   k := 0 ;
   WHILE ch > 32 DO
      IF k >= TokLen THEN FailMsg ("scene: token too long") END ;
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
BEGIN
   n := Word () ;
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
      Str ("X scene: expected '") ;
      Str (expect) ;
      Str ("', found '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END
END Expect ;


PROCEDURE Num () : REAL ;
VAR
   n: INTEGER ;
   x: REAL ;
   endp: ADDRESS ;
BEGIN
   n := Word () ;
   endp := NIL ;
   x := strtod (Tok, endp) ;
   IF endp # ADR (Tok[n]) THEN
      Str ("X scene: not a number: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
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
   n := Word () ;
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
      Str ("X scene: not an integer: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
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
   IF (v > VAL (LONGINT, MAX (INTEGER))) OR (v < VAL (LONGINT, MIN (INTEGER))) THEN
      Str ("X scene: integer out of range: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END ;
   RETURN VAL (INTEGER, v)
END ReadInt ;


PROCEDURE ReadScene ;
VAR
   i, k, nv, capVerts: INTEGER ;
   b: BodyRef ;
   v: Vertex ;
BEGIN
   Expect ("m2c-scene") ;
   IF ReadInt () # 1 THEN FailMsg ("scene: unknown version") END ;
   Expect ("end") ; EndT := Num () ;
   Expect ("frame") ; FrameDt := Num () ;
   Expect ("tolerance") ; Tol := Num () ;
   Expect ("rest_speed") ; RestSpeed := Num () ;
   Expect ("window_angle") ; Alpha := Num () ;
   Expect ("max_same_time") ; MaxSame := ReadLongInt () ;
   Expect ("grid") ;
   GridX0 := Num () ; GridY0 := Num () ; CellW := Num () ; CellH := Num () ;
   GridNX := ReadInt () ; GridNY := ReadInt () ;
   IF (GridNX < 1) OR (GridNY < 1) OR (GridNX > MaxItems DIV GridNY) THEN FailMsg ("scene: bad grid") END ;
   Expect ("bodies") ;
   NBodies := ReadInt () ;
   Bodies := Grow (NIL, NBodies, SIZE (Body)) ;
   NVerts := 0 ;
   capVerts := 16 ;
   Verts := Grow (NIL, capVerts, SIZE (Vertex)) ;
   FOR i := 0 TO NBodies - 1 DO
      Expect ("body") ;
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
      b^.r := Num () ; b^.orbit := Num () ; b^.ophase := Num () ; b^.bound := Num () ;
      b^.large := ReadInt () = 1 ;
      nv := ReadInt () ;
      IF nv < 0 THEN FailMsg ("scene: negative vertex count") END ;
      b^.v0 := NVerts ;
      b^.nv := nv ;
      IF NVerts + nv > capVerts THEN
         WHILE NVerts + nv > capVerts DO capVerts := 2 * capVerts END ;
         Verts := Grow (Verts, capVerts, SIZE (Vertex))
      END ;
      FOR k := 0 TO nv - 1 DO
         Expect ("v") ;
         v.lx := Num () ; v.ly := Num () ; v.rho := Num () ; v.beta := Num () ;
         v.psi := Num () ; v.h := Num () ; v.s1 := Num () ; v.s2 := Num () ;
         v.nx := Num () ; v.ny := Num () ;
         Verts^[NVerts] := v ;
         INC (NVerts)
      END ;
      b^.tb := 0.0 ;
      b^.stamp := 0 ;
      b^.cx := 0 ;
      b^.cy := 0
   END ;
   Expect ("inputs") ;
   NInputs := ReadInt () ;
   Inputs := Grow (NIL, NInputs, SIZE (Input)) ;
   FOR i := 0 TO NInputs - 1 DO
      Expect ("input") ;
      Inputs^[i].t := Num () ;
      Inputs^[i].body := ReadInt () ;
      Inputs^[i].mode := ReadInt () ;
      Inputs^[i].vx := Num () ;
      Inputs^[i].vy := Num () ;
      IF (Inputs^[i].body < 0) OR (Inputs^[i].body >= NBodies) THEN
         FailMsg ("scene: input of an unknown body")
      END
   END ;
   Expect ("end")
END ReadScene ;


BEGIN
   Pending := -2 ;
   NBodies := 0 ;
   NVerts := 0 ;
   NInputs := 0 ;
   Bodies := NIL ;
   Verts := NIL ;
   Inputs := NIL
END SimScene.
