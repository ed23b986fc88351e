IMPLEMENTATION MODULE SimScene ;

(* Reading the flat scene: the whole text in memory (a file or standard
   input is read into a buffer first), its bytes and length checked, then
   whitespace-separated words read in order and checked field by field
   (docs/simulator.md, "Flat scene checks").  A number's word is matched
   against the flat format's grammar here and converted by the C library's
   strtod (correctly rounded, as every runtime's parse is); an integer's
   word has at most 18 digits and is read digit by digit into a LONGINT. *)

FROM SYSTEM IMPORT ADDRESS, ADR, CAST ;
FROM SimC IMPORT strtod, realloc, fopen, fdopen, fclose, fread, free, snprintf ;
FROM SimOut IMPORT FailMsg ;

CONST
   TokLen = 255 ;              (* characters of a word kept in Tok (longer words are no number,
                                  integer or keyword, and a message shows 32 of them) *)
   NumLen = 64 ;               (* characters of a number's word at most *)
   IntLen = 18 ;               (* digits of an integer at most *)
   ShowLen = 32 ;              (* characters of a word a message shows, then "..." *)
   SignBit = VAL (LONGCARD, 9223372036854775808) ;  (* 2^63: a REAL's sign bit *)
   InfBits = VAL (LONGCARD, 9218868437227405312) ;  (* the bits of infinity; NaNs lie above *)
   MsgMax = 511 ;

TYPE
   Token = ARRAY [0..TokLen] OF CHAR ;
   Chars = POINTER TO ARRAY [0..MAX (INTEGER)] OF CHAR ;
   Msg = ARRAY [0..MsgMax] OF CHAR ;

VAR
   Tok: Token ;                (* the last word read (its first TokLen characters) *)
   TokN: CARDINAL ;            (* its whole length *)
   Failed: BOOLEAN ;           (* the reading failed: Message says why *)
   What: ARRAY [0..15] OF CHAR ;   (* what is read, for the messages: "scene" or "add_body" *)
   Message: Msg ;
   SrcText: Chars ;            (* the text: SrcText^[SrcPos .. SrcLen - 1] is still to read *)
   SrcLen, SrcPos: CARDINAL ;
   Buf: Chars ;                (* a file's or standard input's text (realloc'd) *)
   BufCap: CARDINAL ;
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


(* x is neither infinite nor a NaN (from its bits: no comparison of a NaN). *)
PROCEDURE Finite (x: REAL) : BOOLEAN ;
BEGIN
   RETURN CAST (LONGCARD, x) MOD SignBit < InfBits
END Finite ;


(* Range tests that are FALSE for a NaN or an infinity, whatever gm2 makes
   of a comparison with a NaN (it may compile x > m as NOT (x <= m)): the
   comparisons are made only for a finite x.  In: lo <= x <= hi; AtLeast:
   lo <= x; Above: lo < x; AtMost: x <= hi. *)
PROCEDURE In (x, lo, hi: REAL) : BOOLEAN ;
BEGIN
   RETURN Finite (x) AND (lo <= x) AND (x <= hi)
END In ;

PROCEDURE AtLeast (x, lo: REAL) : BOOLEAN ;
BEGIN
   RETURN Finite (x) AND (lo <= x)
END AtLeast ;

PROCEDURE Above (x, lo: REAL) : BOOLEAN ;
BEGIN
   RETURN Finite (x) AND (lo < x)
END Above ;

PROCEDURE AtMost (x, hi: REAL) : BOOLEAN ;
BEGIN
   RETURN Finite (x) AND (x <= hi)
END AtMost ;


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


(* s with the decimal digits of v (and its sign) appended. *)
PROCEDURE AppendWhole (VAR s: ARRAY OF CHAR; v: LONGINT) ;
VAR
   d: ARRAY [0..39] OF CHAR ;
BEGIN
   d[0] := 0C ;
   IF snprintf (ADR (d), 40, "%lld", v) > 0 THEN Append (s, d) END
END AppendWhole ;


(* s with x appended as "%.17g" writes it. *)
PROCEDURE AppendReal (VAR s: ARRAY OF CHAR; x: REAL) ;
VAR
   d: ARRAY [0..39] OF CHAR ;
BEGIN
   d[0] := 0C ;
   IF snprintf (ADR (d), 40, "%.17g", x) > 0 THEN Append (s, d) END
END AppendReal ;


(* s with the last word appended as a message shows it: its first ShowLen
   characters, then "..." when it is longer. *)
PROCEDURE AppendWord (VAR s: ARRAY OF CHAR) ;
VAR
   w: ARRAY [0..ShowLen + 3] OF CHAR ;
   k: CARDINAL ;
BEGIN
   k := 0 ;
   WHILE (k < ShowLen) AND (k < TokN) DO
      w[k] := Tok[k] ;
      INC (k)
   END ;
   w[k] := 0C ;
   IF TokN > ShowLen THEN Append (w, "...") END ;
   Append (s, w)
END AppendWord ;


(* The first fault of this reading: What, ": ", msg. *)
PROCEDURE Error (msg: ARRAY OF CHAR) ;
BEGIN
   IF Failed THEN RETURN END ;
   Failed := TRUE ;
   Message[0] := 0C ;
   Append (Message, What) ;
   Append (Message, ": ") ;
   Append (Message, msg)
END Error ;


(* Error (a ++ x as "%.17g" ++ b). *)
PROCEDURE ErrorReal (a: ARRAY OF CHAR; x: REAL; b: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m[0] := 0C ;
   Append (m, a) ;
   AppendReal (m, x) ;
   Append (m, b) ;
   Error (m)
END ErrorReal ;


(* Error (a ++ v ++ b). *)
PROCEDURE ErrorWhole (a: ARRAY OF CHAR; v: LONGINT; b: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m[0] := 0C ;
   Append (m, a) ;
   AppendWhole (m, v) ;
   Append (m, b) ;
   Error (m)
END ErrorWhole ;


(* Error ("body k: " ++ a ++ x ++ b), x as "%.17g". *)
PROCEDURE BodyReal (k: INTEGER; a: ARRAY OF CHAR; x: REAL; b: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m := "body " ;
   AppendWhole (m, k) ;
   Append (m, ": ") ;
   Append (m, a) ;
   AppendReal (m, x) ;
   Append (m, b) ;
   Error (m)
END BodyReal ;


(* Error ("body k: " ++ a). *)
PROCEDURE BodyError (k: INTEGER; a: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m := "body " ;
   AppendWhole (m, k) ;
   Append (m, ": ") ;
   Append (m, a) ;
   Error (m)
END BodyError ;


(* Error ("body k vertex j: " ++ a). *)
PROCEDURE VertexError (k, j: INTEGER; a: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m := "body " ;
   AppendWhole (m, k) ;
   Append (m, " vertex ") ;
   AppendWhole (m, j) ;
   Append (m, ": ") ;
   Append (m, a) ;
   Error (m)
END VertexError ;


(* The text's length (to a 0C when zeroEnds) and bytes: at most MAX_TEXT
   bytes, each printable ASCII or whitespace (space, tab, newline, return).
   Sets SrcLen to the length. *)
PROCEDURE CheckText (zeroEnds: BOOLEAN) ;
VAR
   k, n: CARDINAL ;
   c: CARDINAL ;
   m: Msg ;
BEGIN
   n := SrcLen ;
   IF zeroEnds THEN
      k := 0 ;
      WHILE (k < n) AND (SrcText^[k] # 0C) DO INC (k) END ;
      n := k
   END ;
   SrcLen := n ;
   IF n > MAX_TEXT THEN
      m := "longer than " ;
      AppendWhole (m, MAX_TEXT) ;
      Append (m, " bytes") ;
      Error (m) ;
      RETURN
   END ;
   k := 0 ;
   WHILE k < n DO
      c := ORD (SrcText^[k]) ;
      IF NOT (((c >= 21H) AND (c <= 7EH)) OR (c = 20H) OR (c = 9) OR (c = 10) OR (c = 13)) THEN
         ErrorWhole ("byte ", VAL (LONGINT, k), ": not printable ASCII") ;
         RETURN
      END ;
      INC (k)
   END
END CheckText ;


(* The stream f read whole into Buf (at most MAX_TEXT + 1 bytes: more is
   too long anyway); SrcText and SrcLen are that text. *)
PROCEDURE Slurp (f: ADDRESS) ;
VAR
   n, got: LONGCARD ;
BEGIN
   n := 0 ;
   LOOP
      IF n >= VAL (LONGCARD, BufCap) THEN
         IF BufCap = 0 THEN BufCap := 65536
         ELSIF BufCap > MAX_TEXT DIV 2 THEN BufCap := MAX_TEXT + 1
         ELSE BufCap := 2 * BufCap
         END ;
         Buf := realloc (Buf, VAL (LONGCARD, BufCap)) ;
         IF Buf = NIL THEN FailMsg ("out of memory") END
      END ;
      IF n >= VAL (LONGCARD, BufCap) THEN EXIT END ;       (* MAX_TEXT + 1 bytes: too long *)
      got := fread (ADR (Buf^[n]), 1, VAL (LONGCARD, BufCap) - n, f) ;
      IF got = 0 THEN EXIT END ;
      n := n + got
   END ;
   SrcText := Buf ;
   SrcLen := VAL (CARDINAL, n) ;
   SrcPos := 0
END Slurp ;


(* The next whitespace-delimited word into Tok and TokN; FALSE (and the
   message) when the text ends first.  expect: the word wanted, for the
   message ("" for a value). *)
PROCEDURE Word (expect: ARRAY OF CHAR) : BOOLEAN ;
VAR
   k: CARDINAL ;
   m: Msg ;
BEGIN
   Tok[0] := 0C ;
   TokN := 0 ;
   IF Failed THEN RETURN FALSE END ;
   WHILE (SrcPos < SrcLen) AND (ORD (SrcText^[SrcPos]) <= 32) DO INC (SrcPos) END ;
   IF SrcPos >= SrcLen THEN
      IF expect[0] = 0C THEN
         Error ("ends early")
      ELSE
         m := "ends early (expected '" ;
         Append (m, expect) ;
         Append (m, "')") ;
         Error (m)
      END ;
      RETURN FALSE
   END ;
   k := 0 ;
   WHILE (SrcPos < SrcLen) AND (ORD (SrcText^[SrcPos]) > 32) DO
      IF k < TokLen THEN Tok[k] := SrcText^[SrcPos] END ;
      INC (k) ;
      INC (SrcPos)
   END ;
   TokN := k ;
   IF k < TokLen THEN Tok[k] := 0C ELSE Tok[TokLen] := 0C END ;
   RETURN TRUE
END Word ;


(* Only whitespace is left. *)
PROCEDURE AtEnd () : BOOLEAN ;
BEGIN
   WHILE (SrcPos < SrcLen) AND (ORD (SrcText^[SrcPos]) <= 32) DO INC (SrcPos) END ;
   RETURN SrcPos >= SrcLen
END AtEnd ;


(* Reads the next word, which must be expect. *)
PROCEDURE Expect (expect: ARRAY OF CHAR) ;
VAR
   k: CARDINAL ;
   same: BOOLEAN ;
   m: Msg ;
BEGIN
   IF NOT Word (expect) THEN RETURN END ;
   same := TokN <= HIGH (expect) + 1 ;
   k := 0 ;
   WHILE same AND (k < TokN) DO
      same := Tok[k] = expect[k] ;
      INC (k)
   END ;
   same := same AND ((k > HIGH (expect)) OR (expect[k] = 0C)) ;
   IF NOT same THEN
      m := "expected '" ;
      Append (m, expect) ;
      Append (m, "', found '") ;
      AppendWord (m) ;
      Append (m, "'") ;
      Error (m)
   END
END Expect ;


PROCEDURE Digit (c: CHAR) : BOOLEAN ;
BEGIN
   RETURN (c >= '0') AND (c <= '9')
END Digit ;


(* Tok is a number's word, whole: an optional sign, digits with an
   optional point and more digits (or a point and at least one digit),
   then optionally e or E, an optional sign and at least one digit. *)
PROCEDURE IsNumber () : BOOLEAN ;
VAR
   k, d: CARDINAL ;
BEGIN
   k := 0 ;
   IF (Tok[k] = '+') OR (Tok[k] = '-') THEN INC (k) END ;
   d := 0 ;                                 (* digits of the mantissa *)
   WHILE Digit (Tok[k]) DO INC (k) ; INC (d) END ;
   IF Tok[k] = '.' THEN
      INC (k) ;
      WHILE Digit (Tok[k]) DO INC (k) ; INC (d) END
   END ;
   IF d = 0 THEN RETURN FALSE END ;
   IF (Tok[k] = 'e') OR (Tok[k] = 'E') THEN
      INC (k) ;
      IF (Tok[k] = '+') OR (Tok[k] = '-') THEN INC (k) END ;
      IF NOT Digit (Tok[k]) THEN RETURN FALSE END ;
      WHILE Digit (Tok[k]) DO INC (k) END
   END ;
   RETURN k = TokN
END IsNumber ;


(* The next word as a number: the nearest double, finite. *)
PROCEDURE Num () : REAL ;
VAR
   x: REAL ;
   endp: ADDRESS ;
   m: Msg ;
BEGIN
   IF NOT Word ("") THEN RETURN 0.0 END ;
   IF (TokN > NumLen) OR NOT IsNumber () THEN
      m := "expected a number, found '" ;
      AppendWord (m) ;
      Append (m, "'") ;
      Error (m) ;
      RETURN 0.0
   END ;
   endp := NIL ;
   x := strtod (Tok, endp) ;
   IF (endp # ADR (Tok[TokN])) OR NOT Finite (x) THEN
      m := "number '" ;
      AppendWord (m) ;
      Append (m, "' is beyond a double's range") ;
      Error (m) ;
      RETURN 0.0
   END ;
   RETURN x
END Num ;


(* The next word as an integer: -?[0-9]{1,18}. *)
PROCEDURE ReadLongInt () : LONGINT ;
VAR
   k: CARDINAL ;
   v: LONGINT ;
   neg, ok: BOOLEAN ;
   m: Msg ;
BEGIN
   IF NOT Word ("") THEN RETURN 0 END ;
   k := 0 ;
   neg := Tok[0] = '-' ;
   IF neg THEN k := 1 END ;
   ok := (k < TokN) AND (TokN - k <= IntLen) ;
   v := 0 ;
   WHILE ok AND (k < TokN) DO
      IF Digit (Tok[k]) THEN
         v := v * 10 + VAL (LONGINT, ORD (Tok[k]) - ORD ('0'))
      ELSE
         ok := FALSE
      END ;
      INC (k)
   END ;
   IF NOT ok THEN
      m := "expected an integer, found '" ;
      AppendWord (m) ;
      Append (m, "'") ;
      Error (m) ;
      RETURN 0
   END ;
   IF neg THEN RETURN -v END ;
   RETURN v
END ReadLongInt ;


(* The rules of a body line (docs/simulator.md, "Flat scene checks", 1-8)
   in their order: the first fault is reported. *)
PROCEDURE CheckBody (k: INTEGER; b: BodyRef; poly, fixed, large, nv: LONGINT; tl, tEnd: REAL) ;
VAR
   reach: REAL ;
   m: Msg ;
BEGIN
   IF (poly # 0) AND (poly # 1) THEN BodyError (k, "poly must be 0 or 1") ; RETURN END ;
   IF (fixed # 0) AND (fixed # 1) THEN BodyError (k, "fixed must be 0 or 1") ; RETURN END ;
   IF (large # 0) AND (large # 1) THEN BodyError (k, "large must be 0 or 1") ; RETURN END ;
   IF fixed = 1 THEN
      IF NOT ((b^.invM = 0.0) AND (b^.invI = 0.0)) THEN
         BodyError (k, "a fixed body has inverse mass 0") ; RETURN
      END
   ELSE
      IF NOT Above (b^.invM, 0.0) THEN
         BodyReal (k, "inverse mass ", b^.invM, " must be positive") ; RETURN
      END ;
      IF (poly = 1) AND NOT Above (b^.invI, 0.0) THEN
         BodyReal (k, "inverse inertia ", b^.invI, " must be positive") ; RETURN
      END ;
      IF (poly = 0) AND (b^.invI # 0.0) THEN
         BodyError (k, "a circle has inverse inertia 0") ; RETURN
      END
   END ;
   IF NOT In (b^.e, 0.0, 1.0) THEN BodyReal (k, "restitution ", b^.e, " outside [0, 1]") ; RETURN END ;
   IF NOT AtLeast (b^.mu, 0.0) THEN BodyReal (k, "friction ", b^.mu, " is negative") ; RETURN END ;
   IF poly = 0 THEN
      IF NOT In (b^.r, tl, LENGTH_MAX) THEN
         BodyReal (k, "radius ", b^.r, " outside [tolerance, 1e150]") ; RETURN
      END ;
      IF nv # 0 THEN BodyError (k, "a circle has no vertices") ; RETURN END ;
      IF b^.orbit # 0.0 THEN
         IF NOT In (b^.orbit, tl, LENGTH_MAX) THEN
            BodyReal (k, "orbit radius ", b^.orbit, " outside [tolerance, 1e150]") ; RETURN
         END ;
         IF fixed # 1 THEN BodyError (k, "an orbiting circle must be fixed") ; RETURN END
      END ;
      IF (b^.om # 0.0) AND NOT Above (b^.orbit, 0.0) THEN
         BodyError (k, "a circle turns only about an orbit") ; RETURN
      END
   ELSE
      IF (b^.r # 0.0) OR (b^.orbit # 0.0) THEN BodyError (k, "a polygon has no radius or orbit") ; RETURN END ;
      IF (nv < 3) OR (nv > MAX_VERTICES) THEN
         m := "body " ;
         AppendWhole (m, k) ;
         Append (m, ": ") ;
         AppendWhole (m, nv) ;
         Append (m, " vertices (3 to ") ;
         AppendWhole (m, MAX_VERTICES) ;
         Append (m, ")") ;
         Error (m) ;
         RETURN
      END
   END ;
   IF NOT In (b^.window, 0.0, 0.5) THEN BodyReal (k, "window ", b^.window, " outside [0, 0.5]") ; RETURN END ;
   (* a polygon's radius and orbit are 0 here: bound >= 0 for it *)
   IF NOT In (b^.bound, b^.r + b^.orbit, LENGTH_MAX) THEN
      BodyReal (k, "bound ", b^.bound, " is too small or too large") ; RETURN
   END ;
   reach := (ABS (b^.px) + ABS (b^.py)) + (ABS (b^.vx) + ABS (b^.vy)) * tEnd
            + (ABS (b^.ax) + ABS (b^.ay)) * tEnd * tEnd / 2.0 + b^.bound ;
   IF NOT AtMost (reach, 2.0 * LENGTH_MAX) THEN
      BodyError (k, "reaches more than 2e150 m from the origin by the end") ; RETURN
   END
END CheckBody ;


(* The rules of a polygon's vertices taken together (12-15): each over
   every vertex before the next; its n vertices are Verts^[v0 ..]. *)
PROCEDURE CheckPolygon (k, v0, n: INTEGER; tl: REAL) ;
VAR
   j, p, q, changes: INTEGER ;
   ex, ey, fx, fy, c: REAL ;
   up, last, any: BOOLEAN ;

   PROCEDURE Edge (j: INTEGER; VAR x, y: REAL) ;
   VAR
      q: INTEGER ;
   BEGIN
      q := j + 1 ;
      IF q = n THEN q := 0 END ;
      x := Verts^[v0 + q].lx - Verts^[v0 + j].lx ;
      y := Verts^[v0 + q].ly - Verts^[v0 + j].ly
   END Edge ;

BEGIN
   FOR j := 0 TO n - 1 DO
      Edge (j, ex, ey) ;
      IF NOT AtLeast (ABS (ex) + ABS (ey), tl) THEN
         VertexError (k, j, "edge shorter than the tolerance") ; RETURN
      END
   END ;
   FOR j := 0 TO n - 1 DO
      p := j - 1 ;
      IF p < 0 THEN p := n - 1 END ;
      Edge (p, ex, ey) ;
      Edge (j, fx, fy) ;
      c := ex * fy - ey * fx ;
      IF NOT Above (c, 0.0) THEN
         VertexError (k, j, "not strictly convex (counter-clockwise)") ; RETURN
      END
   END ;
   (* sign changes of the edges' y over j, cyclic, zeros skipped *)
   changes := 0 ;
   any := FALSE ;
   up := FALSE ;
   last := FALSE ;
   FOR j := 0 TO n - 1 DO
      Edge (j, ex, ey) ;
      IF ey # 0.0 THEN
         up := ey > 0.0 ;
         IF any AND (up # last) THEN INC (changes) END ;
         IF NOT any THEN q := j END ;
         any := TRUE ;
         last := up
      END
   END ;
   IF any THEN
      Edge (q, ex, ey) ;             (* the first nonzero one, after the last: the cyclic pair *)
      IF (ey > 0.0) # last THEN INC (changes) END
   END ;
   IF changes # 2 THEN Winds (k, changes DIV 2) ; RETURN END ;
   FOR j := 0 TO n - 1 DO
      Edge (j, ex, ey) ;
      c := Verts^[v0 + j].nx * ey - Verts^[v0 + j].ny * ex ;
      IF NOT Above (c, 0.0) THEN
         VertexError (k, j, "the normal does not point outward") ; RETURN
      END
   END
END CheckPolygon ;


PROCEDURE Winds (k, times: INTEGER) ;
VAR
   m: Msg ;
BEGIN
   m := "body " ;
   AppendWhole (m, k) ;
   Append (m, ": the polygon winds ") ;
   AppendWhole (m, times) ;
   Append (m, " times") ;
   Error (m)
END Winds ;


(* A "body ..." line and its "v" lines into Bodies^[i] (room is there),
   its vertices from Verts^[v0] on (room is made), checked with the scene's
   tolerance tl and end time tEnd, n bodies a cover may name; the number
   of vertices (0 after a fault). *)
PROCEDURE ReadBody (i, v0, n: INTEGER; tl, tEnd: REAL) : INTEGER ;
VAR
   j, k: INTEGER ;
   poly, fixed, large, nv, cover: LONGINT ;
   b: BodyRef ;
   v: Vertex ;
BEGIN
   Expect ("body") ;
   IF Failed THEN RETURN 0 END ;
   b := ADR (Bodies^[i]) ;
   b^.idx := i ;
   poly := ReadLongInt () ;
   fixed := ReadLongInt () ;
   b^.invM := Num () ; b^.invI := Num () ; b^.e := Num () ; b^.mu := Num () ;
   b^.px := Num () ; b^.py := Num () ; b^.vx := Num () ; b^.vy := Num () ;
   b^.ax := Num () ; b^.ay := Num () ;
   b^.ang := Num () ; b^.om := Num () ;
   b^.r := Num () ; b^.orbit := Num () ; b^.ophase := Num () ; b^.bound := Num () ; b^.window := Num () ;
   large := ReadLongInt () ;
   nv := ReadLongInt () ;
   IF Failed THEN RETURN 0 END ;
   CheckBody (i, b, poly, fixed, large, nv, tl, tEnd) ;
   IF Failed THEN RETURN 0 END ;
   b^.polygon := poly = 1 ;
   b^.fixed := fixed = 1 ;
   b^.large := large = 1 ;
   b^.fax := b^.ax ; b^.fay := b^.ay ;
   b^.sup := -1 ; b^.sup_edge := -1 ;
   b^.tx := 0.0 ; b^.ty := 0.0 ; b^.load := 0.0 ; b^.at := 0.0 ;
   b^.v0 := v0 ;
   b^.nv := VAL (INTEGER, nv) ;
   ReserveVerts (v0 + b^.nv) ;
   b := ADR (Bodies^[i]) ;
   FOR j := 0 TO b^.nv - 1 DO
      Expect ("v") ;
      IF Failed THEN RETURN 0 END ;
      v.lx := Num () ; v.ly := Num () ; v.rho := Num () ; v.beta := Num () ;
      v.psi := Num () ; v.h := Num () ; v.s1 := Num () ; v.s2 := Num () ;
      v.nx := Num () ; v.ny := Num () ;
      cover := ReadLongInt () ;
      IF Failed THEN RETURN 0 END ;
      (* lx, ly and rho (the vertex), h, s1 and s2 (its edge's line and extent: each at most a vertex's
         distance, twice the bound leaving room for their rounding) *)
      IF NOT (In (v.lx, -b^.bound, b^.bound) AND In (v.ly, -b^.bound, b^.bound) AND In (v.rho, 0.0, b^.bound)
              AND In (v.h, -2.0 * b^.bound, 2.0 * b^.bound) AND In (v.s1, -2.0 * b^.bound, 2.0 * b^.bound)
              AND In (v.s2, -2.0 * b^.bound, 2.0 * b^.bound)) THEN
         VertexError (i, j, "outside the bound") ; RETURN 0
      END ;
      IF NOT In (v.nx * v.nx + v.ny * v.ny - 1.0, -1.0E-9, 1.0E-9) THEN
         VertexError (i, j, "the normal is not a unit vector") ; RETURN 0
      END ;
      IF NOT ((cover = -1) OR ((cover >= 0) AND (cover < VAL (LONGINT, n)) AND (cover # VAL (LONGINT, i)))) THEN
         CoverError (i, j, cover, "is not a body") ;
         RETURN 0
      END ;
      v.cover := VAL (INTEGER, cover) ;
      Verts^[v0 + j] := v
   END ;
   IF b^.polygon THEN
      CheckPolygon (i, v0, b^.nv, tl) ;
      IF Failed THEN RETURN 0 END
   END ;
   b^.tb := 0.0 ;
   b^.stamp := 0 ;
   b^.cx := 0 ;
   b^.cy := 0 ;
   b^.gone := FALSE ;
   b^.asleep := FALSE ;
   b^.island := -1 ;
   b^.non := 0 ;
   FOR k := 0 TO RestSlots - 1 DO b^.rc[k].other1 := 0 END ;
   b^.placed := FALSE ;
   b^.seen := 0 ;
   b^.carry := 0 ;
   b^.rest := -1 ;
   RETURN b^.nv
END ReadBody ;


(* Error ("body k vertex j: cover c " ++ why). *)
PROCEDURE CoverError (k, j: INTEGER; c: LONGINT; why: ARRAY OF CHAR) ;
VAR
   m: Msg ;
BEGIN
   m := "body " ;
   AppendWhole (m, k) ;
   Append (m, " vertex ") ;
   AppendWhole (m, j) ;
   Append (m, ": cover ") ;
   AppendWhole (m, c) ;
   Append (m, " ") ;
   Append (m, why) ;
   Error (m)
END CoverError ;


(* Reads the scene from the text (SrcText^[0 .. SrcLen - 1]). *)
PROCEDURE Read ;
VAR
   i, j, k: INTEGER ;
   version, same, nx, ny, n, nIn, body, mode, cells: LONGINT ;
   dt: REAL ;
   inp: Input ;
   removedBy: POINTER TO ARRAY [0..MAX_BODIES - 1] OF INTEGER ;
   m: Msg ;
BEGIN
   Expect ("m2c-scene") ;
   version := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF version # 1 THEN ErrorWhole ("unknown version ", version, "") ; RETURN END ;
   Expect ("end") ; EndT := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT (Above (EndT, 0.0) AND AtMost (EndT, LENGTH_MAX)) THEN
      ErrorReal ("end ", EndT, " outside (0, 1e150]") ; RETURN
   END ;
   Expect ("frame") ; FrameDt := Num () ;
   IF Failed THEN RETURN END ;
   dt := FrameDt ;
   IF NOT ((dt = 0.0) OR (Above (dt, 0.0) AND AtMost (EndT / dt, 1.0E12))) THEN
      IF Above (dt, 0.0) THEN
         ErrorReal ("frame ", dt, " gives more than 1e12 frames")
      ELSE
         ErrorReal ("frame ", dt, " is negative")
      END ;
      RETURN
   END ;
   Expect ("tolerance") ; Tol := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT In (Tol, LENGTH_MIN, LENGTH_MAX) THEN
      ErrorReal ("tolerance ", Tol, " outside [1e-150, 1e150]") ; RETURN
   END ;
   Expect ("rest_speed") ; RestSpeed := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT AtLeast (RestSpeed, 0.0) THEN
      ErrorReal ("rest_speed ", RestSpeed, " is negative") ; RETURN
   END ;
   IF NOT AtMost (RestSpeed, LENGTH_MAX) THEN       (* its square must not overflow *)
      ErrorReal ("rest_speed ", RestSpeed, " beyond 1e150") ; RETURN
   END ;
   Expect ("window_angle") ; Alpha := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT (Above (Alpha, 0.0) AND AtMost (Alpha, 0.5)) THEN
      ErrorReal ("window_angle ", Alpha, " outside (0, 0.5]") ; RETURN
   END ;
   Expect ("max_same_time") ; same := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF same < 1 THEN ErrorWhole ("max_same_time ", same, " is less than 1") ; RETURN END ;
   MaxSame := same ;
   Expect ("max_events") ; same := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF same < 1 THEN ErrorWhole ("max_events ", same, " is less than 1") ; RETURN END ;
   MaxEvents := same ;
   Expect ("grid") ;
   GridX0 := Num () ; GridY0 := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT (In (GridX0, -LENGTH_MAX, LENGTH_MAX) AND In (GridY0, -LENGTH_MAX, LENGTH_MAX)) THEN
      Error ("grid origin beyond 1e150") ; RETURN
   END ;
   CellW := Num () ; CellH := Num () ;
   IF Failed THEN RETURN END ;
   IF NOT In (CellW, LENGTH_MIN, LENGTH_MAX) THEN
      ErrorReal ("grid cell ", CellW, " outside [1e-150, 1e150]") ; RETURN
   END ;
   IF NOT In (CellH, LENGTH_MIN, LENGTH_MAX) THEN
      ErrorReal ("grid cell ", CellH, " outside [1e-150, 1e150]") ; RETURN
   END ;
   nx := ReadLongInt () ; ny := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF (nx < 1) OR (ny < 1) THEN
      m := "grid of " ;
      AppendWhole (m, nx) ;
      Append (m, " x ") ;
      AppendWhole (m, ny) ;
      Append (m, " cells") ;
      Error (m) ;
      RETURN
   END ;
   GridMargin := Num () ;
   IF Failed THEN RETURN END ;
   IF CellH < CellW THEN HalfCell := 0.5 * CellH ELSE HalfCell := 0.5 * CellW END ;
   IF NOT (AtLeast (GridMargin, 0.0) AND (GridMargin < HalfCell)) THEN
      ErrorReal ("grid margin ", GridMargin, " m outside [0, half a cell)") ; RETURN
   END ;
   Expect ("bodies") ;
   n := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF (n < 1) OR (n > MAX_BODIES) THEN
      m[0] := 0C ;
      AppendWhole (m, n) ;
      Append (m, " bodies (1 to ") ;
      AppendWhole (m, MAX_BODIES) ;
      Append (m, ")") ;
      Error (m) ;
      RETURN
   END ;
   cells := 4 * n ;
   IF cells < 16 THEN cells := 16 END ;
   IF (nx > cells) OR (ny > cells DIV nx) THEN    (* nx ny > cells, without forming nx ny *)
      m := "grid of " ;
      AppendWhole (m, nx) ;
      Append (m, " x ") ;
      AppendWhole (m, ny) ;
      Append (m, " cells for ") ;
      AppendWhole (m, n) ;
      Append (m, " bodies (at most max(16, 4 x bodies) cells)") ;
      Error (m) ;
      RETURN
   END ;
   GridNX := VAL (INTEGER, nx) ;
   GridNY := VAL (INTEGER, ny) ;
   NVerts := 0 ;
   FOR i := 0 TO VAL (INTEGER, n) - 1 DO
      Reserve (i + 1) ;
      NVerts := NVerts + ReadBody (i, NVerts, VAL (INTEGER, n), Tol, EndT) ;
      IF Failed THEN RETURN END ;
      NBodies := i + 1
   END ;
   (* a cover is a fixed body: known once every body is read *)
   FOR i := 0 TO NBodies - 1 DO
      FOR j := 0 TO Bodies^[i].nv - 1 DO
         k := Verts^[Bodies^[i].v0 + j].cover ;
         IF (k >= 0) AND NOT Bodies^[k].fixed THEN
            CoverError (i, j, k, "is not a fixed body") ; RETURN
         END
      END
   END ;
   Expect ("inputs") ;
   nIn := ReadLongInt () ;
   IF Failed THEN RETURN END ;
   IF (nIn < 0) OR (nIn > MAX_INPUTS) THEN
      m[0] := 0C ;
      AppendWhole (m, nIn) ;
      Append (m, " inputs (0 to ") ;
      AppendWhole (m, MAX_INPUTS) ;
      Append (m, ")") ;
      Error (m) ;
      RETURN
   END ;
   removedBy := NIL ;
   FOR i := 0 TO VAL (INTEGER, nIn) - 1 DO
      Expect ("input") ;
      inp.t := Num () ;
      body := ReadLongInt () ;
      mode := ReadLongInt () ;
      inp.vx := Num () ;
      inp.vy := Num () ;
      IF Failed THEN free (removedBy) ; RETURN END ;
      m := "input " ;
      AppendWhole (m, i) ;
      IF NOT In (inp.t, 0.0, EndT) THEN
         Append (m, ": time ") ;
         AppendReal (m, inp.t) ;
         Append (m, " outside [0, end]") ;
         Error (m)
      ELSIF (body < 0) OR (body >= VAL (LONGINT, NBodies)) THEN
         ErrorWhole ("input on body ", body, ", which does not exist")
      ELSIF (mode < 0) OR (mode > 4) THEN
         ErrorWhole ("unknown input mode ", mode, "")
      ELSIF Bodies^[VAL (INTEGER, body)].fixed AND (mode # 4)
            AND NOT ((mode = 0) AND Bodies^[VAL (INTEGER, body)].polygon
                     AND (Bodies^[VAL (INTEGER, body)].om = 0.0)) THEN
         (* a fixed body takes removal (4), or set_velocity (0) when it is a
            polygon that does not turn *)
         Append (m, " on fixed body ") ;
         AppendWhole (m, body) ;
         Append (m, ": only set_velocity (on a polygon that does not turn) or remove") ;
         Error (m)
      ELSIF (removedBy # NIL) AND (removedBy^[VAL (INTEGER, body)] >= 0) THEN
         Append (m, ": body ") ;
         AppendWhole (m, body) ;
         Append (m, " was removed by input ") ;
         AppendWhole (m, removedBy^[VAL (INTEGER, body)]) ;
         Error (m)
      ELSIF (mode = 4) AND ((inp.vx # 0.0) OR (inp.vy # 0.0)) THEN
         Append (m, ": a removal has no vector") ;
         Error (m)
      ELSIF (mode = 3) AND NOT In (ABS (inp.vx) + ABS (inp.vy), 0.0, LENGTH_MAX) THEN
         Append (m, ": teleport beyond 1e150 m") ;
         Error (m)
      END ;
      IF Failed THEN free (removedBy) ; RETURN END ;
      IF mode = 4 THEN
         IF removedBy = NIL THEN
            removedBy := realloc (NIL, VAL (LONGCARD, NBodies) * VAL (LONGCARD, SIZE (INTEGER))) ;
            IF removedBy = NIL THEN FailMsg ("out of memory") END ;
            FOR k := 0 TO NBodies - 1 DO removedBy^[k] := -1 END
         END ;
         removedBy^[VAL (INTEGER, body)] := i
      END ;
      inp.body := VAL (INTEGER, body) ;
      inp.mode := VAL (INTEGER, mode) ;
      ReserveInputs (i + 1) ;
      Inputs^[i] := inp ;
      NInputs := i + 1
   END ;
   free (removedBy) ;
   Expect ("end") ;
   IF Failed THEN RETURN END ;
   IF NOT AtEnd () AND Word ("") THEN
      m := "unexpected '" ;
      AppendWord (m) ;
      Append (m, "' after the end") ;
      Error (m)
   END
END Read ;


(* Reads the scene from the text set up (SrcText, SrcLen); afterwards, no
   text. *)
PROCEDURE Load (zeroEnds: BOOLEAN) : BOOLEAN ;
BEGIN
   What := "scene" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   NBodies := 0 ;
   NVerts := 0 ;
   NInputs := 0 ;
   SrcPos := 0 ;
   CheckText (zeroEnds) ;
   IF NOT Failed THEN Read END ;
   SrcText := NIL ;
   SrcLen := 0 ;
   SrcPos := 0 ;
   RETURN NOT Failed
END Load ;


PROCEDURE ReadText (text: ADDRESS; len: CARDINAL) : BOOLEAN ;
BEGIN
   SrcText := text ;
   SrcLen := len ;
   RETURN Load (TRUE)
END ReadText ;


PROCEDURE ReadFile (path: ARRAY OF CHAR) : BOOLEAN ;
VAR
   f: ADDRESS ;
BEGIN
   f := fopen (path, "r") ;
   IF f = NIL THEN
      Failed := TRUE ;
      Message := "cannot open the scene file '" ;
      Append (Message, path) ;
      Append (Message, "'") ;
      RETURN FALSE
   END ;
   Slurp (f) ;
   IF fclose (f) # 0 THEN END ;
   RETURN Load (FALSE)
END ReadFile ;


PROCEDURE ReadStdin () : BOOLEAN ;
VAR
   f: ADDRESS ;
BEGIN
   f := fdopen (0, "r") ;
   IF f = NIL THEN
      Failed := TRUE ;
      Message := "cannot read standard input" ;
      RETURN FALSE
   END ;
   Slurp (f) ;
   RETURN Load (FALSE)
END ReadStdin ;


PROCEDURE ReadBodyText (text: ADDRESS; len: CARDINAL; i, v0: INTEGER; VAR nv: INTEGER) : BOOLEAN ;
VAR
   m: Msg ;
BEGIN
   What := "add_body" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   SrcText := text ;
   SrcLen := len ;
   SrcPos := 0 ;
   nv := 0 ;
   CheckText (TRUE) ;
   IF NOT Failed THEN
      Reserve (i + 1) ;
      nv := ReadBody (i, v0, i, Tol, EndT)
   END ;
   IF NOT Failed THEN
      (* nothing may follow: a word there is an error, the end is not *)
      IF NOT AtEnd () AND Word ("") THEN
         m := "unexpected '" ;
         AppendWord (m) ;
         Append (m, "' after the body") ;
         Error (m)
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
   What := "scene" ;
   Failed := FALSE ;
   Message[0] := 0C ;
   Tok[0] := 0C ;
   TokN := 0 ;
   Buf := NIL ;
   BufCap := 0 ;
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
