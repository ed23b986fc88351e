IMPLEMENTATION MODULE Wire ;

FROM SYSTEM IMPORT CAST ;
FROM CMath IMPORT getchar, putchar ;
IMPORT Roots, RootsGsl ;

VAR
   pending: INTEGER ;   (* a character read ahead, or -2 *)


PROCEDURE Next () : INTEGER ;
VAR
   ch: INTEGER ;
BEGIN
   IF pending # -2
   THEN
      ch := pending ;
      pending := -2 ;
      RETURN ch
   END ;
   RETURN getchar ()
END Next ;


PROCEDURE ReadToken (VAR s: ARRAY OF CHAR) : BOOLEAN ;
VAR
   ch: INTEGER ;
   k: CARDINAL ;
BEGIN
   REPEAT
      ch := Next ()
   UNTIL (ch < 0) OR (ch > 32) ;
   IF ch < 0 THEN RETURN FALSE END ;
   k := 0 ;
   WHILE ch > 32 DO
      IF k < HIGH (s) THEN
         s[k] := CHR (ch) ;
         INC (k)
      END ;
      ch := Next ()
   END ;
   s[k] := 0C ;
   pending := ch ;
   RETURN TRUE
END ReadToken ;


(* Skips to the end of the current line. *)
PROCEDURE SkipLine ;
VAR
   ch: INTEGER ;
BEGIN
   ch := Next () ;
   WHILE (ch >= 0) AND (ch # 10) DO
      ch := Next ()
   END
END SkipLine ;


PROCEDURE HexToReal (s: ARRAY OF CHAR; VAR ok: BOOLEAN) : REAL ;
VAR
   u: LONGCARD ;
   k, d: CARDINAL ;
BEGIN
   u := 0 ;
   k := 0 ;
   ok := TRUE ;
   WHILE (k <= HIGH (s)) AND (s[k] # 0C) DO
      IF (s[k] >= '0') AND (s[k] <= '9') THEN
         d := ORD (s[k]) - ORD ('0')
      ELSIF (s[k] >= 'a') AND (s[k] <= 'f') THEN
         d := ORD (s[k]) - ORD ('a') + 10
      ELSIF (s[k] >= 'A') AND (s[k] <= 'F') THEN
         d := ORD (s[k]) - ORD ('A') + 10
      ELSE
         ok := FALSE ;
         d := 0
      END ;
      u := u * 16 + VAL (LONGCARD, d) ;
      INC (k)
   END ;
   ok := ok AND (k = 16) ;
   RETURN CAST (REAL, u)
END HexToReal ;


PROCEDURE ToInt (s: ARRAY OF CHAR; VAR ok: BOOLEAN) : INTEGER ;
VAR
   v: INTEGER ;
   k: CARDINAL ;
BEGIN
   v := 0 ;
   k := 0 ;
   ok := (HIGH (s) > 0) AND (s[0] # 0C) ;
   WHILE (k <= HIGH (s)) AND (s[k] # 0C) DO
      IF (s[k] >= '0') AND (s[k] <= '9') AND (v < 100000) THEN
         v := v * 10 + VAL (INTEGER, ORD (s[k]) - ORD ('0'))
      ELSE
         ok := FALSE
      END ;
      INC (k)
   END ;
   RETURN v
END ToInt ;


PROCEDURE ReadCase (VAR k: Case) : BOOLEAN ;
VAR
   tok: ARRAY [0..63] OF CHAR ;
   ok, okall: BOOLEAN ;
   i: INTEGER ;
BEGIN
   IF NOT ReadToken (k.op) THEN RETURN FALSE END ;
   IF NOT ReadToken (k.seq) THEN RETURN FALSE END ;
   k.count := -1 ;
   IF (k.op[0] # 'r') OR (k.op[1] # 'o') OR (k.op[2] # 'o') OR (k.op[3] # 't')
      OR (k.op[4] # 's') OR (k.op[5] # 0C)
   THEN
      SkipLine ;
      RETURN TRUE
   END ;
   okall := ReadToken (tok) ;
   k.lo := HexToReal (tok, ok) ;
   okall := okall AND ok AND ReadToken (tok) ;
   k.hi := HexToReal (tok, ok) ;
   okall := okall AND ok AND ReadToken (tok) ;
   i := ToInt (tok, ok) ;
   IF (NOT (okall AND ok)) OR (i > MaxCount)
   THEN
      SkipLine ;
      RETURN TRUE
   END ;
   k.count := i ;
   FOR i := 0 TO k.count - 1 DO
      okall := okall AND ReadToken (tok) ;
      k.c[i] := HexToReal (tok, ok) ;
      okall := okall AND ok
   END ;
   IF NOT okall THEN k.count := -1 END ;
   SkipLine ;
   RETURN TRUE
END ReadCase ;


PROCEDURE WriteString (s: ARRAY OF CHAR) ;
VAR
   k: CARDINAL ;
   r: INTEGER ;
BEGIN
   k := 0 ;
   WHILE (k <= HIGH (s)) AND (s[k] # 0C) DO
      r := putchar (VAL (INTEGER, ORD (s[k]))) ;
      INC (k)
   END
END WriteString ;


PROCEDURE WriteHex (x: REAL) ;
VAR
   u: LONGCARD ;
   dig: ARRAY [0..15] OF INTEGER ;
   i, r: INTEGER ;
BEGIN
   u := CAST (LONGCARD, x) ;
   FOR i := 15 TO 0 BY -1 DO
      dig[i] := VAL (INTEGER, u MOD 16) ;
      u := u DIV 16
   END ;
   FOR i := 0 TO 15 DO
      IF dig[i] < 10 THEN
         r := putchar (48 + dig[i])
      ELSE
         r := putchar (87 + dig[i])
      END
   END
END WriteHex ;


PROCEDURE WriteLn ;
VAR
   r: INTEGER ;
BEGIN
   r := putchar (10)
END WriteLn ;


PROCEDURE Serve (gsl: BOOLEAN) ;
VAR
   k: Case ;
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   WHILE ReadCase (k) DO
      WriteString (k.seq) ;
      IF k.count < 0 THEN
         IF k.op[0] = 'r' THEN
            WriteString (" error malformed")
         ELSE
            WriteString (" error unknown-op")
         END
      ELSE
         IF k.count = 0 THEN
            found := FALSE
         ELSIF gsl THEN
            found := RootsGsl.SmallestRoot (k.c, k.count - 1, k.lo, k.hi, t)
         ELSE
            found := Roots.SmallestRoot (k.c, k.count - 1, k.lo, k.hi, t)
         END ;
         IF found THEN
            WriteString (" ") ;
            WriteHex (t)
         ELSE
            WriteString (" none")
         END
      END ;
      WriteLn
   END
END Serve ;


BEGIN
   pending := -2
END Wire.
