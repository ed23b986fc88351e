MODULE SimOutCheck ;

(* Checks SimOut.Real against the C library's printf("%.17g"): doubles with
   random bit patterns (every exponent), random values of the magnitudes a
   trace holds, near-halfway and power-of-ten neighbours, zeros, infinities.
   Writes the count of numbers checked, how many the fast path decided, and
   every mismatch; exit status 1 on a mismatch.  Build and run (as
   tests/simulator/test_m2_sim_out.py does):
     gm2 -fiso -fcpp -Wall -Werror -O2 -ffp-contract=off -I runtimes/m2 \
         -I runtimes/m2/src runtimes/m2/SimOutCheck.mod SimOut.o -o sim_out_check -lm
   (SimOut.o compiled from runtimes/m2/SimOut.mod).  Argument-free: the
   seed and counts are fixed, so a run is reproducible; Count = 300000
   checks 1,502,407 numbers in a few seconds (Count = 4000000 checks
   20,002,407 numbers, 14,645,151 of them by the fast path). *)

FROM SYSTEM IMPORT ADR, CAST ;
FROM cstdio IMPORT printf ;
FROM SimC IMPORT snprintf, exit ;
FROM SimOut IMPORT Real, Take, FastDigits ;

CONST
   Count = 300000 ;
   Two32 = 4294967296 ;
   Two52 = 4503599627370496 ;

VAR
   state, mul, inc, two63: LONGCARD ;
   bad, fast, checked: INTEGER ;


(* 64 random bits: the high halves of two steps of a 64-bit LCG. *)
PROCEDURE Next () : LONGCARD ;
VAR
   h: LONGCARD ;
BEGIN
   state := state * mul + inc ;
   h := state DIV Two32 ;
   state := state * mul + inc ;
   RETURN h * Two32 + state DIV Two32
END Next ;


PROCEDURE Check (z: REAL) ;
VAR
   a, b: ARRAY [0..79] OF CHAR ;
   n, k, x10: INTEGER ;
   d: LONGCARD ;
   same: BOOLEAN ;
BEGIN
   INC (checked) ;
   IF FastDigits (z, d, x10) THEN INC (fast) END ;
   Real (z) ;
   Take (a) ;
   n := snprintf (ADR (b), 80, "%.17g", z) ;
   IF z # z THEN b := "nan" END ;
   same := TRUE ;
   k := 0 ;
   WHILE same AND (k < 79) AND ((a[k] # 0C) OR (b[k] # 0C)) DO
      same := a[k] = b[k] ;
      INC (k)
   END ;
   IF NOT same THEN
      INC (bad) ;
      IF bad <= 20 THEN
         printf ("mismatch: SimOut %s, printf %s (%d)\n", ADR (a), ADR (b), n)
      END
   END
END Check ;


VAR
   i, j: INTEGER ;
   u: LONGCARD ;
   x, y: REAL ;
BEGIN
   state := 88172645463325252 ;
   mul := VAL (LONGCARD, 6364136223846793005) ;
   inc := VAL (LONGCARD, 1442695040888963407) ;
   two63 := VAL (LONGCARD, 4611686018427387904) * 2 ;
   bad := 0 ;
   fast := 0 ;
   checked := 0 ;
   Check (0.0) ;
   Check (-0.0) ;
   Check (1.0 / 0.0 - 1.0 / 0.0) ;
   FOR i := 1 TO Count DO
      u := Next () ;
      Check (CAST (REAL, u)) ;                        (* any bit pattern *)
      (* magnitudes of a trace: sign, mantissa, exponent within 2^-70..2^40 *)
      u := (Next () MOD Two52) + (953 + Next () MOD 110) * Two52 ;
      IF ODD (i) THEN u := u + two63 END ;
      x := CAST (REAL, u) ;
      Check (x) ;
      (* short decimals and their neighbours, as times and positions are *)
      y := VAL (REAL, VAL (INTEGER, Next () MOD 2000000) - 1000000) / 1000.0 ;
      Check (y) ;
      u := CAST (LONGCARD, y) ;
      Check (CAST (REAL, u + 1)) ;
      Check (CAST (REAL, u - 1))
   END ;
   (* powers of ten and their neighbours *)
   x := 1.0E-300 ;
   FOR j := -300 TO 300 DO
      u := CAST (LONGCARD, x) ;
      Check (x) ;
      Check (CAST (REAL, u + 1)) ;
      Check (CAST (REAL, u - 1)) ;
      Check (-x) ;
      x := x * 10.0
   END ;
   printf ("%d numbers checked, %d by the fast path, %d mismatches\n", checked, fast, bad) ;
   IF bad > 0 THEN exit (1) END
END SimOutCheck.
