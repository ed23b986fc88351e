IMPLEMENTATION MODULE SimOut ;

(* The trace writer (SimOut.def): one output buffer, the numbers and the
   lines of contacts, support ends and counters.

   The fast path of Real, for a finite nonzero x: with X = floor(log10 |x|),
   y = |x| 10^(16 - X) lies in [10^16, 10^17) and "%.17g" writes the
   integer nearest to y (ties to even) as 17 digits, then drops trailing
   zeros.  y is computed in LONGREAL (x87 extended, 64-bit significand) with
   at most two roundings (powers of ten up to 10^27 are exact there), so it
   is within 2 * 2^-64 * 10^17 < 0.011 of the exact product.  Whenever the
   fraction of the computed y is within 0.05 of one half, or y is within 2
   of either end of the range, the exact answer could differ and snprintf
   decides instead; otherwise the nearest integer to the computed y is the
   nearest integer to the exact one.  |X| beyond the table's reach
   (|16 - X| > 54), zeros, infinities and NaNs go to the slow path or are
   written directly. *)

FROM SYSTEM IMPORT ADR, CAST ;
FROM SimC IMPORT write, snprintf, floor, exit ;
FROM CMath IMPORT frexp ;

CONST
   BufSize = 65536 ;
   Room = 64 ;            (* the longest item appended at once *)
   MaxP = 27 ;            (* 10^27 < 2^64 * 2^27: exact in LONGREAL *)
   Log10of2 = 0.30102999566398120 ;

VAR
   buf: ARRAY [0..BufSize - 1] OF CHAR ;
   pos: INTEGER ;
   pow: ARRAY [0..MaxP] OF LONGREAL ;
   lo, hi: LONGREAL ;     (* 10^16 + 2, 10^17 - 2 *)
   on: BOOLEAN ;          (* SetOn *)


PROCEDURE SetOn (o: BOOLEAN) ;
BEGIN
   on := o
END SetOn ;


PROCEDURE Flush ;
VAR
   off: INTEGER ;
   r: LONGINT ;
BEGIN
   off := 0 ;
   WHILE off < pos DO
      r := write (1, ADR (buf[off]), VAL (LONGCARD, pos - off)) ;
      IF r <= 0 THEN
         pos := 0 ;
         RETURN
      END ;
      off := off + VAL (INTEGER, r)
   END ;
   pos := 0
END Flush ;


PROCEDURE Fail ;
BEGIN
   Flush ;
   exit (1)
END Fail ;


PROCEDURE FailMsg (msg: ARRAY OF CHAR) ;
BEGIN
   on := TRUE ;
   Str ("X ") ;
   Str (msg) ;
   Ln ;
   Fail
END FailMsg ;


PROCEDURE Reserve ;
BEGIN
   IF pos > BufSize - Room THEN Flush END
END Reserve ;


PROCEDURE Str (s: ARRAY OF CHAR) ;
VAR
   k: CARDINAL ;
BEGIN
   IF NOT on THEN RETURN END ;
   k := 0 ;
   WHILE (k <= HIGH (s)) AND (s[k] # 0C) DO
      IF pos >= BufSize THEN Flush END ;
      buf[pos] := s[k] ;
      INC (pos) ;
      INC (k)
   END
END Str ;


PROCEDURE Int (v: LONGINT) ;
VAR
   d: ARRAY [0..23] OF CHAR ;
   n: INTEGER ;
   u: LONGCARD ;
BEGIN
   IF NOT on THEN RETURN END ;
   Reserve ;
   IF v < 0 THEN
      buf[pos] := '-' ;
      INC (pos) ;
      u := VAL (LONGCARD, -(v + 1)) + 1
   ELSE
      u := VAL (LONGCARD, v)
   END ;
   n := 0 ;
   REPEAT
      d[n] := CHR (ORD ('0') + VAL (CARDINAL, u MOD 10)) ;
      u := u DIV 10 ;
      INC (n)
   UNTIL u = 0 ;
   WHILE n > 0 DO
      DEC (n) ;
      buf[pos] := d[n] ;
      INC (pos)
   END
END Int ;


PROCEDURE Ln ;
BEGIN
   IF NOT on THEN RETURN END ;
   Reserve ;
   buf[pos] := 12C ;
   INC (pos)
END Ln ;


(* |x| 10^p, with |p| <= 2 MaxP. *)
PROCEDURE Scaled (ax: LONGREAL; p: INTEGER) : LONGREAL ;
BEGIN
   IF p >= 0 THEN
      IF p <= MaxP THEN RETURN ax * pow[p] END ;
      RETURN (ax * pow[MaxP]) * pow[p - MaxP]
   END ;
   IF -p <= MaxP THEN RETURN ax / pow[-p] END ;
   RETURN (ax / pow[MaxP]) / pow[-p - MaxP]
END Scaled ;


PROCEDURE FastDigits (x: REAL; VAR digits: LONGCARD; VAR exp10: INTEGER) : BOOLEAN ;
VAR
   ax: REAL ;
   y, f: LONGREAL ;
   e2, x10, p, tries: INTEGER ;
   d: LONGCARD ;
   fr: REAL ;
BEGIN
   digits := 0 ;
   exp10 := 0 ;
   IF (x # x) OR (x = 0.0) OR (x - x # 0.0) THEN RETURN FALSE END ;
   ax := ABS (x) ;
   fr := frexp (ax, e2) ;                       (* ax in [2^(e2-1), 2^e2) *)
   x10 := VAL (INTEGER, floor (VAL (REAL, e2 - 1) * Log10of2)) ;
   tries := 0 ;
   LOOP
      p := 16 - x10 ;
      IF (p > 2 * MaxP) OR (p < -2 * MaxP) OR (tries > 2) THEN RETURN FALSE END ;
      y := Scaled (VAL (LONGREAL, ax), p) ;
      IF y < 1.0E16 THEN
         DEC (x10)
      ELSIF y >= 1.0E17 THEN
         INC (x10)
      ELSE
         EXIT
      END ;
      INC (tries)
   END ;
   IF (y < lo) OR (y > hi) THEN RETURN FALSE END ;
   d := VAL (LONGCARD, y) ;                     (* truncates: y > 0 *)
   f := y - VAL (LONGREAL, d) ;
   IF (f > 0.45) AND (f < 0.55) THEN RETURN FALSE END ;
   IF f > 0.5 THEN INC (d) END ;
   digits := d ;
   exp10 := x10 ;
   RETURN TRUE
END FastDigits ;


(* Appends the digits of d (17 of them) and exponent x10 as %g does with
   precision 17: trailing zeros dropped, scientific form when x10 < -4 or
   x10 >= 17. *)
PROCEDURE Format (neg: BOOLEAN; d: LONGCARD; x10: INTEGER) ;
VAR
   s: ARRAY [0..16] OF CHAR ;
   k, nd, e: INTEGER ;
BEGIN
   FOR k := 16 TO 0 BY -1 DO
      s[k] := CHR (ORD ('0') + VAL (CARDINAL, d MOD 10)) ;
      d := d DIV 10
   END ;
   nd := 17 ;
   WHILE (nd > 1) AND (s[nd - 1] = '0') DO DEC (nd) END ;
   IF neg THEN
      buf[pos] := '-' ;
      INC (pos)
   END ;
   IF (x10 < -4) OR (x10 >= 17) THEN
      buf[pos] := s[0] ;
      INC (pos) ;
      IF nd > 1 THEN
         buf[pos] := '.' ;
         INC (pos) ;
         FOR k := 1 TO nd - 1 DO
            buf[pos] := s[k] ;
            INC (pos)
         END
      END ;
      buf[pos] := 'e' ;
      INC (pos) ;
      e := x10 ;
      IF e < 0 THEN
         buf[pos] := '-' ;
         e := -e
      ELSE
         buf[pos] := '+'
      END ;
      INC (pos) ;
      IF e >= 100 THEN
         buf[pos] := CHR (ORD ('0') + VAL (CARDINAL, e DIV 100)) ;
         INC (pos)
      END ;
      buf[pos] := CHR (ORD ('0') + VAL (CARDINAL, (e DIV 10) MOD 10)) ;
      INC (pos) ;
      buf[pos] := CHR (ORD ('0') + VAL (CARDINAL, e MOD 10)) ;
      INC (pos)
   ELSIF x10 >= 0 THEN
      FOR k := 0 TO x10 DO           (* the integer part: x10 + 1 <= 17 digits *)
         buf[pos] := s[k] ;
         INC (pos)
      END ;
      IF nd > x10 + 1 THEN
         buf[pos] := '.' ;
         INC (pos) ;
         FOR k := x10 + 1 TO nd - 1 DO
            buf[pos] := s[k] ;
            INC (pos)
         END
      END
   ELSE
      buf[pos] := '0' ;
      INC (pos) ;
      buf[pos] := '.' ;
      INC (pos) ;
      FOR k := 1 TO -x10 - 1 DO
         buf[pos] := '0' ;
         INC (pos)
      END ;
      FOR k := 0 TO nd - 1 DO
         buf[pos] := s[k] ;
         INC (pos)
      END
   END
END Format ;


PROCEDURE Real (x: REAL) ;
VAR
   d: LONGCARD ;
   x10, n: INTEGER ;
BEGIN
   IF NOT on THEN RETURN END ;
   Reserve ;
   IF x # x THEN
      Str ("nan")
   ELSIF FastDigits (x, d, x10) THEN
      Format (x < 0.0, d, x10)
   ELSE
      n := snprintf (ADR (buf[pos]), VAL (LONGCARD, Room), "%.17g", x) ;
      IF (n > 0) AND (n < Room) THEN pos := pos + n END
   END
END Real ;


PROCEDURE SpReal (x: REAL) ;
BEGIN
   IF NOT on THEN RETURN END ;
   Reserve ;
   buf[pos] := ' ' ;
   INC (pos) ;
   Real (x)
END SpReal ;


PROCEDURE Take (VAR s: ARRAY OF CHAR) ;
VAR
   k: INTEGER ;
BEGIN
   k := 0 ;
   WHILE (k < pos) AND (VAL (CARDINAL, k) < HIGH (s)) DO
      s[k] := buf[k] ;
      INC (k)
   END ;
   s[k] := 0C ;
   pos := 0
END Take ;
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


PROCEDURE Stat (name: ARRAY OF CHAR; count: LONGINT) ;
BEGIN
   Str ("N ") ;
   Str (name) ;
   Str (" ") ;
   Int (count) ;
   Ln
END Stat ;




VAR
   p10: INTEGER ;
BEGIN
   pos := 0 ;
   on := TRUE ;
   pow[0] := 1.0 ;
   FOR p10 := 1 TO MaxP DO pow[p10] := pow[p10 - 1] * 10.0 END ;
   lo := pow[16] + 2.0 ;
   hi := pow[16] * 10.0 - 2.0
END SimOut.
