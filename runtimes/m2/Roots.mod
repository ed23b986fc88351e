IMPLEMENTATION MODULE Roots ;

(* The root solver of docs/roots.md, transcribed operation for operation from
   the C runtime (runtimes/c/src); values are in the coefficients' units and
   x, t in the caller's time unit. *)

FROM CMath IMPORT frexp, ldexp ;
FROM RealMath IMPORT sqrt ;   (* a gm2 builtin: the sqrtsd instruction, no call *)
FROM SYSTEM IMPORT CAST ;

CONST
   N1 = MaxDegree + 1 ;
   Splitter = 134217729.0 ;   (* 2^27 + 1, Veltkamp splitting constant *)
   MaxIt = 100 ;              (* bracketed Newton step limit *)
   BernDepth = 12 ;           (* Bernstein subdivision depth limit *)
   QuadSpread = 900 ;         (* degree 2: one scale when coefficient exponents span at most this *)
   OneScaleSpan = 800 ;       (* degree n >= 3: one scale when all roots lie in 2^(+-800/n) *)
   BandSpan = 800 ;           (* otherwise bands of magnitude 2^(800/n) *)
   (* constants, not variables: a division by Unit52 is then a shift *)
   Unit52 = VAL (LONGCARD, 4503599627370496) ;     (* 2^52: the exponent field's unit in a REAL's bits *)
   SignBit = VAL (LONGCARD, 9223372036854775808) ; (* 2^63: the sign bit *)
   InfBits = VAL (LONGCARD, 9218868437227405312) ; (* the bits of infinity; NaNs lie above *)
   MaxRealBits = InfBits - 1 ;                     (* the bits of the largest finite REAL *)
   ModerateLoBits = VAL (LONGCARD, 823) * Unit52 ; (* the bits of 2^-200 (ModerateLo) *)
   ModerateHiBits = VAL (LONGCARD, 1223) * Unit52 ; (* the bits of 2^200 (ModerateHi) *)

TYPE
   Coeffs = ARRAY [0..MaxDegree] OF REAL ;

VAR
   Fact: Coeffs ;             (* i! for 0 <= i <= 16 (exact) *)
   Eps,                       (* 2^-52, spacing of doubles at 1 *)
   Tiny,                      (* 2^-1000, floor of the touching bound *)
   Sixteenth,                 (* 2^-16, bisection step from an end at 0 *)
   NewtonTol,                 (* 2^-30: an accepted Newton step this small (relative) has converged *)
   HalleyTol,                 (* 2^-8: an accepted Halley step this small: the polish finishes it (Bernstein's single root) *)
   HalleyMin,                 (* 2^-968: Halley's products below this lose precision to underflow *)
   HandoffTol,                (* 2^-14: ... or an accepted Newton step (Halley refused) this small *)
   PolishTol,                 (* 2^-22: a polishing Halley step this small ends the polish *)
   ModerateLo, ModerateHi,    (* 2^-200, 2^200: the degree-2 fast path's coefficient range *)
   NoneRel,                   (* 2^-46: degrees 3, 4's no-root test, 16 times the rounding bound *)
   NoneAbs,                   (* 2^-900: keeps its m above 0 when every t_i is 0 or subnormal *)
   HiMin,                     (* 2^-250: below it the test's hi^2..hi^4 may underflow *)
   Third, TwoThirds, Sixth,   (* the doubles nearest 1/3, 2/3, 1/6 *)
   Inf: REAL ;                (* infinity *)
   Init: INTEGER ;


PROCEDURE IsFinite (x: REAL) : BOOLEAN ;
BEGIN
   RETURN (x - x) = 0.0
END IsFinite ;


(* 2^k for -1022 <= k <= 1023 (exact), from its bits: a call of ldexp or
   frexp costs more than the rest of a degree-3 solve's scaling. *)
PROCEDURE Pow2 (k: INTEGER) : REAL ;
VAR
   u: LONGCARD ;
BEGIN
   u := VAL (LONGCARD, k + 1023) * Unit52 ;
   RETURN CAST (REAL, u)
END Pow2 ;


(* Binary exponent e of a finite nonzero x = f 2^e, 0.5 <= |f| < 1 (frexp's;
   read from the exponent field, frexp itself for a subnormal x). *)
PROCEDURE Exponent (x: REAL) : INTEGER ;
VAR
   e, field: INTEGER ;
   f: REAL ;
   u: LONGCARD ;
BEGIN
   u := CAST (LONGCARD, x) ;
   field := VAL (INTEGER, (u DIV Unit52) MOD 2048) ;
   IF field = 0
   THEN
      f := frexp (x, e) ;
      RETURN e
   END ;
   RETURN field - 1022
END Exponent ;


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


(* Root of p in (lo, hi), p(lo) of sign slo (nonzero), p(hi) of the other,
   starting at x0 (lo < x0 < hi). *)
PROCEDURE Newton (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; slo: INTEGER;
                  x0, tolnewton: REAL) : REAL ;
VAR
   x, xa, xb, dx, dxold, v, d, step, xn, tol: REAL ;
   neg: BOOLEAN ;
   i, it: INTEGER ;
BEGIN
   xa := lo ;
   xb := hi ;
   x := x0 ;
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
            tol := tolnewton
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


(* c[0] + c[1] x + ... + c[m] x^m by Estrin's scheme (docs/roots.md step
   7.3): pairs q_i = q_2i + q_2i+1 * p with p = x, then x^2, x^4, ... until
   one value is left; an odd last entry is carried up unchanged.  About
   log2(m + 1) multiply-adds deep where Horner is m (m <= 16). *)
PROCEDURE Estrin (VAR c: Coeffs; m: INTEGER; x: REAL) : REAL ;
VAR
   q: Coeffs ;
   p: REAL ;
   i, k, h: INTEGER ;
BEGIN
   IF m = 0 THEN RETURN c[0] END ;
   (* the first level straight from c, the next ones in place *)
   k := m + 1 ;
   h := k DIV 2 ;
   FOR i := 0 TO h - 1 DO
      q[i] := c[2 * i] + c[2 * i + 1] * x
   END ;
   IF ODD (k) THEN q[h] := c[k - 1] ; INC (h) END ;
   k := h ;
   p := x * x ;
   WHILE k > 1 DO
      h := k DIV 2 ;
      FOR i := 0 TO h - 1 DO
         q[i] := q[2 * i] + q[2 * i + 1] * p
      END ;
      IF ODD (k) THEN q[h] := q[k - 1] ; INC (h) END ;
      k := h ;
      p := p * p
   END ;
   RETURN q[0]
END Estrin ;

(* Bernstein's single simple root in (lo, hi): Newton with Halley's step,
   h = p''/2, and p, p', p''/2 by Estrin (shorter chains than Horner's: this
   loop is latency-bound, and it only brings x within 2^-8; the polish
   evaluates by Horner with its error bound); an accepted Halley step of at most HalleyTol |x| ends it, a
   Newton step of at most HandoffTol |x|.  The step from p(x) = v,
   p'(x) = d (nonzero), p''(x)/2 = h: Halley's v d / (d^2 - v h) when
   d^2 - v h > d^2 / 2 (at most twice the Newton step, same direction; false
   for an overflow or NaN) and both v d and d^2 are at least HalleyMin (no
   precision lost to underflow), else Newton's v / d.  Written out here and
   in PolishHalley: gm2 -O2 did not inline a procedure for it. *)
PROCEDURE Halley (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; slo: INTEGER;
                  x0: REAL) : REAL ;
VAR
   x, xa, xb, dx, dxold, v, d, h, step, xn, tol, dd, vd, den: REAL ;
   da, ha: Coeffs ;
   neg, isHalley: BOOLEAN ;
   i, it: INTEGER ;
BEGIN
   xa := lo ;
   xb := hi ;
   x := x0 ;
   dx := xb - xa ;
   dxold := dx ;
   neg := slo < 0 ;
   tol := Eps ;
   (* the coefficients of p' and p''/2 *)
   FOR i := 0 TO n - 1 DO
      da[i] := VAL (REAL, i + 1) * a[i + 1]
   END ;
   FOR i := 0 TO n - 2 DO
      ha[i] := VAL (REAL, (i + 1) * (i + 2) DIV 2) * a[i + 2]
   END ;
   FOR it := 1 TO MaxIt DO
      v := Estrin (a, n, x) ;
      d := Estrin (da, n - 1, x) ;
      h := Estrin (ha, n - 2, x) ;
      IF v = 0.0 THEN RETURN x END ;
      IF (v < 0.0) = neg THEN xa := x ELSE xb := x END ;
      IF (d # 0.0) AND (ABS (4.0 * v) < ABS (dxold * d))
      THEN
         (* Halley's step, else Newton's (see above) *)
         dd := d * d ;
         vd := v * d ;
         den := dd - v * h ;
         IF (den > 0.5 * dd) AND (ABS (vd) >= HalleyMin) AND (dd >= HalleyMin)
         THEN
            step := vd / den ;
            isHalley := TRUE
         ELSE
            step := v / d ;
            isHalley := FALSE
         END ;
         xn := x - step ;
         IF (xa < xn) AND (xn < xb)
         THEN
            dxold := dx ;
            dx := step ;
            IF isHalley THEN tol := HalleyTol ELSE tol := HandoffTol END
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
END Halley ;


(* A last Newton step inside (xa, xb]: plain when the running error bound
   of Horner at x is within a few ulps of x, else up to two steps with
   compensated Horner. *)
PROCEDURE Polish (VAR a: Coeffs; n: INTEGER; x, xa, xb: REAL) : REAL ;
VAR
   ax, v, d, mu, vc, xn: REAL ;
   i, k: INTEGER ;
BEGIN
   FOR k := 1 TO 2 DO
      ax := ABS (x) ;
      v := a[n] ;
      d := 0.0 ;
      mu := 0.5 * ABS (v) ;
      FOR i := n - 1 TO 0 BY -1 DO
         d := d * x + v ;
         v := v * x + a[i] ;
         mu := mu * ax + ABS (v)
      END ;
      IF d = 0.0 THEN RETURN x END ;
      (* running error bound of Horner (Higham, Alg. 5.1): |v - p(x)| <= eps (mu - |v|/2) *)
      IF mu <= 2.0 * ABS (x * d)
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


(* The polish after Bernstein's Halley iteration: Halley's step (as in
   Halley) from p(x) (plain Horner where its running error bound allows, else
   compensated), p'(x) and p''(x)/2, kept only inside (xa, xb]; a Halley step
   of at most PolishTol |x| (a Newton step: NewtonTol) ends it, else another
   round, at most three. *)
PROCEDURE PolishHalley (VAR a: Coeffs; n: INTEGER; x, xa, xb: REAL) : REAL ;
VAR
   ax, v, d, h, mu, step, xn, tol, dd, vd, den: REAL ;
   i, k: INTEGER ;
BEGIN
   FOR k := 1 TO 3 DO
      ax := ABS (x) ;
      v := a[n] ;
      d := 0.0 ;
      h := 0.0 ;
      mu := 0.5 * ABS (v) ;
      FOR i := n - 1 TO 0 BY -1 DO
         h := h * x + d ;
         d := d * x + v ;
         v := v * x + a[i] ;
         mu := mu * ax + ABS (v)
      END ;
      IF d = 0.0 THEN RETURN x END ;
      (* plain Horner not accurate enough: compensated *)
      IF mu > 2.0 * ABS (x * d) THEN v := CompHorner (a, n, x) END ;
      (* Halley's step, else Newton's (see Halley) *)
      dd := d * d ;
      vd := v * d ;
      den := dd - v * h ;
      IF (den > 0.5 * dd) AND (ABS (vd) >= HalleyMin) AND (dd >= HalleyMin)
      THEN
         step := vd / den ;
         tol := PolishTol
      ELSE
         step := v / d ;
         tol := NewtonTol
      END ;
      xn := x - step ;
      IF NOT ((xa < xn) AND (xn <= xb)) THEN RETURN x END ;
      IF ABS (step) <= tol * ABS (xn) THEN RETURN xn END ;
      x := xn
   END ;
   RETURN x
END PolishHalley ;


(* Real roots of a x^2 + b x + c (a # 0), ascending, into r[0..]; returns
   the count. *)
PROCEDURE Quadratic (a, b, c: REAL; VAR r: ARRAY OF REAL) : INTEGER ;
VAR
   p, pe, q, qe, a4, disc, bound, s, qq, r1, r2: REAL ;
BEGIN
   (* the plain discriminant when it cannot cancel (4ac <= b*b/2), none when
      it is clearly negative, error-free products only in between *)
   p := b * b ;
   q := (4.0 * a) * c ;
   disc := p - q ;
   IF q <= 0.5 * p
   THEN
      IF disc = 0.0
      THEN
         (* b = 0 and ac = 0 *)
         r[0] := -b / (2.0 * a) ;
         RETURN 1
      END
   ELSIF disc < -Eps * (p + q)
   THEN
      RETURN 0
   ELSE
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
      END
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


(* Quadratic in x = 2^s u (docs/roots.md step 7.4): s balances a 2^(2s)
   against c (or b 2^s when c = 0), a common power of two puts the largest
   coefficient in [1, 2), the roots u come back as ldexp (u, s).  The same
   bits as Quadratic where its products stay normal; where they underflow
   (roots far from 1 with tiny coefficients) the roots are kept.  floor(d/2)
   is written with nonnegative operands only. *)
PROCEDURE QuadraticScaled (a, b, c: REAL; VAR r: ARRAY OF REAL) : INTEGER ;
VAR
   ea, eb, ec, d, s, m, k, i, nr: INTEGER ;
BEGIN
   ea := Exponent (a) ;
   IF b # 0.0 THEN eb := Exponent (b) ELSE eb := 0 END ;
   IF c # 0.0 THEN ec := Exponent (c) ELSE ec := 0 END ;
   IF c # 0.0
   THEN
      d := ec - ea ;
      IF d >= 0 THEN s := d DIV 2 ELSE s := -((1 - d) DIV 2) END
   ELSIF b # 0.0
   THEN
      s := eb - ea
   ELSE
      s := 0
   END ;
   m := ea + 2 * s ;
   IF (b # 0.0) AND (eb + s > m) THEN m := eb + s END ;
   IF (c # 0.0) AND (ec > m) THEN m := ec END ;
   k := 1 - m ;
   nr := Quadratic (ldexp (a, 2 * s + k), ldexp (b, s + k), ldexp (c, k), r) ;
   FOR i := 0 TO nr - 1 DO
      r[i] := ldexp (r[i], s)
   END ;
   RETURN nr
END QuadraticScaled ;


(* All roots of p (degree n) in the open (lo, hi), ascending, given the m
   ascending roots crit of p' there; returns the count written to out. *)
PROCEDURE RootsBetween (VAR a: Coeffs; n: INTEGER; VAR crit: Coeffs; m: INTEGER;
                        lo, hi: REAL; VAR out: Coeffs) : INTEGER ;
VAR
   k, i, sl, sr: INTEGER ;
   xl, xr: REAL ;
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
         out[k] := Newton (a, n, xl, xr, sl, 0.5 * (xl + xr), NewtonTol) ;
         INC (k)
      END ;
      xl := xr ;
      sl := sr
   END ;
   RETURN k
END RootsBetween ;


(* The derivative method on [lo, hi] (answers in (lo, hi]): roots of the
   derivatives bottom up, then the first root of p with careful signs. *)
PROCEDURE ByDerivatives (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   xl, xr, x: REAL ;
   crit, next: Coeffs ;
   ders: ARRAY [0..MaxDegree - 2] OF Coeffs ;
   qr: ARRAY [0..1] OF REAL ;
   i, k, m, m2, nq, sl, sr: INTEGER ;
BEGIN
   ders[0] := a ;
   FOR k := 1 TO n - 2 DO
      FOR i := 0 TO n - k DO
         ders[k][i] := ders[k - 1][i + 1] * VAL (REAL, i + 1)
      END
   END ;
   nq := QuadraticScaled (ders[n - 2][2], ders[n - 2][1], ders[n - 2][0], qr) ;
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
         x := Newton (a, n, xl, xr, sl, 0.5 * (xl + xr), NewtonTol) ;
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
END ByDerivatives ;


(* Sign variations of b[0..n], or -1 when one of them is within e of zero;
   mx receives max |b_i|. *)
PROCEDURE Variations (VAR b: Coeffs; n: INTEGER; e: REAL; VAR mx: REAL) : INTEGER ;
VAR
   m, ab: REAL ;
   unsure: BOOLEAN ;
   i, v: INTEGER ;
   neg, negi: BOOLEAN ;
BEGIN
   m := ABS (b[0]) ;
   unsure := m <= e ;
   neg := b[0] < 0.0 ;
   v := 0 ;
   FOR i := 1 TO n DO
      ab := ABS (b[i]) ;
      IF ab > m THEN m := ab END ;
      IF ab <= e THEN unsure := TRUE END ;
      negi := b[i] < 0.0 ;
      IF negi # neg THEN INC (v) END ;
      neg := negi
   END ;
   mx := m ;
   IF unsure THEN RETURN -1 END ;
   RETURN v
END Variations ;


(* The general method for degree n >= 3 (a scaled): clip to the root bound,
   Bernstein subdivision left to right (no root / one simple root / split),
   the derivative method where the Bernstein signs are unsure. *)
PROCEDURE General (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   mx, r, cap, w, f, y, pt, e, nf, xl, xr, xm, bm, x0, x: REAL ;
   b, c: Coeffs ;
   stb: ARRAY [0..BernDepth - 1] OF Coeffs ;
   ste, stl, stu: ARRAY [0..BernDepth - 1] OF REAL ;
   std: ARRAY [0..BernDepth - 1] OF INTEGER ;
   i, j, k, v, sp, depth, sl: INTEGER ;
   split, neg, negi: BOOLEAN ;
BEGIN
   (* 1. clip to the root bound (r >= 2: nothing to clip in [-2, 2]) *)
   IF NOT ((-2.0 <= lo) AND (hi <= 2.0))
   THEN
      mx := 0.0 ;
      FOR i := 0 TO n - 1 DO
         IF ABS (a[i]) > mx THEN mx := ABS (a[i]) END
      END ;
      mx := mx / ABS (a[n]) ;   (* = max |a_i|/|a_n| (rounding is monotone) *)
      r := 2.0 * (1.0 + mx) ;
      cap := Pow2 (900 DIV n) ;
      IF r > cap THEN r := cap END ;
      IF lo < -r THEN lo := -r END ;
      IF hi > r THEN hi := r END ;
      IF NOT (lo < hi) THEN RETURN FALSE END
   END ;
   (* 2. n! times the Bernstein coefficients of p on [lo, hi], error bound e *)
   FOR i := 0 TO n DO
      b[i] := a[i]
   END ;
   IF lo # 0.0
   THEN
      FOR i := 0 TO n - 1 DO
         FOR j := n - 1 TO i BY -1 DO
            b[j] := b[j] + lo * b[j + 1]
         END
      END
   END ;
   w := hi - lo ;
   f := 1.0 ;
   FOR j := 0 TO n DO
      b[j] := b[j] * f * (Fact[j] * Fact[n - j]) ;
      f := f * w
   END ;
   FOR k := 1 TO n DO
      FOR j := n TO k BY -1 DO
         b[j] := b[j] + b[j - 1]
      END
   END ;
   y := ABS (lo) + w ;
   pt := ABS (a[n]) ;
   FOR i := n - 1 TO 0 BY -1 DO
      pt := pt * y + ABS (a[i])
   END ;
   nf := VAL (REAL, n) ;
   e := 8.0 * VAL (REAL, n + 1) * Eps * pt * Fact[n] + Tiny ;
   (* 3. subdivision, left to right *)
   sp := 0 ;
   depth := 0 ;
   xl := lo ;
   xr := hi ;
   LOOP
      v := Variations (b, n, e, bm) ;
      IF v = 1
      THEN
         (* one simple root in (xl, xr): start where the control polygon crosses *)
         (* (gm2 -O2 mis-evaluates "(x < 0.0) = (y < 0.0)": compare flags) *)
         i := 0 ;
         neg := b[0] < 0.0 ;
         negi := b[1] < 0.0 ;
         WHILE negi = neg DO
            INC (i) ;
            negi := b[i + 1] < 0.0
         END ;
         x0 := xl + ((xr - xl) / nf) * (VAL (REAL, i) + b[i] / (b[i] - b[i + 1])) ;
         IF NOT ((xl < x0) AND (x0 < xr)) THEN x0 := 0.5 * (xl + xr) END ;
         IF b[0] < 0.0 THEN sl := -1 ELSE sl := 1 END ;
         x := Halley (a, n, xl, xr, sl, x0) ;
         x := PolishHalley (a, n, x, xl, xr) ;
         IF NOT (x > xl) THEN x := xr END ;
         IF x > xr THEN x := xr END ;
         t := x ;
         RETURN TRUE
      END ;
      split := FALSE ;
      IF (v # 0) AND ((depth = BernDepth) OR
                      ((v < 0) AND ((ABS (b[0]) <= e) OR (ABS (b[n]) <= e))))
      THEN
         IF ByDerivatives (a, n, xl, xr, t) THEN RETURN TRUE END
      ELSIF v # 0
      THEN
         (* de Casteljau at 1/2: left half in b, right half pushed *)
         c := b ;
         stb[sp][n] := c[n] ;
         FOR k := 1 TO n DO
            FOR i := 0 TO n - k DO
               c[i] := 0.5 * (c[i] + c[i + 1])
            END ;
            b[k] := c[0] ;
            stb[sp][n - k] := c[n - k]
         END ;
         xm := 0.5 * (xl + xr) ;
         e := e + nf * Eps * bm ;
         INC (depth) ;
         ste[sp] := e ;
         stl[sp] := xm ;
         stu[sp] := xr ;
         std[sp] := depth ;
         INC (sp) ;
         xr := xm ;
         split := TRUE
      END ;
      IF NOT split
      THEN
         (* no root in (xl, xr]: the next pending interval *)
         IF sp = 0 THEN RETURN FALSE END ;
         DEC (sp) ;
         b := stb[sp] ;
         e := ste[sp] ;
         xl := stl[sp] ;
         xr := stu[sp] ;
         depth := std[sp]
      END
   END
END General ;


PROCEDURE Scale (VAR c: ARRAY OF REAL; n: INTEGER; VAR a: ARRAY OF REAL) : INTEGER ;
VAR
   m, v: REAL ;
   i: INTEGER ;
BEGIN
   m := 0.0 ;
   FOR i := 0 TO n DO
      v := ABS (c[i]) ;
      IF v > m THEN m := v END
   END ;
   RETURN ScaleBy (c, n, Exponent (m), a)
END Scale ;


(* Scale with e = Exponent (max |c_i|) known.  Each a[i] is c[i] times the
   factors in one expression (the products of the copy-then-scale loops,
   in their order). *)
PROCEDURE ScaleBy (VAR c: ARRAY OF REAL; n, e: INTEGER; VAR a: ARRAY OF REAL) : INTEGER ;
VAR
   f, g: REAL ;
   k, i: INTEGER ;
BEGIN
   k := 1 - e ;
   IF k > 1000
   THEN
      (* 2^k is not a double: first 2^600, then 2^(k - 600) *)
      g := Pow2 (600) ;
      f := Pow2 (k - 600) ;
      FOR i := 0 TO n DO
         a[i] := (c[i] * g) * f
      END
   ELSE
      IF k >= -1022
      THEN
         f := Pow2 (k)
      ELSE
         f := ldexp (1.0, k)   (* 2^-1023, subnormal *)
      END ;
      FOR i := 0 TO n DO
         a[i] := c[i] * f
      END
   END ;
   (* top coefficients that underflowed to zero in the scaling *)
   WHILE (n >= 0) AND (a[n] = 0.0) DO
      DEC (n)
   END ;
   RETURN n
END ScaleBy ;


(* The first root of a x^2 + b x + c (a # 0) in (lo, hi]: the operations of
   Quadratic, without its array of roots. *)
PROCEDURE QuadraticIn (a, b, c, lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   p, pe, q, qe, a4, disc, bound, s, qq, r1, r2, x: REAL ;
   two: BOOLEAN ;
BEGIN
   p := b * b ;
   q := (4.0 * a) * c ;
   disc := p - q ;
   two := TRUE ;
   IF q <= 0.5 * p
   THEN
      IF disc = 0.0 THEN two := FALSE END
   ELSIF disc < -Eps * (p + q)
   THEN
      RETURN FALSE
   ELSE
      TwoProd (b, b, p, pe) ;
      a4 := 4.0 * a ;
      TwoProd (a4, c, q, qe) ;
      disc := (p - q) + (pe - qe) ;
      bound := Eps * Eps * (p + ABS (q)) ;
      IF disc < -bound THEN RETURN FALSE END ;
      IF disc <= bound THEN two := FALSE END
   END ;
   IF two
   THEN
      s := sqrt (disc) ;
      IF b < 0.0 THEN s := -s END ;
      qq := -0.5 * (b + s) ;
      r1 := qq / a ;
      r2 := c / qq ;
      IF r2 < r1
      THEN
         x := r1 ;
         r1 := r2 ;
         r2 := x
      END ;
      IF (lo < r1) AND (r1 <= hi)
      THEN
         t := r1 ;
         RETURN TRUE
      END ;
      x := r2
   ELSE
      x := -b / (2.0 * a)
   END ;
   IF (lo < x) AND (x <= hi)
   THEN
      t := x ;
      RETURN TRUE
   END ;
   RETURN FALSE
END QuadraticIn ;


(* ceil(a / k) for k > 0, with nonnegative operands only. *)
PROCEDURE CeilDiv (a, k: INTEGER) : INTEGER ;
BEGIN
   IF a >= 0 THEN RETURN (a + k - 1) DIV k END ;
   RETURN -((-a) DIV k)
END CeilDiv ;


(* Scaled coefficients (max |a_i| in [1, 2), a[n] # 0, n >= 1): the first
   root in (lo, hi] by the closed forms or the general method. *)
PROCEDURE ScaledAny (VAR a: Coeffs; n: INTEGER; lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   x: REAL ;
BEGIN
   IF n = 1
   THEN
      x := -a[0] / a[1] ;
      IF NOT ((lo < x) AND (x <= hi)) THEN RETURN FALSE END ;
      t := x ;
      RETURN TRUE
   ELSIF n = 2
   THEN
      RETURN QuadraticIn (a[2], a[1], a[0], lo, hi, t)
   END ;
   (* The degree as a constant for 3 to 8 (the simulator's degrees and the
      common ones): built with the Makefile's ROOTS_OPT, GCC makes one copy
      of General per constant degree and unrolls its loops completely, as C
      does with always-inline and #pragma GCC unroll.  The same operations
      in the same order. *)
   CASE n OF
   3: RETURN General (a, 3, lo, hi, t) |
   4: RETURN General (a, 4, lo, hi, t) |
   5: RETURN General (a, 5, lo, hi, t) |
   6: RETURN General (a, 6, lo, hi, t) |
   7: RETURN General (a, 7, lo, hi, t) |
   8: RETURN General (a, 8, lo, hi, t)
   ELSE
      RETURN General (a, n, lo, hi, t)
   END
END ScaledAny ;


(* (ue, le): every root of c (degree n, c[n] # 0, j < n the lowest index
   with c[j] # 0) has |t| < 2^ue, every nonzero root |t| > 2^le (Fujiwara's
   bound on p and on its reverse, in exponents). *)
PROCEDURE RootExponents (VAR c: ARRAY OF REAL; n, j: INTEGER; VAR ue, le: INTEGER) ;
VAR
   en, ej, u, lx, i, v: INTEGER ;
BEGIN
   en := Exponent (c[n]) ;
   ej := Exponent (c[j]) ;
   u := -1073741824 ;
   lx := -1073741824 ;
   FOR i := j TO n - 1 DO
      IF c[i] # 0.0
      THEN
         v := CeilDiv (Exponent (c[i]) - en + 1, n - i) ;
         IF v > u THEN u := v END
      END
   END ;
   FOR i := j + 1 TO n DO
      IF c[i] # 0.0
      THEN
         v := CeilDiv (Exponent (c[i]) - ej + 1, i - j) ;
         IF v > lx THEN lx := v END
      END
   END ;
   ue := u + 1 ;
   le := -(lx + 1)
END RootExponents ;


(* 2^e, or infinity beyond the largest double (a band edge). *)
PROCEDURE Edge (e: INTEGER) : REAL ;
BEGIN
   IF e > 1023 THEN RETURN Inf END ;
   RETURN ldexp (1.0, e)
END Edge ;


(* The smallest root in (xl, xr], where 2^(s - w) <= |x| <= 2^s: solved in
   u = t 2^-s with the coefficients c_i 2^(s i) scaled together so that the
   largest lies in [1, 2) (those far below underflow: negligible there). *)
PROCEDURE Band (VAR c: ARRAY OF REAL; n, s: INTEGER; xl, xr: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   a: Coeffs ;
   m, i, f: INTEGER ;
   u, x: REAL ;
BEGIN
   m := -1073741824 ;
   FOR i := 0 TO n DO
      IF c[i] # 0.0
      THEN
         f := Exponent (c[i]) + s * i ;
         IF f > m THEN m := f END
      END
   END ;
   FOR i := 0 TO n DO
      a[i] := ldexp (c[i], s * i + 1 - m)
   END ;
   WHILE (n >= 0) AND (a[n] = 0.0) DO
      DEC (n)
   END ;
   IF n <= 0 THEN RETURN FALSE END ;
   IF NOT ScaledAny (a, n, ldexp (xl, -s), ldexp (xr, -s), u) THEN RETURN FALSE END ;
   x := ldexp (u, s) ;
   IF NOT ((xl < x) AND (x <= xr)) THEN RETURN FALSE END ;
   t := x ;
   RETURN TRUE
END Band ;


(* Roots too spread for one scale: bands of magnitude, each with its own
   power-of-two scale of t, in the order of t (docs/roots.md step 7). *)
PROCEDURE Banded (VAR c: ARRAY OF REAL; n, j, ue, le: INTEGER; lo, hi: REAL;
                  VAR t: REAL) : BOOLEAN ;
VAR
   w, nb, k, s: INTEGER ;
   xl, xr: REAL ;
BEGIN
   w := BandSpan DIV n ;
   nb := CeilDiv (ue - le, w) ;
   k := nb - 1 ;
   WHILE k >= 0 DO
      s := le + (k + 1) * w ;
      xl := -Edge (s) ;
      xr := -Edge (s - w) ;
      IF lo > xl THEN xl := lo END ;
      IF hi < xr THEN xr := hi END ;
      IF (xl < xr) AND Band (c, n, s, xl, xr, t) THEN RETURN TRUE END ;
      DEC (k)
   END ;
   IF (j > 0) AND (lo < 0.0) AND (0.0 <= hi)
   THEN
      t := 0.0 ;
      RETURN TRUE
   END ;
   FOR k := 0 TO nb - 1 DO
      s := le + (k + 1) * w ;
      xl := Edge (s - w) ;
      xr := Edge (s) ;
      IF lo > xl THEN xl := lo END ;
      IF hi < xr THEN xr := hi END ;
      IF (xl < xr) AND Band (c, n, s, xl, xr, t) THEN RETURN TRUE END
   END ;
   RETURN FALSE
END Banded ;


(* Degree n >= 2 (c[n] # 0; a NaN or infinity answers none): one
   power-of-two scale of the coefficients when the roots allow it, else
   bands. *)
PROCEDURE Solve (VAR c: ARRAY OF REAL; n: INTEGER; lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   a: Coeffs ;
   mx, mn: REAL ;
   i, j, spread, ue, le, lim, n2, emx: INTEGER ;
   u, umax, umin: LONGCARD ;
   many: BOOLEAN ;
BEGIN
   (* max and smallest nonzero |c_i| from their bits without the sign
      (ordered like the values); a NaN or infinity shows as the largest *)
   umax := 0 ;
   umin := InfBits ;
   FOR i := 0 TO n DO
      u := CAST (LONGCARD, c[i]) MOD SignBit ;
      IF u > umax THEN umax := u END ;
      IF (u # 0) AND (u < umin) THEN umin := u END
   END ;
   IF umax >= InfBits THEN RETURN FALSE END ;
   mx := CAST (REAL, umax) ;
   mn := CAST (REAL, umin) ;
   emx := Exponent (mx) ;
   spread := emx - Exponent (mn) ;
   (* n = 2: spread > QuadSpread; n >= 3: spread > OneScaleSpan DIV n - 2,
      that is (spread + 2) n > OneScaleSpan (no division) *)
   IF n = 2
   THEN
      many := spread > QuadSpread
   ELSE
      many := (spread + 2) * n > OneScaleSpan
   END ;
   IF many
   THEN
      j := 0 ;
      WHILE c[j] = 0.0 DO
         INC (j)
      END ;
      RootExponents (c, n, j, ue, le) ;
      lim := OneScaleSpan DIV n ;
      IF (n = 2) OR NOT ((ue <= lim) AND (le >= -lim))
      THEN
         RETURN Banded (c, n, j, ue, le, lo, hi, t)
      END
   END ;
   n2 := ScaleBy (c, n, emx, a) ;
   IF n2 <= 0 THEN RETURN FALSE END ;
   RETURN ScaledAny (a, n2, lo, hi, t)
END Solve ;


(* SmallestRoot's general entry (docs/roots.md steps 1-8): every call its
   degree-2 fast path does not answer. *)
PROCEDURE Entry (VAR c: ARRAY OF REAL; degree: INTEGER; lo, hi: REAL;
                 VAR t: REAL) : BOOLEAN ;
VAR
   n: INTEGER ;
   x: REAL ;
BEGIN
   IF (degree < 0) OR (degree > MaxDegree) OR (degree > VAL (INTEGER, HIGH (c)))
   THEN
      RETURN FALSE
   END ;
   IF (NOT (IsFinite (lo) AND IsFinite (hi))) OR (NOT (lo < hi)) THEN RETURN FALSE END ;
   (* a NaN or infinity stops the search for the top nonzero coefficient, so
      it stays in c[0..n], whose finiteness Solve tests in its first pass *)
   n := degree ;
   WHILE (n >= 0) AND (c[n] = 0.0) DO
      DEC (n)
   END ;
   IF n <= 0 THEN RETURN FALSE END ;
   IF n = 1
   THEN
      IF NOT (IsFinite (c[0]) AND IsFinite (c[1])) THEN RETURN FALSE END ;
      (* one correctly rounded division: no scaling needed *)
      x := -c[0] / c[1] ;
      IF NOT ((lo < x) AND (x <= hi)) THEN RETURN FALSE END
   ELSIF NOT Solve (c, n, lo, hi, x)
   THEN
      RETURN FALSE
   END ;
   t := x + 0.0 ;
   RETURN TRUE
END Entry ;


(* QuadraticIn for the fast path, its root as SmallestRoot answers it (never
   -0.0); a procedure of its own so that the fast path's call of it is its
   last act (a jump, no frame). *)
PROCEDURE QuadraticExact (a, b, c, lo, hi: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   x: REAL ;
BEGIN
   IF NOT QuadraticIn (a, b, c, lo, hi, x) THEN RETURN FALSE END ;
   t := x + 0.0 ;
   RETURN TRUE
END QuadraticExact ;


(* True when the cubic c0 + c1 t + c2 t^2 + c3 t^3 has its Bernstein
   coefficients on [0, hi] all of one sign beyond their rounding: no root in
   [0, hi] (docs/roots.md step 1, "lo >= 0" (c)). FALSE says nothing.
   The t_i are c_i hi^i, the b_j the Bernstein coefficients (weights C(j,i)/C(3,i));
   their rounding is below 2^-50 sum |t_i|, m is 16 times that (NoneRel).
   gm2 may compile x > m as NOT (x <= m), true for a NaN; harmless: with finite
   c_i and hi >= 2^-250 no t_i is NaN, so m is finite or inf, and t0 = c0
   (finite) is never beyond inf; a NaN or infinite input answers none anyway. *)
PROCEDURE NoRoot3 (t0, c1, c2, c3, hi: REAL) : BOOLEAN ;
VAR
   h2, t1, t2, t3, b1, b2, b3, s, m: REAL ;
BEGIN
   h2 := hi * hi ;
   t1 := c1 * hi ;
   t2 := c2 * h2 ;
   t3 := c3 * (h2 * hi) ;
   b3 := (t0 + t1) + (t2 + t3) ;
   (* p(0), p(hi) of opposite signs: the usual case with a root, tested first *)
   IF (t0 < 0.0) # (b3 < 0.0) THEN RETURN FALSE END ;
   s := (ABS (t0) + ABS (t1)) + (ABS (t2) + ABS (t3)) ;
   m := NoneRel * s + NoneAbs ;
   b1 := t0 + t1 * Third ;
   b2 := (t0 + t1 * TwoThirds) + t2 * Third ;
   IF t0 > m
   THEN
      RETURN (b1 > m) AND (b2 > m) AND (b3 > m)
   END ;
   RETURN (t0 < -m) AND (b1 < -m) AND (b2 < -m) AND (b3 < -m)
END NoRoot3 ;


(* The quartic's counterpart of NoRoot3 (the same reasoning, weights C(j,i)/C(4,i)). *)
PROCEDURE NoRoot4 (t0, c1, c2, c3, c4, hi: REAL) : BOOLEAN ;
VAR
   h2, t1, t2, t3, t4, b1, b2, b3, b4, s, m: REAL ;
BEGIN
   h2 := hi * hi ;
   t1 := c1 * hi ;
   t2 := c2 * h2 ;
   t3 := c3 * (h2 * hi) ;
   t4 := c4 * (h2 * h2) ;
   b4 := ((t0 + t1) + (t2 + t3)) + t4 ;
   IF (t0 < 0.0) # (b4 < 0.0) THEN RETURN FALSE END ;
   s := ((ABS (t0) + ABS (t1)) + (ABS (t2) + ABS (t3))) + ABS (t4) ;
   m := NoneRel * s + NoneAbs ;
   b1 := t0 + t1 * 0.25 ;
   b2 := (t0 + t1 * 0.5) + t2 * Sixth ;
   b3 := (t0 + t1 * 0.75) + (t2 * 0.5 + t3 * 0.25) ;
   IF t0 > m
   THEN
      RETURN (b1 > m) AND (b2 > m) AND (b3 > m) AND (b4 > m)
   END ;
   RETURN (t0 < -m) AND (b1 < -m) AND (b2 < -m) AND (b3 < -m) AND (b4 < -m)
END NoRoot4 ;


PROCEDURE NoRootTo (VAR c: ARRAY OF REAL; degree: INTEGER; hi: REAL) : BOOLEAN ;
BEGIN
   IF NOT (hi >= HiMin) THEN RETURN FALSE END ;
   IF (degree = 3) AND (HIGH (c) >= 3) THEN RETURN NoRoot3 (c[0], c[1], c[2], c[3], hi) END ;
   IF (degree = 4) AND (HIGH (c) >= 4) THEN RETURN NoRoot4 (c[0], c[1], c[2], c[3], c[4], hi) END ;
   RETURN FALSE
END NoRootTo ;


(* The degree-2 fast path (docs/roots.md step 1) is written out in the
   exported entry, and everything else is left to Entry, called from two
   places so that gcc does not inline it (it inlines a procedure called once
   however large): the fast path then needs no stack frame and no saved
   registers (with Entry inlined, every call pushed six registers and made a
   frame of 232 bytes first), and the operations of QuadraticIn are copied
   here up to its error-free branch, which it is called for.  The admission
   reads only bits, no floating-point comparison, so that a NaN cannot pass it
   (gm2 may compile x < y as NOT (x >= y), true for a NaN): lo < hi with both
   finite as the bits of hi - lo in [1, MAX(REAL)'s] (positive and finite),
   and every coefficient zero or 2^-200 <= |c_i| < 2^200 (c2 nonzero) as the
   bits of its magnitude, exactly step 1's rule.  Degrees 3 and 4 with lo >= 0
   first ask NoRoot3 / NoRoot4. *)
PROCEDURE SmallestRoot (VAR c: ARRAY OF REAL; degree: INTEGER; lo, hi: REAL;
                        VAR t: REAL) : BOOLEAN ;
VAR
   a, b, cc, p, q, d, s, qq, r1, r2, x: REAL ;
   ua, ub, uc, uw: LONGCARD ;
BEGIN
   IF (degree = 2) AND (HIGH (c) >= 2)
   THEN
      a := c[2] ;
      b := c[1] ;
      cc := c[0] ;
      (* lo >= 0 and no sign change: none, at any magnitude (docs/roots.md
         step 1, "lo >= 0" (a)); a NaN that passes gm2's comparisons here
         answers none, as the contract wants *)
      IF (lo >= 0.0) AND (cc * b > 0.0) AND (b * a > 0.0) THEN RETURN FALSE END ;
      ua := CAST (LONGCARD, a) MOD SignBit ;
      ub := CAST (LONGCARD, b) MOD SignBit ;
      uc := CAST (LONGCARD, cc) MOD SignBit ;
      uw := CAST (LONGCARD, hi - lo) ;
      IF (ua >= ModerateLoBits) AND (ua < ModerateHiBits)
         AND ((ub = 0) OR (ub >= ModerateLoBits) AND (ub < ModerateHiBits))
         AND ((uc = 0) OR (uc >= ModerateLoBits) AND (uc < ModerateHiBits))
         AND (uw >= 1) AND (uw <= MaxRealBits)
      THEN
         p := b * b ;
         q := (4.0 * a) * cc ;
         d := p - q ;
         IF q <= 0.5 * p
         THEN
            IF d = 0.0
            THEN
               (* b = 0 and ac = 0: the double root *)
               x := -b / (2.0 * a) ;
               IF (lo < x) AND (x <= hi)
               THEN
                  t := x + 0.0 ;
                  RETURN TRUE
               END ;
               RETURN FALSE
            END
         ELSIF d < -Eps * (p + q)
         THEN
            RETURN FALSE
         ELSE
            (* cancellation possible: QuadraticIn's error-free discriminant *)
            RETURN QuadraticExact (a, b, cc, lo, hi, t)
         END ;
         s := sqrt (d) ;
         IF b < 0.0 THEN s := -s END ;
         qq := -0.5 * (b + s) ;
         r1 := qq / a ;
         r2 := cc / qq ;
         IF r2 < r1
         THEN
            x := r1 ;
            r1 := r2 ;
            r2 := x
         END ;
         IF (lo < r1) AND (r1 <= hi)
         THEN
            t := r1 + 0.0 ;
            RETURN TRUE
         END ;
         IF (lo < r2) AND (r2 <= hi)
         THEN
            t := r2 + 0.0 ;
            RETURN TRUE
         END ;
         RETURN FALSE
      END ;
      RETURN Entry (c, degree, lo, hi, t)
   END ;
   (* lo >= 0: most windows without a root answer none here (docs/roots.md
      step 1, "lo >= 0" (c)); hi >= 2^-250 keeps hi^2..hi^4 from underflowing *)
   IF (degree = 3) AND (HIGH (c) >= 3)
   THEN
      IF (lo >= 0.0) AND (hi >= HiMin) AND NoRoot3 (c[0], c[1], c[2], c[3], hi) THEN RETURN FALSE END
   ELSIF (degree = 4) AND (HIGH (c) >= 4)
   THEN
      IF (lo >= 0.0) AND (hi >= HiMin) AND NoRoot4 (c[0], c[1], c[2], c[3], c[4], hi) THEN RETURN FALSE END
   END ;
   RETURN Entry (c, degree, lo, hi, t)
END SmallestRoot ;


BEGIN
   Fact[0] := 1.0 ;
   FOR Init := 1 TO MaxDegree DO
      Fact[Init] := Fact[Init - 1] * VAL (REAL, Init)
   END ;
   Eps := ldexp (1.0, -52) ;
   Tiny := ldexp (1.0, -1000) ;
   Sixteenth := ldexp (1.0, -16) ;
   NewtonTol := ldexp (1.0, -30) ;
   HalleyTol := ldexp (1.0, -8) ;
   HalleyMin := ldexp (1.0, -968) ;
   HandoffTol := ldexp (1.0, -14) ;
   PolishTol := ldexp (1.0, -22) ;
   ModerateLo := ldexp (1.0, -200) ;
   ModerateHi := ldexp (1.0, 200) ;
   NoneRel := ldexp (1.0, -46) ;
   NoneAbs := ldexp (1.0, -900) ;
   HiMin := ldexp (1.0, -250) ;
   Third := 1.0 / 3.0 ;
   TwoThirds := 2.0 / 3.0 ;
   Sixth := 1.0 / 6.0 ;
   Inf := ldexp (1.0, 1023) ;
   Inf := Inf * 2.0
END Roots.
