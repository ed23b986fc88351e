IMPLEMENTATION MODULE Roots ;

(* The root solver of docs/roots.md, transcribed operation for operation from
   the C runtime (runtimes/c/src); values are in the coefficients' units and
   x, t in the caller's time unit. *)

FROM CMath IMPORT sqrt, frexp, ldexp ;

CONST
   N1 = MaxDegree + 1 ;
   Splitter = 134217729.0 ;   (* 2^27 + 1, Veltkamp splitting constant *)
   MaxIt = 100 ;              (* bracketed Newton step limit *)

TYPE
   Coeffs = ARRAY [0..MaxDegree] OF REAL ;

VAR
   Eps,                       (* 2^-52, spacing of doubles at 1 *)
   Tiny,                      (* 2^-1000, floor of the touching bound *)
   Sixteenth,                 (* 2^-16, bisection step from an end at 0 *)
   NewtonTol: REAL ;          (* 2^-30: an accepted Newton step this small (relative) has converged *)


PROCEDURE IsFinite (x: REAL) : BOOLEAN ;
BEGIN
   RETURN (x - x) = 0.0
END IsFinite ;


(* Error-free product a*b = p + e (Dekker, no FMA). *)
PROCEDURE TwoProd (a, b: REAL; VAR p, e: REAL) ;
VAR
   t, ah, al, bh, bl: REAL ;
BEGIN
   p := a * b ;
   t := Splitter * a ;
   ah := t - (t - a) ;
   al := a - ah ;
   t := Splitter * b ;
   bh := t - (t - b) ;
   bl := b - bh ;
   e := ((ah * bh - p) + ah * bl + al * bh) + al * bl
END TwoProd ;


(* p(x) by compensated Horner. *)
PROCEDURE CompHorner (VAR a: Coeffs; n: INTEGER; x: REAL) : REAL ;
VAR
   s, c, p, pe, ai, z, se: REAL ;
   i: INTEGER ;
BEGIN
   s := a[n] ;
   c := 0.0 ;
   FOR i := n - 1 TO 0 BY -1 DO
      TwoProd (s, x, p, pe) ;
      ai := a[i] ;
      s := p + ai ;
      z := s - p ;
      se := (p - (s - z)) + (ai - z) ;
      c := c * x + (pe + se)
   END ;
   RETURN s + c
END CompHorner ;


(* Sign of p(x): -1, 0 (zero within the compensated bound), +1. *)
PROCEDURE SignTop (VAR a: Coeffs; n: INTEGER; x: REAL) : INTEGER ;
VAR
   ax, v, pt, r, bound, nf: REAL ;
   i: INTEGER ;
BEGIN
   ax := ABS (x) ;
   v := a[n] ;
   pt := ABS (v) ;
   FOR i := n - 1 TO 0 BY -1 DO
      v := v * x + a[i] ;
      pt := pt * ax + ABS (a[i])
   END ;
   nf := VAL (REAL, n) ;
   IF ABS (v) > 2.0 * nf * Eps * pt
   THEN
      IF v > 0.0 THEN RETURN 1 ELSE RETURN -1 END
   END ;
   r := CompHorner (a, n, x) ;
   bound := (2.0 * nf * Eps) * (2.0 * nf * Eps) * pt + Tiny ;
   IF ABS (r) <= bound
   THEN
      RETURN 0
   ELSIF r > 0.0
   THEN
      RETURN 1
   ELSE
      RETURN -1
   END
END SignTop ;


(* Sign of the plain Horner value: -1, 0 (exactly zero), +1. *)
PROCEDURE SignPlain (VAR a: Coeffs; n: INTEGER; x: REAL) : INTEGER ;
VAR
   v: REAL ;
   i: INTEGER ;
BEGIN
   v := a[n] ;
   FOR i := n - 1 TO 0 BY -1 DO
      v := v * x + a[i]
   END ;
   IF v > 0.0
   THEN
      RETURN 1
   ELSIF v < 0.0
   THEN
      RETURN -1
   ELSE
      RETURN 0
   END
END SignPlain ;


(* Bisection point of [xa, xb]; half = (xb - xa)/2. *)
PROCEDURE Midpoint (xa, xb, half: REAL) : REAL ;
BEGIN
   IF (xa < 0.0) AND (0.0 < xb) THEN RETURN 0.0 END ;
   IF (xa > 0.0) AND (xb > 8.0 * xa) THEN RETURN sqrt (xa) * sqrt (xb) END ;
   IF (xb < 0.0) AND (xa < 8.0 * xb) THEN RETURN -(sqrt (-xa) * sqrt (-xb)) END ;
   IF (xa = 0.0) AND (xb > 0.0) THEN RETURN xb * Sixteenth END ;
   IF (xb = 0.0) AND (xa < 0.0) THEN RETURN xa * Sixteenth END ;
   RETURN xa + half
END Midpoint ;


(* Root of p in (lo, hi), p(lo) of sign slo (nonzero); xa, xb receive the
   final bracket. *)
PROCEDURE Newton (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; slo: INTEGER;
                  VAR xa, xb: REAL) : REAL ;
VAR
   x, dx, dxold, v, d, step, xn, tol: REAL ;
   neg: BOOLEAN ;
   i, it: INTEGER ;
BEGIN
   xa := lo ;
   xb := hi ;
   x := 0.5 * (xa + xb) ;
   dx := xb - xa ;
   dxold := dx ;
   neg := slo < 0 ;
   tol := Eps ;
   FOR it := 1 TO MaxIt DO
      v := a[n] ;
      d := 0.0 ;
      FOR i := n - 1 TO 0 BY -1 DO
         d := d * x + v ;
         v := v * x + a[i]
      END ;
      IF v = 0.0 THEN RETURN x END ;
      IF (v < 0.0) = neg THEN xa := x ELSE xb := x END ;
      IF (d # 0.0) AND (ABS (4.0 * v) < ABS (dxold * d))
      THEN
         step := v / d ;
         xn := x - step ;
         IF (xa < xn) AND (xn < xb)
         THEN
            dxold := dx ;
            dx := step ;
            tol := NewtonTol
         ELSE
            dxold := dx ;
            dx := 0.5 * (xb - xa) ;
            xn := Midpoint (xa, xb, dx) ;
            tol := Eps
         END
      ELSE
         dxold := dx ;
         dx := 0.5 * (xb - xa) ;
         xn := Midpoint (xa, xb, dx) ;
         tol := Eps
      END ;
      IF NOT ((xa < xn) AND (xn < xb)) THEN RETURN x END ;
      IF ABS (dx) <= tol * ABS (xn) THEN RETURN xn END ;
      x := xn
   END ;
   RETURN x
END Newton ;


(* A last Newton step inside [xa, xb]: plain when Horner is accurate enough
   at x, else up to two steps with compensated Horner. *)
PROCEDURE Polish (VAR a: Coeffs; n: INTEGER; x, xa, xb: REAL) : REAL ;
VAR
   ax, v, d, pt, vc, xn: REAL ;
   i, k: INTEGER ;
BEGIN
   FOR k := 1 TO 2 DO
      ax := ABS (x) ;
      v := a[n] ;
      d := 0.0 ;
      pt := ABS (v) ;
      FOR i := n - 1 TO 0 BY -1 DO
         d := d * x + v ;
         v := v * x + a[i] ;
         pt := pt * ax + ABS (a[i])
      END ;
      IF d = 0.0 THEN RETURN x END ;
      IF VAL (REAL, n) * pt <= 8.0 * ABS (x * d)
      THEN
         (* Horner is accurate enough here: one plain Newton step *)
         xn := x - v / d ;
         IF (xa < xn) AND (xn <= xb) THEN RETURN xn END ;
         RETURN x
      END ;
      vc := CompHorner (a, n, x) ;
      IF vc = 0.0 THEN RETURN x END ;
      xn := x - vc / d ;
      IF (NOT ((xa < xn) AND (xn <= xb))) OR (xn = x) THEN RETURN x END ;
      x := xn
   END ;
   RETURN x
END Polish ;


(* Real roots of a x^2 + b x + c (a # 0), ascending, into r[0..]; returns
   the count. *)
PROCEDURE Quadratic (a, b, c: REAL; VAR r: ARRAY OF REAL) : INTEGER ;
VAR
   p, pe, q, qe, a4, disc, bound, s, qq, r1, r2: REAL ;
BEGIN
   TwoProd (b, b, p, pe) ;
   a4 := 4.0 * a ;
   TwoProd (a4, c, q, qe) ;
   disc := (p - q) + (pe - qe) ;
   bound := Eps * Eps * (p + ABS (q)) ;
   IF disc < -bound THEN RETURN 0 END ;
   IF disc <= bound
   THEN
      r[0] := -b / (2.0 * a) ;
      RETURN 1
   END ;
   s := sqrt (disc) ;
   IF b < 0.0 THEN s := -s END ;
   qq := -0.5 * (b + s) ;
   r1 := qq / a ;
   r2 := c / qq ;
   IF r1 <= r2
   THEN
      r[0] := r1 ;
      r[1] := r2
   ELSE
      r[0] := r2 ;
      r[1] := r1
   END ;
   RETURN 2
END Quadratic ;


(* All roots of p (degree n) in the open (lo, hi), ascending, given the m
   ascending roots crit of p' there; returns the count written to out. *)
PROCEDURE RootsBetween (VAR a: Coeffs; n: INTEGER; VAR crit: Coeffs; m: INTEGER;
                        lo, hi: REAL; VAR out: Coeffs) : INTEGER ;
VAR
   k, i, sl, sr: INTEGER ;
   xl, xr, xa, xb: REAL ;
BEGIN
   k := 0 ;
   xl := lo ;
   sl := SignPlain (a, n, lo) ;
   FOR i := 0 TO m DO
      IF i < m THEN xr := crit[i] ELSE xr := hi END ;
      sr := SignPlain (a, n, xr) ;
      IF (sl = 0) AND (i > 0)
      THEN
         out[k] := xl ;
         INC (k)
      ELSIF sl * sr < 0
      THEN
         out[k] := Newton (a, n, xl, xr, sl, xa, xb) ;
         INC (k)
      END ;
      xl := xr ;
      sl := sr
   END ;
   RETURN k
END RootsBetween ;


(* The general method for degree n >= 3 (a scaled). *)
PROCEDURE General (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   an, mx, v, r, cap, mid, rad, s, y, pt, n1, xl, xr, xa, xb, x: REAL ;
   q, crit, next: Coeffs ;
   ders: ARRAY [0..MaxDegree - 2] OF Coeffs ;
   qr: ARRAY [0..1] OF REAL ;
   i, j, k, m, m2, nq, sl, sr: INTEGER ;
BEGIN
   (* 1. clip to the root bound *)
   an := ABS (a[n]) ;
   mx := 0.0 ;
   FOR i := 0 TO n - 1 DO
      v := ABS (a[i]) / an ;
      IF v > mx THEN mx := v END
   END ;
   r := 2.0 * (1.0 + mx) ;
   cap := ldexp (1.0, 900 DIV n) ;
   IF r > cap THEN r := cap END ;
   IF lo < -r THEN lo := -r END ;
   IF hi > r THEN hi := r END ;
   IF NOT (lo < hi) THEN RETURN FALSE END ;
   (* 2. cheap exit: Taylor shift at the midpoint *)
   mid := 0.5 * (lo + hi) ;
   rad := hi - mid ;
   IF mid - lo > rad THEN rad := mid - lo END ;
   rad := rad * (1.0 + 4.0 * Eps) ;
   q := a ;
   FOR i := 0 TO n - 1 DO
      FOR j := n - 1 TO i BY -1 DO
         q[j] := q[j] + mid * q[j + 1]
      END
   END ;
   s := ABS (q[n]) ;
   FOR k := n - 1 TO 1 BY -1 DO
      s := s * rad + ABS (q[k])
   END ;
   s := s * rad ;
   y := ABS (mid) + rad ;
   pt := ABS (a[n]) ;
   FOR i := n - 1 TO 0 BY -1 DO
      pt := pt * y + ABS (a[i])
   END ;
   n1 := VAL (REAL, n + 1) ;
   IF ABS (q[0]) - s * (1.0 + 4.0 * n1 * Eps) > 8.0 * n1 * Eps * pt
   THEN
      RETURN FALSE
   END ;
   (* 3. derivative tables and their roots, bottom up *)
   ders[0] := a ;
   FOR k := 1 TO n - 2 DO
      FOR i := 0 TO n - k DO
         ders[k][i] := ders[k - 1][i + 1] * VAL (REAL, i + 1)
      END
   END ;
   nq := Quadratic (ders[n - 2][2], ders[n - 2][1], ders[n - 2][0], qr) ;
   m := 0 ;
   FOR i := 0 TO nq - 1 DO
      IF (lo < qr[i]) AND (qr[i] < hi)
      THEN
         crit[m] := qr[i] ;
         INC (m)
      END
   END ;
   FOR k := n - 3 TO 1 BY -1 DO
      m2 := RootsBetween (ders[k], n - k, crit, m, lo, hi, next) ;
      FOR i := 0 TO m2 - 1 DO
         crit[i] := next[i]
      END ;
      m := m2
   END ;
   (* 4. top level: first root, careful signs *)
   xl := lo ;
   sl := SignTop (a, n, lo) ;
   FOR i := 0 TO m DO
      IF (sl = 0) AND (i > 0)
      THEN
         t := xl ;
         RETURN TRUE
      END ;
      IF i < m THEN xr := crit[i] ELSE xr := hi END ;
      sr := SignTop (a, n, xr) ;
      IF sl * sr < 0
      THEN
         x := Newton (a, n, xl, xr, sl, xa, xb) ;
         x := Polish (a, n, x, xl, xr) ;   (* the monotone piece bounds the polish *)
         IF NOT (x > xl) THEN x := xr END ;
         IF x > xr THEN x := xr END ;
         t := x ;
         RETURN TRUE
      END ;
      xl := xr ;
      sl := sr
   END ;
   IF sl = 0
   THEN
      t := hi ;
      RETURN TRUE
   END ;
   RETURN FALSE
END General ;


PROCEDURE Scale (VAR c: ARRAY OF REAL; n: INTEGER; VAR a: ARRAY OF REAL) : INTEGER ;
VAR
   m, v, f: REAL ;
   e, k, i: INTEGER ;
BEGIN
   m := 0.0 ;
   FOR i := 0 TO n DO
      v := ABS (c[i]) ;
      IF v > m THEN m := v END
   END ;
   f := frexp (m, e) ;
   k := 1 - e ;
   FOR i := 0 TO n DO
      a[i] := c[i]
   END ;
   IF k > 1000
   THEN
      f := ldexp (1.0, 600) ;
      FOR i := 0 TO n DO
         a[i] := a[i] * f
      END ;
      k := k - 600
   END ;
   f := ldexp (1.0, k) ;
   FOR i := 0 TO n DO
      a[i] := a[i] * f
   END ;
   (* top coefficients that underflowed to zero in the scaling *)
   WHILE (n >= 0) AND (a[n] = 0.0) DO
      DEC (n)
   END ;
   RETURN n
END Scale ;


PROCEDURE SmallestRoot (c: ARRAY OF REAL; degree: INTEGER; lo, hi: REAL;
                        VAR t: REAL) : BOOLEAN ;
VAR
   a: Coeffs ;
   r: ARRAY [0..1] OF REAL ;
   n, i, nr: INTEGER ;
   x: REAL ;
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
   IF n = 1
   THEN
      x := -a[0] / a[1] ;
      IF NOT ((lo < x) AND (x <= hi)) THEN RETURN FALSE END
   ELSIF n = 2
   THEN
      nr := Quadratic (a[2], a[1], a[0], r) ;
      found := FALSE ;
      i := 0 ;
      WHILE (i < nr) AND (NOT found) DO
         IF (lo < r[i]) AND (r[i] <= hi)
         THEN
            x := r[i] ;
            found := TRUE
         END ;
         INC (i)
      END ;
      IF NOT found THEN RETURN FALSE END
   ELSIF NOT General (a, n, lo, hi, x)
   THEN
      RETURN FALSE
   END ;
   t := x + 0.0 ;
   RETURN TRUE
END SmallestRoot ;


BEGIN
   Eps := ldexp (1.0, -52) ;
   Tiny := ldexp (1.0, -1000) ;
   Sixteenth := ldexp (1.0, -16) ;
   NewtonTol := ldexp (1.0, -30)
END Roots.
