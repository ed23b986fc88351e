IMPLEMENTATION MODULE RootsGsl ;

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM Roots IMPORT MaxDegree, Scale, IsFinite ;
FROM Gsl IMPORT gsl_poly_complex_workspace_alloc, gsl_poly_complex_solve,
                gsl_set_error_handler_off ;

VAR
   work: ARRAY [0..MaxDegree] OF ADDRESS ;   (* cached workspaces by degree *)
   i0: INTEGER ;
   old: ADDRESS ;


PROCEDURE SmallestRoot (VAR c: ARRAY OF REAL; degree: INTEGER; lo, hi: REAL;
                        VAR t: REAL) : BOOLEAN ;
VAR
   a: ARRAY [0..MaxDegree] OF REAL ;
   z: ARRAY [0..2 * MaxDegree - 1] OF REAL ;
   n, i: INTEGER ;
   re, im, scale, best: REAL ;
   found: BOOLEAN ;
BEGIN
   IF (degree < 0) OR (degree > MaxDegree) OR (degree > VAL (INTEGER, HIGH (c)))
   THEN
      RETURN FALSE
   END ;
   IF (NOT (IsFinite (lo) AND IsFinite (hi))) OR (NOT (lo < hi)) THEN RETURN FALSE END ;
   FOR i := 0 TO degree DO
      IF NOT IsFinite (c[i]) THEN RETURN FALSE END
   END ;
   n := degree ;
   WHILE (n >= 0) AND (c[n] = 0.0) DO
      DEC (n)
   END ;
   IF n <= 0 THEN RETURN FALSE END ;
   n := Scale (c, n, a) ;
   IF n <= 0 THEN RETURN FALSE END ;
   IF work[n] = NIL
   THEN
      work[n] := gsl_poly_complex_workspace_alloc (VAL (LONGCARD, n + 1)) ;
      IF work[n] = NIL THEN RETURN FALSE END
   END ;
   IF gsl_poly_complex_solve (ADR (a), VAL (LONGCARD, n + 1), work[n], ADR (z)) # 0
   THEN
      RETURN FALSE
   END ;
   found := FALSE ;
   best := 0.0 ;
   FOR i := 0 TO n - 1 DO
      re := z[2 * i] ;
      im := z[2 * i + 1] ;
      scale := ABS (re) ;
      IF scale < 1.0 THEN scale := 1.0 END ;
      IF (ABS (im) <= 1.0E-7 * scale) AND (lo < re) AND (re <= hi) AND ((NOT found) OR (re < best))
      THEN
         best := re ;
         found := TRUE
      END
   END ;
   IF found THEN t := best + 0.0 END ;
   RETURN found
END SmallestRoot ;


BEGIN
   FOR i0 := 0 TO MaxDegree DO
      work[i0] := NIL
   END ;
   old := gsl_set_error_handler_off ()
END RootsGsl.
