MODULE ToiTestee ;

(* The TOI library's conformance testee (docs/conformance.md, op "toi";
   docs/toi.md), the wire of runtimes/c/tools/m2c_toi_testee.c.  Reads lines
     toi SEQ HORIZON TOL BODY_A BODY_B
   where a body is N (0: a circle, then its radius; else N vertices x y),
   then its motion x y vx vy ax ay angle omega orbit orbit_phase; every
   number a hex double (16 hex digits of its bits) but N and SEQ.  Answers
     SEQ hit T FEATURE FIRST I J PX PY NX NY | SEQ none | SEQ overlapped
     | SEQ error refused | SEQ error malformed
   A line whose words are out of order is answered malformed and skipped. *)

FROM Wire IMPORT HexToReal, ReadToken, SkipLine, ToInt, WriteHex, WriteLn, WriteString ;
FROM Toi IMPORT Circle, Defaults, Hit, MaxVertices, Motion, None, Options, Overlapped, Polygon, Result, Shape,
                TimeOfImpact ;

VAR
   tok, seq: ARRAY [0..63] OF CHAR ;
   horizon: REAL ;
   o: Options ;
   sa, sb: Shape ;
   qa, qb: Motion ;
   r: Result ;
   whole: BOOLEAN ;          (* the line read as the wire says *)


(* The next word as a hex double; ok stays TRUE only while every word reads. *)
PROCEDURE Hex (VAR ok: BOOLEAN) : REAL ;
VAR
   w: ARRAY [0..63] OF CHAR ;
   x: REAL ;
   good: BOOLEAN ;
BEGIN
   IF NOT ok THEN RETURN 0.0 END ;
   IF NOT ReadToken (w) THEN
      ok := FALSE ;
      RETURN 0.0
   END ;
   x := HexToReal (w, good) ;
   ok := good ;
   RETURN x
END Hex ;


(* One body's words into s and q. *)
PROCEDURE ReadBody (VAR s: Shape; VAR q: Motion; VAR ok: BOOLEAN) ;
VAR
   w: ARRAY [0..63] OF CHAR ;
   xy: ARRAY [0..2 * MaxVertices - 1] OF REAL ;
   n, k: INTEGER ;
   good: BOOLEAN ;
BEGIN
   IF NOT ok THEN RETURN END ;
   IF NOT ReadToken (w) THEN
      ok := FALSE ;
      RETURN
   END ;
   n := ToInt (w, good) ;
   IF NOT good OR (n > MaxVertices) THEN
      ok := FALSE ;
      RETURN
   END ;
   IF n = 0 THEN
      ok := Circle (s, Hex (ok)) AND ok
   ELSE
      FOR k := 0 TO 2 * n - 1 DO xy[k] := Hex (ok) END ;
      ok := ok AND Polygon (s, xy, n)
   END ;
   q.x := Hex (ok) ;
   q.y := Hex (ok) ;
   q.vx := Hex (ok) ;
   q.vy := Hex (ok) ;
   q.ax := Hex (ok) ;
   q.ay := Hex (ok) ;
   q.angle := Hex (ok) ;
   q.omega := Hex (ok) ;
   q.orbit := Hex (ok) ;
   q.orbitPhase := Hex (ok)
END ReadBody ;


PROCEDURE WriteInt (v: INTEGER) ;
VAR
   d, out: ARRAY [0..15] OF CHAR ;
   k, m: INTEGER ;
   u: CARDINAL ;
BEGIN
   m := 0 ;
   IF v < 0 THEN
      out[0] := '-' ;
      m := 1 ;
      u := VAL (CARDINAL, -v)
   ELSE
      u := VAL (CARDINAL, v)
   END ;
   k := 0 ;
   REPEAT
      d[k] := CHR (ORD ('0') + u MOD 10) ;
      u := u DIV 10 ;
      INC (k)
   UNTIL u = 0 ;
   WHILE k > 0 DO
      DEC (k) ;
      out[m] := d[k] ;
      INC (m)
   END ;
   out[m] := 0C ;
   WriteString (out)
END WriteInt ;


BEGIN
   WHILE ReadToken (tok) DO
      whole := ReadToken (seq) ;
      Defaults (o) ;
      whole := whole AND (tok[0] = 't') AND (tok[1] = 'o') AND (tok[2] = 'i') AND (tok[3] = 0C) ;
      horizon := Hex (whole) ;
      o.tol := Hex (whole) ;
      ReadBody (sa, qa, whole) ;
      ReadBody (sb, qb, whole) ;
      WriteString (seq) ;
      IF NOT whole THEN
         SkipLine ;
         WriteString (" error malformed")
      ELSE
         CASE TimeOfImpact (sa, qa, sb, qb, horizon, o, r) OF
            Hit:
               WriteString (" hit ") ;
               WriteHex (r.t) ;
               WriteString (" ") ;
               WriteInt (r.feature) ;
               WriteString (" ") ;
               WriteInt (r.first) ;
               WriteString (" ") ;
               WriteInt (r.i) ;
               WriteString (" ") ;
               WriteInt (r.j) ;
               WriteString (" ") ;
               WriteHex (r.px) ;
               WriteString (" ") ;
               WriteHex (r.py) ;
               WriteString (" ") ;
               WriteHex (r.nx) ;
               WriteString (" ") ;
               WriteHex (r.ny)
          | None: WriteString (" none")
          | Overlapped: WriteString (" overlapped")
         ELSE
            WriteString (" error refused")
         END
      END ;
      WriteLn
   END
END ToiTestee.
