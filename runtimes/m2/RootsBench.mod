MODULE RootsBench ;

(* Benchmark driver of the Modula-2 runtime.  Standard input: a first line
   "bench m2|gsl REPS", then wire lines as the testee reads (Wire.def).
   Polynomials are grouped by degree and each group is solved REPS times
   in-process, each pass timed with CLOCK_MONOTONIC.  Prints per degree:
   "DEGREE MEDIAN_NS_PER_SOLVE FOUND".  Bad input (a header other than that,
   a line that is not a roots case, more than MaxPer polynomials of a degree)
   is an error on standard error naming the line, exit status 2, as
   m2c_bench: no case is dropped silently. *)

FROM Wire IMPORT Case, ReadCase, WriteString, WriteLn ;
FROM CTime IMPORT timespec, clock_gettime ;
FROM CMath IMPORT putchar, getchar, exit ;
IMPORT Roots, RootsGsl, StdChans, TextIO ;

CONST
   MaxPer = 2000 ;   (* polynomials kept per degree *)
   MaxReps = 1000 ;

TYPE
   Poly = RECORD
      lo, hi: REAL ;
      c: ARRAY [0..Roots.MaxDegree] OF REAL ;
   END ;

VAR
   polys: ARRAY [0..Roots.MaxDegree] OF ARRAY [0..MaxPer - 1] OF Poly ;
   counts: ARRAY [0..Roots.MaxDegree] OF INTEGER ;
   times: ARRAY [0..MaxReps - 1] OF REAL ;
   k: Case ;
   gsl: BOOLEAN ;
   reps, deg, i, r, j, found, np, line: INTEGER ;
   sum, x: REAL ;


PROCEDURE WriteIntTo (v: INTEGER) ;
VAR
   dig: ARRAY [0..19] OF CHAR ;
   n: INTEGER ;
BEGIN
   n := 0 ;
   REPEAT
      dig[n] := CHR (48 + v MOD 10) ;
      v := v DIV 10 ;
      INC (n)
   UNTIL v = 0 ;
   WHILE n > 0 DO
      DEC (n) ;
      TextIO.WriteChar (StdChans.ErrChan (), dig[n])
   END
END WriteIntTo ;


PROCEDURE WriteInt (v: INTEGER) ;
VAR
   dig: ARRAY [0..19] OF INTEGER ;
   n, rr: INTEGER ;
BEGIN
   n := 0 ;
   REPEAT
      dig[n] := v MOD 10 ;
      v := v DIV 10 ;
      INC (n)
   UNTIL v = 0 ;
   WHILE n > 0 DO
      DEC (n) ;
      rr := putchar (48 + dig[n])
   END
END WriteInt ;


PROCEDURE Fail (line: INTEGER; msg: ARRAY OF CHAR) ;
BEGIN
   TextIO.WriteString (StdChans.ErrChan (), "roots_bench: line ") ;
   WriteIntTo (line) ;
   TextIO.WriteString (StdChans.ErrChan (), ": ") ;
   TextIO.WriteString (StdChans.ErrChan (), msg) ;
   TextIO.WriteChar (StdChans.ErrChan (), CHR (10)) ;
   exit (2)
END Fail ;


PROCEDURE Same (a, b: ARRAY OF CHAR) : BOOLEAN ;
VAR
   k: CARDINAL ;
BEGIN
   k := 0 ;
   LOOP
      IF (k > HIGH (a)) OR (a[k] = 0C) THEN RETURN (k > HIGH (b)) OR (b[k] = 0C) END ;
      IF (k > HIGH (b)) OR (a[k] # b[k]) THEN RETURN FALSE END ;
      INC (k)
   END
END Same ;


(* The header line "bench m2|gsl REPS" (1 <= REPS <= MaxReps), read to its
   end with getchar before Wire reads anything: a header without REPS must
   not take its count from the first case's line. *)
PROCEDURE ReadHeader (VAR gsl: BOOLEAN; VAR reps: INTEGER) ;
VAR
   w: ARRAY [0..2] OF ARRAY [0..15] OF CHAR ;
   nw, k, ch: INTEGER ;
   ok: BOOLEAN ;
BEGIN
   nw := 0 ;
   k := 0 ;
   ok := TRUE ;
   ch := getchar () ;
   WHILE (ch >= 0) AND (ch # 10) DO
      IF ch > 32 THEN
         IF k = 0 THEN INC (nw) END ;
         IF (nw > 3) OR (k >= 15) THEN
            ok := FALSE
         ELSE
            w[nw - 1][k] := CHR (ch) ;
            INC (k) ;
            w[nw - 1][k] := 0C
         END
      ELSE
         k := 0
      END ;
      ch := getchar ()
   END ;
   ok := ok AND (nw = 3) AND Same (w[0], "bench") AND (Same (w[1], "m2") OR Same (w[1], "gsl")) ;
   reps := 0 ;
   k := 0 ;
   WHILE ok AND (w[2][k] # 0C) DO
      ok := (w[2][k] >= '0') AND (w[2][k] <= '9') AND (reps <= MaxReps) ;
      reps := reps * 10 + VAL (INTEGER, ORD (w[2][k]) - ORD ('0')) ;
      INC (k)
   END ;
   IF (NOT ok) OR (reps < 1) OR (reps > MaxReps) THEN
      Fail (1, "expected the header 'bench m2|gsl REPS' with 1 <= REPS <= 1000")
   END ;
   gsl := Same (w[1], "gsl")
END ReadHeader ;


PROCEDURE Elapsed (VAR a, b: timespec) : REAL ;
BEGIN
   RETURN VAL (REAL, b.tv_sec - a.tv_sec) * 1.0E9 + VAL (REAL, b.tv_nsec - a.tv_nsec)
END Elapsed ;


(* One timed pass over the np polynomials of degree deg: ns per solve; the
   number found and the sum of the roots into found and sum.  A procedure of
   its own, as m2c_bench's pass: its counters are locals in registers, where
   the module body's are global variables read and written on every call. *)
PROCEDURE Pass (gsl: BOOLEAN; deg, np: INTEGER; VAR found: INTEGER; VAR sum: REAL) : REAL ;
VAR
   t0, t1: timespec ;
   t, s: REAL ;
   i, nf, rc: INTEGER ;
BEGIN
   nf := 0 ;
   s := 0.0 ;
   rc := clock_gettime (1, t0) ;
   FOR i := 0 TO np - 1 DO
      IF gsl
      THEN
         IF RootsGsl.SmallestRoot (polys[deg][i].c, deg, polys[deg][i].lo, polys[deg][i].hi, t) THEN
            INC (nf) ;
            s := s + t
         END
      ELSIF Roots.SmallestRoot (polys[deg][i].c, deg, polys[deg][i].lo, polys[deg][i].hi, t) THEN
         INC (nf) ;
         s := s + t
      END
   END ;
   rc := clock_gettime (1, t1) ;
   found := nf ;
   sum := s ;
   RETURN Elapsed (t0, t1) / VAL (REAL, np)
END Pass ;


BEGIN
   ReadHeader (gsl, reps) ;
   FOR deg := 0 TO Roots.MaxDegree DO counts[deg] := 0 END ;
   line := 1 ;
   WHILE ReadCase (k) DO
      INC (line) ;
      IF (k.count < 1) OR (k.count > Roots.MaxDegree + 1) THEN
         Fail (line, "expected a roots case with 1 to 17 coefficients")
      END ;
      deg := k.count - 1 ;
      IF counts[deg] >= MaxPer THEN
         Fail (line, "more than 2000 polynomials of one degree")
      END ;
      polys[deg][counts[deg]].lo := k.lo ;
      polys[deg][counts[deg]].hi := k.hi ;
      FOR i := 0 TO deg DO
         polys[deg][counts[deg]].c[i] := k.c[i]
      END ;
      INC (counts[deg])
   END ;
   FOR deg := 0 TO Roots.MaxDegree DO
      np := counts[deg] ;
      IF np > 0 THEN
         found := 0 ;
         sum := 0.0 ;
         FOR r := -1 TO reps - 1 DO
            x := Pass (gsl, deg, np, found, sum) ;
            IF r >= 0 THEN times[r] := x END
         END ;
         (* insertion sort for the median *)
         FOR i := 1 TO reps - 1 DO
            x := times[i] ;
            j := i - 1 ;
            WHILE (j >= 0) AND (times[j] > x) DO
               times[j + 1] := times[j] ;
               DEC (j)
            END ;
            times[j + 1] := x
         END ;
         x := times[reps DIV 2] ;
         WriteInt (deg) ;
         WriteString (" ") ;
         WriteInt (TRUNC (x)) ;
         WriteString (".") ;
         i := TRUNC ((x - VAL (REAL, TRUNC (x))) * 1000.0) ;
         IF i < 100 THEN WriteString ("0") END ;
         IF i < 10 THEN WriteString ("0") END ;
         WriteInt (i) ;
         WriteString (" ") ;
         WriteInt (found) ;
         WriteLn
      END
   END
END RootsBench.
