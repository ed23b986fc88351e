IMPLEMENTATION MODULE ExactToc ;

(* The driver of docs/exact-motion.md, transcribed operation for operation
   from the C runtime (runtimes/c/src/m2c_exact.c). *)

FROM CMath IMPORT ldexp, cos, sqrt, floor ;
FROM Roots IMPORT SmallestRoot, IsFinite, MaxDegree ;

CONST
   MaxDepth = 40 ;       (* subdivision levels *)
   MaxSteps = 200 ;      (* zones visited per level *)
   PolishSteps = 4 ;     (* Newton steps on the exact gap *)

TYPE
   Params = ARRAY [0..MaxParams - 1] OF REAL ;
   Coeffs = ARRAY [0..MaxDegree] OF REAL ;

VAR
   Safe,                 (* 1 + 2^-40: covers the rounding of Reach *)
   Floor,                (* 2^-46 = 64 eps: the rounding floor is Floor * scale *)
   TwoM30,               (* 2^-30 *)
   Sharp,                (* 2^-42: a root known to this relative width is not polished *)
   Settled,              (* 2^-50: a Newton step this small (relative, 4 ulps) ends the polish *)
   Slack,                (* 2^-40: the lower bound on the gap at t = 0 against its roundings *)
   Inf: REAL ;           (* infinity *)
   (* the call being answered (the driver is not reentrant) *)
   Cur: Motion ;
   Par: Params ;
   CurSolver: SolverProc ;
   CurZeroTol: REAL ;
   (* two circles without orbits: the differences of GapAt (x0, x1, x2, y0,
      y1, y2, R); the gap is then this polynomial and its scale the layout's
      magnitude sum (UsePd) *)
   UsePd: BOOLEAN ;
   Pd: ARRAY [0..6] OF REAL ;
   Two50: REAL ;         (* 2^-50 *)


PROCEDURE Defaults (VAR o: Options) ;
BEGIN
   o.windowAngle := WindowAngle ;
   o.refine := TRUE ;
   o.zeroTol := 0.0 ;
   o.solver := SmallestRoot
END Defaults ;


PROCEDURE Value (VAR c: Coeffs; n: INTEGER; x: REAL) : REAL ;
VAR
   v: REAL ;
   i: INTEGER ;
BEGIN
   v := c[n] ;
   FOR i := n - 1 TO 0 BY -1 DO
      v := v * x + c[i]
   END ;
   RETURN v
END Value ;


PROCEDURE Slope (VAR c: Coeffs; n: INTEGER; x: REAL) : REAL ;
VAR
   d: REAL ;
   i: INTEGER ;
BEGIN
   IF n < 1 THEN RETURN 0.0 END ;
   d := VAL (REAL, n) * c[n] ;
   FOR i := n - 1 TO 1 BY -1 DO
      d := d * x + VAL (REAL, i) * c[i]
   END ;
   RETURN d
END Slope ;


(* A bound on |p(s) - p(0)| for 0 <= s <= L, a little above the rounded sum. *)
PROCEDURE Reach (VAR c: Coeffs; n: INTEGER; L: REAL) : REAL ;
VAR
   b: REAL ;
   i: INTEGER ;
BEGIN
   IF n < 1 THEN RETURN 0.0 END ;
   b := c[n] ;   (* not ABS (c[n]): gm2 -Wall counts no use inside ABS *)
   b := ABS (b) ;
   FOR i := n - 1 TO 1 BY -1 DO
      b := b * L + ABS (c[i])
   END ;
   RETURN b * L * Safe
END Reach ;


(* Two circles without orbits: the magnitude sum of the gap's terms at
   time t, (|r1| + |r2|)^2 + Y^2 + X^2 with X = |x1| + |x2| + (|vx1| +
   |vx2|) |t| + (|ax1| + |ax2|) t^2/2 (the value the generated scale gives
   at t = 0 when the orbit radii are zero). *)
PROCEDURE StillScale (t: REAL) : REAL ;
VAR
   u, u2, sr, sx, sy, ax, ay: REAL ;
BEGIN
   sr := ABS (Par[Cur.circles[11]]) + ABS (Par[Cur.circles[23]]) ;
   IF t = 0.0 THEN              (* the same value, the terms in t being zero *)
      ax := ABS (Par[Cur.circles[0]]) + ABS (Par[Cur.circles[12]]) ;
      ay := ABS (Par[Cur.circles[1]]) + ABS (Par[Cur.circles[13]]) ;
      RETURN sr * sr + ay * ay + ax * ax
   END ;
   u := ABS (t) ;
   u2 := 0.5 * u * u ;
   sx := ABS (Par[Cur.circles[0]]) + ABS (Par[Cur.circles[12]])
         + (ABS (Par[Cur.circles[2]]) + ABS (Par[Cur.circles[14]])) * u
         + (ABS (Par[Cur.circles[4]]) + ABS (Par[Cur.circles[16]])) * u2 ;
   sy := ABS (Par[Cur.circles[1]]) + ABS (Par[Cur.circles[13]])
         + (ABS (Par[Cur.circles[3]]) + ABS (Par[Cur.circles[15]])) * u
         + (ABS (Par[Cur.circles[5]]) + ABS (Par[Cur.circles[17]])) * u2 ;
   RETURN sr * sr + sy * sy + sx * sx
END StillScale ;


PROCEDURE FloorAt (t: REAL) : REAL ;
BEGIN
   IF UsePd THEN RETURN Floor * StillScale (t) END ;
   RETURN Floor * Cur.scale (Par, t)
END FloorAt ;


(* The exact gap and its derivative: the motion's, or for two circles
   without orbits the centres' distance squared minus the radii's sum
   squared, differences first (Pd). *)
PROCEDURE GapAt (t: REAL) : REAL ;
VAR
   x, y: REAL ;
BEGIN
   IF NOT UsePd THEN RETURN Cur.gap (Par, t) END ;
   x := (Pd[2] * t + Pd[1]) * t + Pd[0] ;
   y := (Pd[5] * t + Pd[4]) * t + Pd[3] ;
   RETURN y * y - Pd[6] * Pd[6] + x * x
END GapAt ;


PROCEDURE GapDtAt (t: REAL) : REAL ;
VAR
   x, y: REAL ;
BEGIN
   IF NOT UsePd THEN RETURN Cur.gapDt (Par, t) END ;
   x := (Pd[2] * t + Pd[1]) * t + Pd[0] ;
   y := (Pd[5] * t + Pd[4]) * t + Pd[3] ;
   RETURN 2.0 * (x * (2.0 * Pd[2] * t + Pd[1]) + y * (2.0 * Pd[5] * t + Pd[4]))
END GapDtAt ;


(* ---- Two circles: the whole-horizon bound (docs/exact-motion.md) ----
   H(t) = |D(t)|^2 - (R + rho1 + rho2)^2, D the centres' difference without
   orbits, R the sum of radii, rho a bound on an orbit offset's length: the
   gap is positive wherever H > 0. *)

(* A bound on |(sin(wx t + phx), sin(wy t + phy))| times |radius|: with
   wx = wy the squared length is 1 - cos(A + B) cos(phx - phy) <= 1 +
   |cos(phx - phy)| (1 for a circular orbit), else at most 2. *)
PROCEDURE OrbitReach (radius, wx, phx, wy, phy: REAL) : REAL ;
VAR
   k2: REAL ;
BEGIN
   IF radius = 0.0 THEN RETURN 0.0 END ;
   k2 := 2.0 ;
   IF wx = wy THEN
      k2 := 1.0 + (ABS (cos (phx - phy)) + Two50 * (1.0 + ABS (phx) + ABS (phy)))
   END ;
   RETURN ABS (radius) * sqrt (k2) * Safe
END OrbitReach ;


(* H's coefficients h[0..4], the differences Pd, margin a bound on the
   rounding of H on [0, T]; returns rho1 + rho2.  Without orbits (rho1 =
   rho2 = 0) H is the exact gap, differences first. *)
PROCEDURE CirclesBound (VAR m: Motion; VAR p: ARRAY OF REAL; T: REAL;
                        VAR h: Coeffs; VAR margin: REAL) : REAL ;
VAR
   x0, y0, x1, y1, x2, y2, rho, r, big, sx, sy: REAL ;
BEGIN
   x0 := p[m.circles[0]] - p[m.circles[12]] ;
   y0 := p[m.circles[1]] - p[m.circles[13]] ;
   x1 := p[m.circles[2]] - p[m.circles[14]] ;
   y1 := p[m.circles[3]] - p[m.circles[15]] ;
   x2 := 0.5 * (p[m.circles[4]] - p[m.circles[16]]) ;
   y2 := 0.5 * (p[m.circles[5]] - p[m.circles[17]]) ;
   rho := OrbitReach (p[m.circles[6]], p[m.circles[7]], p[m.circles[8]], p[m.circles[9]], p[m.circles[10]])
          + OrbitReach (p[m.circles[18]], p[m.circles[19]], p[m.circles[20]], p[m.circles[21]],
                        p[m.circles[22]]) ;
   r := ABS (p[m.circles[11]] + p[m.circles[23]]) ;
   IF rho = 0.0 THEN big := r ELSE big := (r + rho) * Safe END ;   (* no orbit: H is the exact gap *)
   h[0] := x0 * x0 + y0 * y0 - big * big ;
   h[1] := 2.0 * (x0 * x1 + y0 * y1) ;
   h[2] := x1 * x1 + y1 * y1 + 2.0 * (x0 * x2 + y0 * y2) ;
   h[3] := 2.0 * (x1 * x2 + y1 * y2) ;
   h[4] := x2 * x2 + y2 * y2 ;
   sx := ABS (x0) + (ABS (x1) + ABS (x2) * T) * T ;
   sy := ABS (y0) + (ABS (y1) + ABS (y2) * T) * T ;
   margin := Floor * (sx * sx + sy * sy + big * big) ;
   Pd[0] := x0 ; Pd[1] := x1 ; Pd[2] := x2 ;
   Pd[3] := y0 ; Pd[4] := y1 ; Pd[5] := y2 ; Pd[6] := r ;
   RETURN rho
END CirclesBound ;


(* A lower bound on the gap at t = 0 from CirclesBound's differences (Pd)
   and orbit reach rho: the centres are |D| apart without their orbits,
   each orbit offset at most its rho, so the gap is at least (|D| - rho)^2 -
   R^2 (|D| rounded down, the square and R^2 by 2^-40 against the
   roundings); -Inf when |D| <= rho. *)
PROCEDURE ClearAtZero (rho: REAL) : REAL ;
VAR
   dist, s: REAL ;
BEGIN
   dist := sqrt (Pd[0] * Pd[0] + Pd[3] * Pd[3]) * (1.0 - Slack) ;
   IF NOT (dist > rho) THEN RETURN -Inf END ;
   s := dist - rho ;
   RETURN s * s * (1.0 - Slack) - Pd[6] * Pd[6] * (1.0 + Slack)
END ClearAtZero ;


(* Two circles: the window rate, the largest |angular velocity| of the
   orbit terms of the bodies that orbit (radius not zero).  It is what the
   generated rate gives for this layout (each approximation's error term is
   its body's orbit radius times a factor, and the radius squared is one of
   them), without its sines. *)
PROCEDURE CirclesRate (VAR m: Motion; VAR p: ARRAY OF REAL) : REAL ;
VAR
   rate, wx, wy: REAL ;
   b: INTEGER ;
BEGIN
   rate := 0.0 ;
   b := 0 ;
   WHILE b <= 12 DO
      IF p[m.circles[b + 6]] # 0.0 THEN
         wx := ABS (p[m.circles[b + 7]]) ;
         wy := ABS (p[m.circles[b + 9]]) ;
         IF wx > rate THEN rate := wx END ;
         IF wy > rate THEN rate := wy END
      END ;
      b := b + 12
   END ;
   RETURN rate
END CirclesRate ;


(* The first t in [lo, T] where H(t) <= 2 margin (H > margin, so the gap
   > 0, before it), or 2 T + 1 when there is none. *)
PROCEDURE Entry (VAR h: Coeffs; n: INTEGER; margin, lo, T: REAL) : REAL ;
VAR
   q: Coeffs ;
   i: INTEGER ;
   r: REAL ;
BEGIN
   IF Value (h, n, lo) <= 2.0 * margin THEN RETURN lo END ;
   FOR i := 0 TO n DO q[i] := h[i] END ;
   q[0] := h[0] - 2.0 * margin ;
   IF SmallestRoot (q, n, lo, T, r) THEN RETURN r END ;
   RETURN 2.0 * T + 1.0
END Entry ;


(* How far the exact gap's root may lie from the root s of the polynomial c
   of degree n that is within err of the gap: err / |c'(s)| (infinite where
   c' is zero). *)
PROCEDURE Width (VAR c: Coeffs; n: INTEGER; s, err: REAL) : REAL ;
VAR
   d: REAL ;
BEGIN
   d := ABS (Slope (c, n, s)) ;
   IF d > 0.0 THEN RETURN err / d END ;
   RETURN Inf
END Width ;


(* The polynomial c of degree n is the exact gap: its smallest root in
   (start, horizon], polished. *)
PROCEDURE PolySearch (VAR c: Coeffs; n: INTEGER; start, horizon: REAL; refine: BOOLEAN;
                      VAR t: REAL) : INTEGER ;
VAR
   r: REAL ;
BEGIN
   IF NOT CurSolver (c, n, start, horizon, r) THEN RETURN 0 END ;
   IF refine THEN r := Polish (r, start, horizon, start, horizon) END ;
   IF r > horizon THEN r := horizon END ;
   t := r + 0.0 ;
   RETURN 1
END PolySearch ;


(* The first root of the exact gap in [t0, t0 + L] (closed) or (t0, t0 + L]:
   1 with r, its bracket [a, b] and wd how far the gap's root may lie from
   r, 0 for none, -1 on an error. *)
PROCEDURE FirstRoot (t0, L: REAL; closed: BOOLEAN; depth: INTEGER;
                     VAR r, a, b, wd: REAL) : INTEGER ;
VAR
   pp: Params ;
   c, q: Coeffs ;
   n, i, step, st: INTEGER ;
   e, f, s, mg, x, z, v, d, w, we: REAL ;
BEGIN
   IF Cur.hasWindow THEN
      n := Cur.window (Par, t0, L, c, e)
   ELSE
      Cur.shift (Par, t0, pp) ;
      n := Cur.coefficients (pp, c) ;
      IF (n >= 0) AND (n <= MaxDegree) THEN e := Cur.truncation (pp, L) END
   END ;
   IF (n < 0) OR (n > MaxDegree) THEN RETURN -1 END ;
   f := FloorAt (t0 + L) ;
   a := t0 ;
   b := t0 + L ;
   IF closed AND (ABS (c[0]) <= f) THEN
      r := t0 ;
      wd := Inf ;
      RETURN 1
   END ;
   IF (e <= f) OR (depth >= MaxDepth) THEN
      IF NOT CurSolver (c, n, 0.0, L, s) THEN RETURN 0 END ;
      r := t0 + s ;
      wd := Width (c, n, s, e + f) ;
      RETURN 1
   END ;
   mg := e + f ;
   IF ABS (c[0]) - Reach (c, n, L) > mg THEN RETURN 0 END ;   (* |P| > mg on the whole window *)
   x := 0.0 ;
   FOR step := 1 TO MaxSteps DO
      v := Value (c, n, x) ;
      IF ABS (v) <= mg THEN
         z := x
      ELSE
         FOR i := 0 TO n DO q[i] := c[i] END ;
         IF v > 0.0 THEN q[0] := c[0] - mg ELSE q[0] := c[0] + mg END ;
         IF NOT CurSolver (q, n, x, L, z) THEN RETURN 0 END
      END ;
      d := Slope (c, n, z) ;
      w := L - z ;               (* to the window's end, at most half the window *)
      IF w > 0.5 * L THEN w := 0.5 * L END ;
      IF d # 0.0 THEN
         we := 8.0 * mg / ABS (d) ;
         IF we < w THEN w := we END
      END ;
      IF NOT (w > 0.0) THEN RETURN 0 END ;
      st := FirstRoot (t0 + z, w, closed OR (z > 0.0), depth + 1, r, a, b, wd) ;
      IF st # 0 THEN RETURN st END ;
      x := z + w ;
      IF NOT (x < L) THEN RETURN 0 END
   END ;
   (* too many zones: this level's polynomial decides the rest *)
   IF NOT CurSolver (c, n, x, L, s) THEN RETURN 0 END ;
   a := t0 + x ;
   b := t0 + L ;
   r := t0 + s ;
   wd := Width (c, n, s, mg) ;
   RETURN 1
END FirstRoot ;


(* Newton steps on the exact gap, kept while |gap| decreases inside [a, b]
   and (lo, hi]; a step of at most Settled times the root is taken without
   evaluating the gap there, and ends the polish.  The driver polishes a root only when it may lie more than
   Sharp r from the gap's (near a double root, or where the rounding or
   truncation of its polynomial is large). *)
PROCEDURE Polish (x, a, b, lo, hi: REAL) : REAL ;
VAR
   g, d, xn, gn: REAL ;
   i: INTEGER ;
BEGIN
   g := GapAt (x) ;
   FOR i := 1 TO PolishSteps DO
      IF g = 0.0 THEN RETURN x END ;
      d := GapDtAt (x) ;
      IF NOT (d # 0.0) THEN RETURN x END ;
      xn := x - g / d ;
      IF NOT ((xn >= a) AND (xn <= b) AND (xn > lo) AND (xn <= hi)) THEN RETURN x END ;
      (* converged to rounding: the next step would be noise *)
      IF ABS (xn - x) <= Settled * ABS (xn) THEN RETURN xn END ;
      gn := GapAt (xn) ;
      IF NOT (ABS (gn) < ABS (g)) THEN RETURN x END ;
      x := xn ;
      g := gn
   END ;
   RETURN x
END Polish ;


(* Where a contact at t = 0 that separates has left the zero band. *)
PROCEDURE Depart (horizon, band0, d0: REAL) : REAL ;
VAR
   tau, band: REAL ;
   i: INTEGER ;
BEGIN
   IF d0 > 0.0 THEN tau := 2.0 * band0 / d0 ELSE tau := horizon * TwoM30 END ;
   IF NOT (tau > 0.0) THEN tau := horizon * TwoM30 END ;
   FOR i := 1 TO 200 DO
      IF NOT (tau < horizon) THEN RETURN horizon END ;
      band := FloorAt (tau) ;
      IF CurZeroTol > band THEN band := CurZeroTol END ;
      IF ABS (GapAt (tau)) > 2.0 * band THEN RETURN tau END ;
      tau := 2.0 * tau
   END ;
   RETURN horizon
END Depart ;


CONST
   Search = 3 ;          (* Begin: search (start, horizon] *)

(* The checks and the rules at t = 0 shared by FirstContact and PolyContact
   (m and p become the call's Cur and Par): -1 an error, 0 none, 1 a contact
   at 0, Overlapped, or Search with start (0, or where a separating contact
   at 0 has left the zero band). *)
PROCEDURE Begin (VAR m: Motion; VAR p: ARRAY OF REAL; horizon, clear0: REAL;
                 VAR o: Options; VAR t, start: REAL) : INTEGER ;
VAR
   i: INTEGER ;
   band0, g0, d0: REAL ;
BEGIN
   IF (m.nparams < 0) OR (m.nparams > MaxParams) OR (m.maxDegree > MaxDegree)
      OR (VAL (INTEGER, HIGH (p)) + 1 < m.nparams) THEN
      RETURN -1
   END ;
   IF NOT (o.windowAngle > 0.0) OR NOT IsFinite (o.windowAngle) OR NOT (o.zeroTol >= 0.0) THEN
      RETURN -1
   END ;
   IF NOT IsFinite (horizon) OR NOT (horizon > 0.0) THEN RETURN 0 END ;
   FOR i := 0 TO m.nparams - 1 DO
      IF NOT IsFinite (p[i]) THEN RETURN 0 END
   END ;
   Cur := m ;
   FOR i := 0 TO m.nparams - 1 DO Par[i] := p[i] END ;
   CurSolver := o.solver ;
   CurZeroTol := o.zeroTol ;
   start := 0.0 ;
   band0 := FloorAt (0.0) ;
   IF o.zeroTol > band0 THEN band0 := o.zeroTol END ;
   IF clear0 > 2.0 * band0 THEN RETURN Search END ;
   g0 := GapAt (0.0) ;
   IF g0 < -band0 THEN          (* inside each other at t = 0: not a contact, its own answer *)
      t := 0.0 ;
      RETURN Overlapped
   END ;
   IF ABS (g0) <= band0 THEN
      d0 := GapDtAt (0.0) ;
      IF d0 < 0.0 THEN
         t := 0.0 ;
         RETURN 1
      END ;
      start := Depart (horizon, band0, d0) ;
      IF NOT (start < horizon) THEN RETURN 0 END
   END ;
   RETURN Search
END Begin ;


(* Two circles without orbits: their gap is the polynomial H of
   CirclesBound (exact up to its margin), solved once over (start,
   horizon]; the root is polished on the gap only when its width under that
   margin exceeds Sharp r. *)
PROCEDURE StillCircles (VAR m: Motion; VAR p: ARRAY OF REAL; horizon: REAL;
                        VAR o: Options; VAR t: REAL) : INTEGER ;
VAR
   st, n: INTEGER ;
   start, margin, rho, r: REAL ;
   h: Coeffs ;
BEGIN
   rho := CirclesBound (m, p, horizon, h, margin) ;
   UsePd := TRUE ;
   st := Begin (m, p, horizon, -Inf, o, t, start) ;
   IF st # Search THEN RETURN st END ;
   n := 4 ;
   WHILE (n > 0) AND (h[n] = 0.0) DO n := n - 1 END ;
   IF NOT CurSolver (h, n, start, horizon, r) THEN RETURN 0 END ;
   IF o.refine AND NOT (Width (h, n, r, margin) <= Sharp * r) THEN
      r := Polish (r, start, horizon, start, horizon)
   END ;
   IF r > horizon THEN r := horizon END ;
   t := r + 0.0 ;
   RETURN 1
END StillCircles ;


PROCEDURE FirstContact (VAR m: Motion; VAR p: ARRAY OF REAL; horizon: REAL;
                        VAR o: Options; VAR t: REAL) : INTEGER ;
VAR
   st, n, nb: INTEGER ;
   start, span, h, rate, t0, t1, w, wj, L, r, a, b, s, e, mb, rho, wd, clear0: REAL ;
   bound: BOOLEAN ;
   pp: Params ;
   c, hb: Coeffs ;
BEGIN
   UsePd := FALSE ;
   bound := FALSE ;
   clear0 := -Inf ;
   nb := 0 ;
   mb := 0.0 ;
   IF m.hasCircles AND (VAL (INTEGER, HIGH (p)) + 1 >= m.nparams)
      AND (p[m.circles[6]] = 0.0) AND (p[m.circles[18]] = 0.0) THEN
      RETURN StillCircles (m, p, horizon, o, t)    (* no orbit: no windows *)
   END ;
   (* (non-finite parameters or horizon: Begin answers before any use) *)
   IF m.hasCircles AND (VAL (INTEGER, HIGH (p)) + 1 >= m.nparams) THEN
      bound := TRUE ;
      rho := CirclesBound (m, p, horizon, hb, mb) ;
      nb := 4 ;
      WHILE (nb > 0) AND (hb[nb] = 0.0) DO nb := nb - 1 END ;
      clear0 := ClearAtZero (rho)
   END ;
   st := Begin (m, p, horizon, clear0, o, t, start) ;
   IF st # Search THEN RETURN st END ;
   IF bound THEN e := Entry (hb, nb, mb, start, horizon) ELSE e := start END ;
   IF NOT (e <= horizon) THEN RETURN 0 END ;   (* the bound keeps the circles apart over the whole horizon *)
   span := horizon - start ;
   h := span ;
   IF bound THEN rate := CirclesRate (m, p) ELSE rate := Cur.rate (Par) END ;
   IF (rate > 0.0) AND (o.windowAngle / rate < span) THEN h := o.windowAngle / rate END ;
   IF span / h > MaxWindows THEN RETURN -1 END ;
   t0 := start ;
   w := 0.0 ;
   LOOP
      IF e > t0 THEN             (* skip the windows that end before the bound's zone *)
         wj := floor ((e - start) / h) ;
         IF (wj > 0.0) AND (start + wj * h > e) THEN wj := wj - 1.0 END ;
         IF wj > w THEN
            w := wj ;
            t0 := start + w * h
         END
      END ;
      IF NOT (t0 < horizon) THEN RETURN 0 END ;
      t1 := start + (w + 1.0) * h ;
      IF NOT (t1 < horizon) THEN t1 := horizon END ;
      L := t1 - t0 ;
      IF o.refine THEN
         st := FirstRoot (t0, L, w > 0.0, 0, r, a, b, wd) ;
         IF (st = 1) AND NOT (wd <= Sharp * r) THEN r := Polish (r, a, b, start, horizon) END
      ELSE
         Cur.shift (Par, t0, pp) ;
         n := Cur.coefficients (pp, c) ;
         IF (n < 0) OR (n > MaxDegree) THEN
            st := -1
         ELSIF ABS (c[0]) - Reach (c, n, L) > 0.0 THEN
            st := 0
         ELSIF CurSolver (c, n, 0.0, L, s) THEN
            st := 1 ;
            r := t0 + s
         ELSE
            st := 0
         END
      END ;
      IF st < 0 THEN RETURN -1 END ;
      IF st = 1 THEN
         IF r > horizon THEN r := horizon END ;
         t := r + 0.0 ;
         RETURN 1
      END ;
      t0 := t1 ;
      w := w + 1.0 ;
      IF bound AND (t0 < horizon) THEN
         e := Entry (hb, nb, mb, t0, horizon) ;
         IF NOT (e <= horizon) THEN RETURN 0 END
      END
   END
END FirstContact ;


(* What PolyContact's motion holds for the pieces it never calls. *)
PROCEDURE NoShift (VAR p: ARRAY OF REAL; t: REAL; VAR out: ARRAY OF REAL) ;
VAR
   i: INTEGER ;
BEGIN
   t := t ;
   FOR i := 0 TO VAL (INTEGER, HIGH (out)) DO out[i] := p[i] END
END NoShift ;


PROCEDURE NoValue (VAR p: ARRAY OF REAL; t: REAL) : REAL ;
BEGIN
   p[0] := p[0] ;
   t := t ;
   RETURN 0.0
END NoValue ;


PROCEDURE NoRate (VAR p: ARRAY OF REAL) : REAL ;
BEGIN
   p[0] := p[0] ;
   RETURN 0.0
END NoRate ;


PROCEDURE PolyContact (VAR m: PolyMotion; VAR p: ARRAY OF REAL; horizon: REAL;
                       VAR o: Options; VAR t: REAL) : INTEGER ;
VAR
   st, n: INTEGER ;
   start: REAL ;
   c: Coeffs ;
   mo: Motion ;
BEGIN
   mo.nparams := m.nparams ;
   mo.maxDegree := m.maxDegree ;
   mo.coefficients := m.coefficients ;
   mo.shift := NoShift ;
   mo.gap := m.gap ;
   mo.gapDt := m.gapDt ;
   mo.scale := m.scale ;
   mo.truncation := NoValue ;
   mo.rate := NoRate ;
   mo.hasCircles := FALSE ;
   mo.hasWindow := FALSE ;
   UsePd := FALSE ;
   st := Begin (mo, p, horizon, -Inf, o, t, start) ;
   IF st # Search THEN RETURN st END ;
   n := Cur.coefficients (Par, c) ;
   IF (n < 0) OR (n > MaxDegree) THEN RETURN -1 END ;
   RETURN PolySearch (c, n, start, horizon, o.refine, t)
END PolyContact ;


BEGIN
   Floor := ldexp (1.0, -46) ;
   Safe := 1.0 + ldexp (1.0, -40) ;
   TwoM30 := ldexp (1.0, -30) ;
   Two50 := ldexp (1.0, -50) ;
   Sharp := ldexp (1.0, -42) ;
   Settled := ldexp (1.0, -50) ;
   Slack := ldexp (1.0, -40) ;
   Inf := ldexp (1.0, 1100) ;   (* overflows to infinity *)
   UsePd := FALSE
END ExactToc.
