MODULE RootsBench ;

(* Benchmark driver of the Modula-2 runtime.  Standard input: a first line
   "bench m2|gsl REPS", then wire lines as the testee reads (Wire.def).
   Polynomials are grouped by degree and each group is solved REPS times
   in-process, each pass timed with CLOCK_MONOTONIC.  Prints per degree:
   "DEGREE MEDIAN_NS_PER_SOLVE FOUND". *)

FROM Wire IMPORT Case, ReadCase, ReadToken, WriteString, WriteLn ;
FROM CTime IMPORT timespec, clock_gettime ;
FROM CMath IMPORT putchar ;
IMPORT Roots, RootsGsl ;

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
   tok: ARRAY [0..63] OF CHAR ;
   gsl, found1: BOOLEAN ;
   reps, deg, i, r, j, found, np: INTEGER ;
   t, sum, x: REAL ;
   t0, t1: timespec ;


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


PROCEDURE Elapsed (VAR a, b: timespec) : REAL ;
BEGIN
   RETURN VAL (REAL, b.tv_sec - a.tv_sec) * 1.0E9 + VAL (REAL, b.tv_nsec - a.tv_nsec)
END Elapsed ;


BEGIN
   reps := 0 ;
   gsl := FALSE ;
   IF ReadToken (tok) AND ReadToken (tok) THEN
      gsl := (tok[0] = 'g') ;
      IF ReadToken (tok) THEN
         i := 0 ;
         WHILE (tok[i] >= '0') AND (tok[i] <= '9') DO
            reps := reps * 10 + VAL (INTEGER, ORD (tok[i]) - ORD ('0')) ;
            INC (i)
         END
      END
   END ;
   IF (reps < 1) OR (reps > MaxReps) THEN reps := 21 END ;
   FOR deg := 0 TO Roots.MaxDegree DO counts[deg] := 0 END ;
   WHILE ReadCase (k) DO
      IF (k.count >= 1) AND (counts[k.count - 1] < MaxPer) THEN
         deg := k.count - 1 ;
         polys[deg][counts[deg]].lo := k.lo ;
         polys[deg][counts[deg]].hi := k.hi ;
         FOR i := 0 TO deg DO
            polys[deg][counts[deg]].c[i] := k.c[i]
         END ;
         INC (counts[deg])
      END
   END ;
   FOR deg := 0 TO Roots.MaxDegree DO
      np := counts[deg] ;
      IF np > 0 THEN
         found := 0 ;
         sum := 0.0 ;
         FOR r := -1 TO reps - 1 DO
            found := 0 ;
            sum := 0.0 ;
            i := clock_gettime (1, t0) ;
            FOR i := 0 TO np - 1 DO
               IF gsl THEN
                  found1 := RootsGsl.SmallestRoot (polys[deg][i].c, deg, polys[deg][i].lo, polys[deg][i].hi, t)
               ELSE
                  found1 := Roots.SmallestRoot (polys[deg][i].c, deg, polys[deg][i].lo, polys[deg][i].hi, t)
               END ;
               IF found1 THEN
                  INC (found) ;
                  sum := sum + t
               END
            END ;
            i := clock_gettime (1, t1) ;
            IF r >= 0 THEN times[r] := Elapsed (t0, t1) / VAL (REAL, np) END
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
