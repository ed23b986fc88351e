IMPLEMENTATION MODULE SimPredict ;

(* Predictions: a transcription of the Python reference
   (runtimes/python/max2code_rt/sim/), procedure for procedure, with the
   same IEEE double operations in the same order (no FMA: built with
   -ffp-contract=off; sin and cos are libm's through RealMath, sqrt libm's
   through CMath).  The reference's predict_cc, predict_pe, pe_coefficients,
   pe_first, circles_first, circles_apart, cc_count, centre_params,
   circle_params, bounds_meet and features are PredictCC, PredictPE,
   PeCoefficients, PeFirst, CirclesFirst, CirclesApart, CcCount,
   CentreParams, CircleParams, BoundsMeet and Features.

   The generated entries of equations/circle-circle.mxm and
   equations/point-edge.mxm are included below from the build directory
   (gm2 -fcpp, the build directory on the include path): the build
   (max2code/toolchain/m2.py) includes their selection entries here and
   their coefficient procedures as part modules that the included text
   imports, as gm2 12 takes time in the square of a module's length
   (max2code/toolchain/m2_split.py).  The build defines
   SIM_CC_VARIANTS and SIM_PE_VARIANTS, the number of variants each
   NAME_variant counts (max2code/toolchain/m2.py reads them from the
   generated files). *)

FROM SYSTEM IMPORT ADR ;
FROM RealMath IMPORT cos, sin ;
FROM Roots IMPORT IsFinite, NoRootTo, SmallestRoot ;
FROM CMath IMPORT sqrt ;
FROM SimScene IMPORT Alpha, Bodies, BodyRef, CellH, CellW, EndT, GridMargin, GridNX, GridNY, GridX0, GridY0,
                     Grow, HalfCell, MAX_VERTICES, MaxItems, NBodies, Tol, Vertex, Verts ;
FROM SimQueue IMPORT Event, FeatCC, FeatPE, KCell ;
FROM SimGrid IMPORT Cells, large_near, Max, Min, Near ;
FROM SimWorld IMPORT CcCounts, Fails, Inf, NCc, NPe, PeCounts, push, push_collision, push_horizon, Stats ;
FROM SimMotion IMPORT PointAt, StateAt, TurnRate ;
FROM SimSupport IMPORT schedule_support ;
FROM SimSleep IMPORT grounded ;
FROM SimOverlap IMPORT edge_line, polygons_separation, separation, VertexPoints ;

#include "circle_circle.mxd"
#include "point_edge.mxd"

CONST
   HalfPi = 1.5707963267948966 ;   (* pi/2 rounded to double (cos x = sin(x + pi/2)) *)
   (* the most stages (a meeting of the bounds, a clear stretch, a Taylor
      window) one prediction of a pair goes through before it leaves the rest
      to a horizon *)
   Chain = 8 ;
   (* windows: a clear stretch of two turning polygons shorter than this
      leads straight to the window at its end (the TOI library only) *)
   Straight = 4.0 ;
   (* CirclesApart's margins: far above the coefficients' rounding *)
   TwoM40 = 1.0 / 1099511627776.0 ;
   TwoM30 = 1.0 / 1073741824.0 ;
   TwoM90 = TwoM30 * TwoM30 * TwoM30 ;
   TwoM450 = TwoM90 * TwoM90 * TwoM90 * TwoM90 * TwoM90 ;   (* ... and its bounds on sizes *)
   TwoP450 = 1.0 / TwoM450 ;
   TwoM900 = TwoM450 * TwoM450 ;
   (* FirstContact's margin: a root beyond before (1 + 2^-10) is far beyond before *)
   BeforeMargin = 1.0 / 1024.0 ;
   (* NoRootHigh's margin and least interval *)
   TwoM46 = 1.0 / 70368744177664.0 ;
   TwoM100 = TwoM90 * (1.0 / 1024.0) ;
   CcVariants = SIM_CC_VARIANTS ;
   PeVariants = SIM_PE_VARIANTS ;
   CcMaxDegree = circle_circle_coefficients_max_degree ;
   PeMaxDegree = point_edge_coefficients_max_degree ;

TYPE
   (* the point_edge polynomial of one edge (bound_polygon's) *)
   EdgePoly = RECORD
      deg: INTEGER ;
      c: ARRAY [0..PeMaxDegree] OF REAL ;
   END ;
   EdgePolyArray = POINTER TO ARRAY [0..MaxItems - 1] OF EdgePoly ;
   (* The circle_circle parameters of a moving circle's centre (CircleParams
      or CentreParams), in the order x, vx, ax, d, e, f, y, vy, ay, p, q. *)
   CParams = ARRAY [0..10] OF REAL ;
   (* The best contact of a pair so far. *)
   Best = RECORD
      found: BOOLEAN ;
      t: REAL ;
      feat, a, b, i, j: INTEGER ;
   END ;

VAR
   (* the point-edge check of the prediction under way (predict_pe's inside) *)
   ChkX, ChkY: BodyRef ;
   ChkRho, ChkBeta: REAL ;     (* the point: rho, beta about X's centre (rho 0: the centre) *)
   ChkEdge: INTEGER ;
   ChkVert: INTEGER ;          (* the point is X's vertex ChkVert (local index; -1: not a vertex) *)
   ChkNow: REAL ;
   EdgePolys: EdgePolyArray ;  (* bound_polygon's polynomials, one per edge of the polygon *)
   Binomial: ARRAY [0..8], [0..8] OF REAL ;    (* C(j, i), exact; set by the module's body *)
   CapEdgePolys: INTEGER ;
   (* WindowBound's values per edge of the window's edge polygon: the outward
      unit normal now, the gap (m) of the vertex polygon's centre beyond the
      edge's line now, and the margin (m) of the line's offset *)
   WinEX, WinEY, WinOff, WinSlack: ARRAY [0..MAX_VERTICES - 1] OF REAL ;
   (* and the place (m) of that centre along the edge's tangent (-WinEY, WinEX)
      now, and the edge's extent (m) widened by the margins *)
   WinAlong, WinLo, WinHi: ARRAY [0..MAX_VERTICES - 1] OF REAL ;
   (* clear_time's vertices of its two polygons, their velocities (m/s) from
      their turns (spin_velocities), and edges_clear's gaps of one axis (m) *)
   ClrAX, ClrAY, ClrBX, ClrBY: ARRAY [0..MAX_VERTICES - 1] OF REAL ;
   ClrAWX, ClrAWY, ClrBWX, ClrBWY, ClrGap: ARRAY [0..MAX_VERTICES - 1] OF REAL ;


(* A neighbour of X's vertex i at t lies more than the tolerance behind the
   line (c, sn) . (p - (qx, qy)) = h (an edge's line: its outward unit
   normal (c, sn), its body's centre (qx, qy)), previous neighbour first
   (docs/simulator.md, "Corners"). *)
PROCEDURE behind (X: BodyRef; i: INTEGER; t, qx, qy, c, sn, h: REAL) : BOOLEAN ;
VAR
   px, py, pvx, pvy, pa, lim, kx, ky: REAL ;
   n, m, k: INTEGER ;
   v: Vertex ;
BEGIN
   n := X^.nv ;
   StateAt (X, t, px, py, pvx, pvy, pa) ;
   lim := -Tol ;
   FOR m := 0 TO 1 DO
      IF m = 0 THEN k := (i + n - 1) MOD n ELSE k := (i + 1) MOD n END ;
      v := Verts^[X^.v0 + k] ;
      kx := px + v.rho * cos (pa + v.beta) ;
      ky := py + v.rho * sin (pa + v.beta) ;
      IF (kx - qx) * c + (ky - qy) * sn - h < lim THEN RETURN TRUE END
   END ;
   RETURN FALSE
END behind ;


(* The point-edge check of predict_pe: whether the contact at s lies on the
   edge (within the tolerance) and, when the point is X's vertex ChkVert,
   neither of its neighbours lies behind the edge's line (behind); the
   prediction sets Chk*. *)
PROCEDURE Inside (s: REAL) : BOOLEAN ;
VAR
   t, px, py, pvx, pvy, pa, qx, qy, qvx, qvy, qa, th, c, sn, along: REAL ;
   ed: Vertex ;
BEGIN
   ed := Verts^[ChkEdge] ;
   t := ChkNow + s ;
   StateAt (ChkX, t, px, py, pvx, pvy, pa) ;
   IF ChkRho # 0.0 THEN
      px := px + ChkRho * cos (pa + ChkBeta) ;
      py := py + ChkRho * sin (pa + ChkBeta)
   END ;
   StateAt (ChkY, t, qx, qy, qvx, qvy, qa) ;
   th := qa + ed.psi ;
   c := cos (th) ;
   sn := sin (th) ;
   along := (px - qx) * (-sn) + (py - qy) * c ;
   IF NOT ((ed.s1 - Tol <= along) AND (along <= ed.s2 + Tol)) THEN RETURN FALSE END ;
   IF ChkVert < 0 THEN RETURN TRUE END ;
   RETURN NOT behind (ChkX, ChkVert, t, qx, qy, c, sn, ed.h)
END Inside ;


PROCEDURE Check (edge: BOOLEAN; s: REAL) : BOOLEAN ;
BEGIN
   IF edge THEN RETURN Inside (s) END ;
   RETURN TRUE
END Check ;


(* At a zero s of the gap c: approaching (first derivative d < 0), or
   resting and pressed together (d = 0, second derivative < 0). *)
PROCEDURE pressing (VAR c: ARRAY OF REAL; deg: INTEGER; d, s: REAL) : BOOLEAN ;
VAR
   dd: REAL ;
   k: INTEGER ;
BEGIN
   IF d < 0.0 THEN RETURN TRUE END ;
   IF (d # 0.0) OR (deg < 2) THEN RETURN FALSE END ;
   dd := 0.0 ;
   FOR k := deg TO 2 BY -1 DO
      dd := dd * s + VAL (REAL, k * (k - 1)) * c[k]
   END ;
   RETURN dd < 0.0
END pressing ;


(* At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
   pressed together (c2 < 0) so that the gap closes again before it ever
   exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.  (A
   resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.) *)
PROCEDURE touching_now (VAR c: ARRAY OF REAL; deg: INTEGER; kappa: REAL) : BOOLEAN ;
BEGIN
   IF c[1] < 0.0 THEN RETURN TRUE END ;
   IF (deg < 2) OR NOT (c[2] < 0.0) THEN RETURN FALSE END ;
   RETURN c[0] + c[1] * c[1] / (4.0 * (-c[2])) <= kappa
END touching_now ;


(* The polynomial c of degree n (5 to 8) surely has no root in [0, hi]
   (hi >= 2^-100, so that hi^8 stays normal): its Bernstein coefficients
   there, b_j = sum_{i <= j} C(j, i) u_i with t_i = c_i hi^i and u_i = t_i /
   C(n, i), are all beyond m = 2^-46 S + 2^-900 (S = sum |t_i|) with t_0's
   sign (the root solver's test for degrees 3 and 4, for higher degrees:
   docs/simulator.md, "Features that cannot come first").  A sum S that is
   not finite answers FALSE at once: gm2 may compile b > m as NOT (b <= m),
   true for a NaN; with S finite no b_j is NaN (the other runtimes' IEEE
   comparisons answer FALSE there too). *)
PROCEDURE NoRootHigh (VAR c: ARRAY OF REAL; n: INTEGER; hi: REAL) : BOOLEAN ;
VAR
   u: ARRAY [0..8] OF REAL ;
   p, s, t, m, b: REAL ;
   i, j: INTEGER ;
   neg, ok: BOOLEAN ;
BEGIN
   p := 1.0 ;
   s := 0.0 ;
   FOR i := 0 TO n DO
      t := c[i] * p ;
      p := p * hi ;
      s := s + ABS (t) ;
      u[i] := t / Binomial[n, i]
   END ;
   IF NOT IsFinite (s) THEN RETURN FALSE END ;
   m := TwoM46 * s + TwoM900 ;
   neg := u[0] < 0.0 ;
   FOR j := 0 TO n DO
      b := 0.0 ;
      FOR i := 0 TO j DO
         b := b + Binomial[j, i] * u[i]
      END ;
      IF neg THEN ok := b < -m ELSE ok := b > m END ;
      IF NOT ok THEN RETURN FALSE END
   END ;
   RETURN TRUE
END NoRootHigh ;


(* The smallest s in [0, w] where the gap c(s) reaches zero while
   decreasing, or touches zero with zero slope while pressed together
   (resting contact), and the check holds (edge: Inside, else always).  At
   s = 0 the gap counts as zero within kappa: approaching or pressed
   (touching_now) means contact now, separating or merely touching never.

   before: the earliest contact of the pair's other features found so far
   (Inf for none); a contact at or after it is never kept (the earliest one,
   first found on a tie, wins), so the search may answer none instead
   (docs/simulator.md, "Features that cannot come first"): at once when
   before is 0, and when a Bernstein test shows no root in [0, before (1 +
   2^-10)] (degrees 3 and 4: the root solver's entry's, NoRootTo; 5 to 8:
   NoRootHigh), so that a root found in [0, w] lies beyond before by far
   more than the solver's error. *)
PROCEDURE FirstContact (VAR c: ARRAY OF REAL; deg: INTEGER; w, kappa: REAL; edge: BOOLEAN; before: REAL;
                        VAR s: REAL) : BOOLEAN ;
VAR
   lo, d, h: REAL ;
   it, k: INTEGER ;
BEGIN
   IF NOT (before > 0.0) THEN RETURN FALSE END ;
   IF (deg >= 1) AND (ABS (c[0]) <= kappa) AND touching_now (c, deg, kappa) AND Check (edge, 0.0) THEN
      s := 0.0 ;
      RETURN TRUE
   END ;
   IF (before < w) AND (deg >= 3) AND (deg <= 8) THEN
      h := before + before * BeforeMargin ;
      IF h < w THEN
         IF deg <= 4 THEN
            IF NoRootTo (c, deg, h) THEN RETURN FALSE END
         ELSIF (h >= TwoM100) AND NoRootHigh (c, deg, h) THEN
            RETURN FALSE
         END
      END
   END ;
   lo := 0.0 ;
   FOR it := 0 TO deg + 1 DO
      IF NOT SmallestRoot (c, deg, lo, w, s) THEN RETURN FALSE END ;
      d := 0.0 ;
      FOR k := deg TO 1 BY -1 DO
         d := d * s + VAL (REAL, k) * c[k]
      END ;
      IF pressing (c, deg, d, s) AND Check (edge, s) THEN RETURN TRUE END ;
      lo := s
   END ;
   RETURN FALSE
END FirstContact ;


(* circle_circle parameters of a circle's centre (v < 0) or of a polygon's
   vertex v, at time now: x, vx, ax, d, e (= om), f (= phase + pi/2);
   y, vy, ay, p (= om), q (= phase). *)
PROCEDURE CircleParams (b: BodyRef; now: REAL; v: INTEGER;
                        VAR x, vx, ax, d, e, f, y, vy, ay, p, q: REAL) ;
VAR
   ang, phase, om: REAL ;
BEGIN
   StateAt (b, now, x, y, vx, vy, ang) ;
   IF v < 0 THEN
      d := b^.orbit ;
      phase := ang + b^.ophase
   ELSE
      d := Verts^[v].rho ;
      phase := ang + Verts^[v].beta
   END ;
   om := b^.om ;
   IF (om = 0.0) AND (d # 0.0) THEN
      (* an orbit that does not turn is a fixed offset: fold it in *)
      x := x + d * cos (phase) ;
      y := y + d * sin (phase) ;
      d := 0.0
   END ;
   IF d = 0.0 THEN
      om := 0.0 ;
      phase := 0.0
   END ;
   ax := b^.ax ;
   e := om ;
   f := phase + HalfPi ;
   ay := b^.ay ;
   p := om ;
   q := phase
END CircleParams ;


(* The generated circle_circle selection: counts the variant, fills coef and
   returns its degree. *)
PROCEDURE CcCoefficients (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z: REAL;
                          VAR coef: ARRAY OF REAL) : INTEGER ;
VAR
   idx: INTEGER ;
BEGIN
   idx := circle_circle_variant (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z) ;
   IF (idx < 0) OR (idx >= CcVariants) THEN
      Fails ("circle_circle: the scene uses an effect the generated code leaves out") ;
      coef[0] := 1.0 ;
      RETURN 0                 (* no contact: the world has failed, nothing more is handled *)
   END ;
   INC (CcCounts^[idx]) ;
   INC (Stats.features) ;
   RETURN circle_circle_coefficients (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z,
                                      coef)
END CcCoefficients ;


(* Counts a circle_circle prediction that CirclesApart decided: its variant
   and the features counter, as CcCoefficients would. *)
PROCEDURE CcCount (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z: REAL) ;
VAR
   idx: INTEGER ;
BEGIN
   idx := circle_circle_variant (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z) ;
   IF (idx < 0) OR (idx >= CcVariants) THEN
      Fails ("circle_circle: the scene uses an effect the generated code leaves out") ;
      RETURN
   END ;
   INC (CcCounts^[idx]) ;
   INC (Stats.features)
END CcCount ;


PROCEDURE CircleParamsOf (b: BodyRef; now: REAL; v: INTEGER; VAR c: CParams) ;
BEGIN
   CircleParams (b, now, v, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10])
END CircleParamsOf ;


(* circle_circle parameters of b's centre of rotation at time now, no orbit:
   the centre of a bounding circle (CircleParams of a polygon). *)
PROCEDURE CentreParams (b: BodyRef; now: REAL; VAR c: CParams) ;
VAR
   ang: REAL ;
BEGIN
   StateAt (b, now, c[0], c[6], c[1], c[7], ang) ;
   c[2] := b^.ax ;
   c[3] := 0.0 ;
   c[4] := 0.0 ;
   c[5] := HalfPi ;
   c[8] := b^.ay ;
   c[9] := 0.0 ;
   c[10] := 0.0
END CentreParams ;


(* The first contact within [0, w] of a circle of radius ra moving as pa
   and one of radius rb moving as pb. *)
PROCEDURE CirclesFirst (VAR pa: CParams; ra: REAL; VAR pb: CParams; rb, w, before: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   kappa: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   kappa := Tol * (2.0 * (ra + rb) + Tol) ;
   IF (pa[2] - pb[2] = 0.0) AND (pa[8] - pb[8] = 0.0) AND (pa[3] = 0.0) AND (pb[3] = 0.0)
      AND CirclesApart (pa[0] - pb[0], pa[1] - pb[1], pa[6] - pb[6], pa[7] - pb[7], ra + rb, kappa) THEN
      CcCount (pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2], pa[3], pa[4], pa[5],
               pa[6] - pb[6], pa[7] - pb[7], pa[8] - pb[8], pa[9], pa[10],
               0.0, 0.0, 0.0, pb[3], pb[4], pb[5], 0.0, 0.0, 0.0, pb[9], pb[10], ra, rb) ;
      RETURN FALSE
   END ;
   deg := circles_gap (pa, ra, pb, rb, coef) ;
   RETURN FirstContact (coef, deg, w, kappa, FALSE, before, t)
END CirclesFirst ;


(* The reference's circles_apart, for a pair whose circles do not orbit and
   whose relative acceleration is zero (CirclesFirst tests that): relative
   position (x, y), velocity (vx, vy), r = ra + rb.  The pair surely has no
   contact, decided without the polynomial (docs/simulator.md, "Pairs that
   stay apart"): the centres separate (p . v > 0 by more than its rounding),
   or they approach on a line that passes farther than r from each other
   ((p x v)^2 > (r^2 + kappa) |v|^2 by more than the rounding); sizes
   bounded so that nothing underflows or overflows. *)
PROCEDURE CirclesApart (x, vx, y, vy, r, kappa: REAL) : BOOLEAN ;
VAR
   px, py, size, v2, p2, cross: REAL ;
BEGIN
   px := x * vx ;
   py := y * vy ;
   size := ABS (px) + ABS (py) ;
   IF (size >= TwoM900) AND (px + py > TwoM40 * size) THEN
      RETURN TRUE
   END ;
   v2 := vx * vx + vy * vy ;
   p2 := x * x + y * y ;
   IF NOT ((v2 >= TwoM450) AND (v2 <= TwoP450) AND (p2 >= TwoM450) AND (p2 <= TwoP450)) THEN
      RETURN FALSE
   END ;
   cross := x * vy - y * vx ;
   RETURN cross * cross - (r * r + kappa) * v2 > TwoM30 * p2 * v2
END CirclesApart ;


(* The circle_circle polynomial (squared distance of the centres less
   (ra + rb)^2, in s from the parameters' time) of a circle of radius ra
   moving as pa (CircleParams) and one of radius rb moving as pb: fills coef
   and returns its degree. *)
PROCEDURE circles_gap (VAR pa: CParams; ra: REAL; VAR pb: CParams; rb: REAL; VAR coef: ARRAY OF REAL) : INTEGER ;
BEGIN
   (* only differences of the centres' motions matter: circle 1 moves
      relative to circle 2's centre of rotation, so that a common gravity
      cancels (no_accel variants) and far from the origin nothing is lost *)
   RETURN CcCoefficients (pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2], pa[3], pa[4], pa[5],
                          pa[6] - pb[6], pa[7] - pb[7], pa[8] - pb[8], pa[9], pa[10],
                          0.0, 0.0, 0.0, pb[3], pb[4], pb[5], 0.0, 0.0, 0.0, pb[9], pb[10], ra, rb, coef)
END circles_gap ;


(* Circle of A against circle of B (vb < 0, radius rb) or vertex vb of B
   (radius 0); before: FirstContact's. *)
PROCEDURE PredictCC (A, B: BodyRef; vb: INTEGER; rb, now, w, before: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   pa, pb: CParams ;
BEGIN
   CircleParamsOf (A, now, -1, pa) ;
   CircleParamsOf (B, now, vb, pb) ;
   RETURN CirclesFirst (pa, A^.r, pb, rb, w, before, t)
END PredictCC ;


(* The point_edge polynomial of a circle of radius rad whose centre orbits
   X's centre at rho (phase beta in X's frame) against the line of edge j of
   Y, in s = t - now (its coef[0]: the gap now): its degree, or -1 when the
   generated code leaves the effect out (the world has failed). *)
PROCEDURE PeCoefficients (X, Y: BodyRef; rho, beta, rad: REAL; j: INTEGER; now: REAL;
                          VAR coef: ARRAY OF REAL) : INTEGER ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2: REAL ;
   phn, wr, phr, h: REAL ;
   ed: INTEGER ;
   idx: INTEGER ;
   a1, a2, a3, a4, a5, a6: REAL ;
BEGIN
   ed := Y^.v0 + j ;
   StateAt (X, now, x1, y1, u1, v1, ang1) ;
   StateAt (Y, now, x2, y2, u2, v2, ang2) ;
   phn := ang2 + Verts^[ed].psi ;
   wr := X^.om - Y^.om ;
   phr := (ang1 + beta) - phn ;
   h := Verts^[ed].h + rad ;
   IF (wr = 0.0) AND (rho # 0.0) THEN
      (* the point does not turn relative to the edge: its offset along the
         normal is a constant, folded into the line's offset *)
      h := h - rho * cos (phr) ;
      rho := 0.0
   END ;
   a1 := x1 - x2 ;
   a2 := u1 - u2 ;
   a3 := X^.ax - Y^.ax ;
   a4 := y1 - y2 ;
   a5 := v1 - v2 ;
   a6 := X^.ay - Y^.ay ;
   idx := point_edge_variant (a1, a2, a3, a4, a5, a6, rho, wr, phr, Y^.om, phn, h) ;
   IF (idx < 0) OR (idx >= PeVariants) THEN
      Fails ("point_edge: the scene uses an effect the generated code leaves out") ;
      coef[0] := 1.0 ;
      RETURN -1                (* the world has failed, nothing more is handled *)
   END ;
   INC (PeCounts^[idx]) ;
   INC (Stats.features) ;
   RETURN point_edge_coefficients (a1, a2, a3, a4, a5, a6, rho, wr, phr, Y^.om, phn, h, coef)
END PeCoefficients ;


(* The first contact within [0, w] of PeCoefficients' polynomial (degree
   deg; none when deg < 0) whose point (X's centre, or rho, beta about it)
   lies on edge j's segment; when the point is X's vertex i (i >= 0), both
   neighbours of that vertex must also lie no more than the tolerance behind
   edge j's line (behind: else that line does not separate the bodies
   there, a corner meeting a corner: another feature pair is the contact). *)
PROCEDURE PeFirst (VAR coef: ARRAY OF REAL; deg: INTEGER; X, Y: BodyRef; rho, beta: REAL; j: INTEGER;
                   now, w: REAL; i: INTEGER; before: REAL; VAR t: REAL) : BOOLEAN ;
BEGIN
   IF deg < 0 THEN RETURN FALSE END ;
   ChkX := X ;
   ChkY := Y ;
   ChkRho := rho ;
   ChkBeta := beta ;
   ChkEdge := Y^.v0 + j ;
   ChkVert := i ;
   ChkNow := now ;
   RETURN FirstContact (coef, deg, w, Tol, TRUE, before, t)
END PeFirst ;


(* Point of X (circle centre with radius, vx < 0, or vertex vx: the index in
   Verts of X's vertex vx - X^.v0) against the line of edge j of Y (none while a fixed body covers the edge: its cover
   is not gone; nothing is counted); before: FirstContact's. *)
PROCEDURE PredictPE (X, Y: BodyRef; vx, j: INTEGER; now, w, before: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   rho, beta, rad: REAL ;
   deg, cover: INTEGER ;
   coef: ARRAY [0..PeMaxDegree] OF REAL ;
BEGIN
   cover := Verts^[Y^.v0 + j].cover ;
   IF (cover >= 0) AND (cover < NBodies) AND NOT Bodies^[cover].gone THEN RETURN FALSE END ;
   IF vx < 0 THEN
      rho := X^.orbit ;
      beta := X^.ophase ;
      rad := X^.r
   ELSE
      rho := Verts^[vx].rho ;
      beta := Verts^[vx].beta ;
      rad := 0.0
   END ;
   deg := PeCoefficients (X, Y, rho, beta, rad, j, now, coef) ;
   IF vx < 0 THEN
      RETURN PeFirst (coef, deg, X, Y, rho, beta, j, now, w, -1, before, t)
   END ;
   RETURN PeFirst (coef, deg, X, Y, rho, beta, j, now, w, vx - X^.v0, before, t)
END PredictPE ;


PROCEDURE Better (VAR best: Best; found: BOOLEAN; t: REAL; feat, a, b, i, j: INTEGER) ;
BEGIN
   IF found AND ((NOT best.found) OR (t < best.t)) THEN
      best.found := TRUE ;
      best.t := t ;
      best.feat := feat ;
      best.a := a ;
      best.b := b ;
      best.i := i ;
      best.j := j
   END
END Better ;


(* FirstContact's before for the earliest contact found so far (t, when
   found). *)
PROCEDURE BeforeOf (found: BOOLEAN; t: REAL) : REAL ;
BEGIN
   IF found THEN RETURN t END ;
   RETURN Inf
END BeforeOf ;


(* T turns, polygon P does not: when T's bounding circle (radius T.bound
   about T's centre of rotation, which does not turn) first touches P itself
   (its edges, then its vertices) within (0, w]: TRUE and meet = 0.0 when no
   edge line of P has the circle beyond it by more than the tolerance now
   (overlapping, or near a corner), TRUE and meet > 0 when they touch later,
   FALSE when they do not meet.  Exact: neither the circle nor P turns. *)
PROCEDURE bound_polygon (T, P: BodyRef; now, w: REAL; VAR meet: REAL) : BOOLEAN ;
VAR
   j, k: INTEGER ;
   apart, found, got: BOOLEAN ;
   t: REAL ;
   pt, pv: CParams ;
BEGIN
   IF P^.nv > CapEdgePolys THEN
      CapEdgePolys := P^.nv ;
      EdgePolys := Grow (EdgePolys, CapEdgePolys, SIZE (EdgePoly))
   END ;
   apart := FALSE ;
   FOR j := 0 TO P^.nv - 1 DO
      EdgePolys^[j].deg := PeCoefficients (T, P, 0.0, 0.0, T^.bound, j, now, EdgePolys^[j].c) ;
      IF EdgePolys^[j].c[0] > Tol THEN apart := TRUE END
   END ;
   IF NOT apart THEN
      meet := 0.0 ;
      RETURN TRUE
   END ;
   found := FALSE ;
   meet := 0.0 ;
   FOR j := 0 TO P^.nv - 1 DO
      got := PeFirst (EdgePolys^[j].c, EdgePolys^[j].deg, T, P, 0.0, 0.0, j, now, w, -1,
                      BeforeOf (found, meet), t) ;
      IF got AND ((NOT found) OR (t < meet)) THEN
         found := TRUE ;
         meet := t
      END
   END ;
   CentreParams (T, now, pt) ;
   FOR k := 0 TO P^.nv - 1 DO
      CircleParamsOf (P, now, P^.v0 + k, pv) ;
      got := CirclesFirst (pt, T^.bound, pv, 0.0, w, BeforeOf (found, meet), t) ;
      IF got AND ((NOT found) OR (t < meet)) THEN
         found := TRUE ;
         meet := t
      END
   END ;
   RETURN found
END bound_polygon ;


(* When the bounding circles first touch within (0, w]: TRUE and meet = 0.0
   when they overlap or touch now (within the tolerance), TRUE and meet > 0
   when they touch later, FALSE when they do not meet (exact: bounding
   circles do not turn). *)
PROCEDURE BoundsMeet (A, B: BodyRef; now, w: REAL; VAR meet: REAL) : BOOLEAN ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2, dx, dy, r: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   StateAt (A, now, x1, y1, u1, v1, ang1) ;
   StateAt (B, now, x2, y2, u2, v2, ang2) ;
   IF Library THEN
      (* bounds that overlap now need no polynomial (a test that says
         overlap only goes on to the next step) *)
      dx := x1 - x2 ;
      dy := y1 - y2 ;
      r := A^.bound + B^.bound ;
      IF dx * dx + dy * dy - r * r <= Tol * (2.0 * r + Tol) THEN
         meet := 0.0 ;
         RETURN TRUE
      END
   END ;
   deg := CcCoefficients (x1 - x2, u1 - u2, A^.ax - B^.ax, 0.0, 0.0, HalfPi, y1 - y2, v1 - v2, A^.ay - B^.ay,
                          0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, HalfPi, 0.0, 0.0, 0.0, 0.0, 0.0,
                          A^.bound, B^.bound, coef) ;
   IF coef[0] <= Tol * (2.0 * (A^.bound + B^.bound) + Tol) THEN
      meet := 0.0 ;
      RETURN TRUE
   END ;
   RETURN SmallestRoot (coef, deg, 0.0, w, meet)
END BoundsMeet ;


PROCEDURE CirclePolygon (C, P: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   j, k: INTEGER ;
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   FOR j := 0 TO P^.nv - 1 DO
      found := PredictPE (C, P, -1, j, now, w, BeforeOf (best.found, best.t), t) ;
      Better (best, found, t, FeatPE, C^.idx, P^.idx, -1, j)
   END ;
   FOR k := 0 TO P^.nv - 1 DO
      found := PredictCC (C, P, P^.v0 + k, 0.0, now, w, BeforeOf (best.found, best.t), t) ;
      Better (best, found, t, FeatCC, C^.idx, P^.idx, -1, k)
   END
END CirclePolygon ;


(* What every vertex-edge pair of a window shares, X holding the vertices
   and Y the edges: FALSE when the bound does not hold (a turn over 1 rad
   in the window); else cos and sin of X's angle now (ca, sa), the bound's
   part common to every pair (base, m), its part per metre of a vertex's
   radius (perRho), the same two for the place along an edge (abase,
   aperRho), and per edge of Y WinEX, WinEY, WinOff, WinSlack, WinAlong,
   WinLo, WinHi.

   The gap g(s) = n(s) . (d(s) + r(s)) - h of a vertex (r: its offset from
   X's centre, |r| = rho, turning at wx) from the line of an edge of Y (n:
   its unit normal, turning at wy; d: X's centre less Y's) changes over
   [0, w] by at most w (|wy| D + V + |wx - wy| rho), since
   |g'| <= |wy| |d| + |d'| + |wx - wy| rho (D >= |d|, V >= |d'| over the
   window); point_edge's polynomial is g with the sin and cos of both turns
   replaced by their Taylor polynomials of order n >= 1, each off by at most
   x^2/2 for a turn x <= 1 rad, so it is within (xn^2 D + xr^2 rho) of g
   (xn = |wy| w, xr = |wx - wy| w).  When |g(0)| exceeds both plus the
   tolerance (FirstContact's contact now) and a margin of 2^-30 of the sizes
   and of the angles' lever for every rounding, the polynomial keeps the
   sign of g(0) all through the window: no root, no contact (docs/toi.md,
   "Cost").  Likewise the place a(s) = t(s) . (d(s) + r(s)) of the vertex
   along the edge (t: the edge's unit tangent) changes by at most
   w (|wy| (D + rho) + V + |wx| rho): when a(0) lies farther than that
   beyond the edge's extent widened by the tolerance, Inside (evaluated on
   the exact motion) refuses every root of the window. *)
PROCEDURE WindowBound (X, Y: BodyRef; now, w: REAL; VAR ca, sa, base, perRho, abase, aperRho: REAL) : BOOLEAN ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2, dx, dy, u, v, ax, ay, speed, acc, d, vel: REAL ;
   wy, wr, xn, xr, lever, cb, sb, nx, ny, margin: REAL ;
   j, e: INTEGER ;
BEGIN
   StateAt (X, now, x1, y1, u1, v1, ang1) ;
   StateAt (Y, now, x2, y2, u2, v2, ang2) ;
   dx := x1 - x2 ;
   dy := y1 - y2 ;
   u := u1 - u2 ;
   v := v1 - v2 ;
   ax := X^.ax - Y^.ax ;
   ay := X^.ay - Y^.ay ;
   speed := sqrt (u * u + v * v) ;
   acc := sqrt (ax * ax + ay * ay) ;
   d := sqrt (dx * dx + dy * dy) + (speed + 0.5 * acc * w) * w ;
   vel := speed + acc * w ;
   wy := ABS (Y^.om) ;
   wr := ABS (X^.om - Y^.om) ;
   xn := wy * w ;
   xr := wr * w ;
   lever := ABS (ang1) + ABS (ang2) + 8.0 ;
   base := w * (wy * d + vel) + xn * xn * d + Tol + TwoM30 * (1.0 + lever) * d ;
   perRho := w * wr + xr * xr + TwoM30 * (1.0 + lever) ;
   abase := w * (wy * d + vel) + Tol + TwoM30 * (1.0 + lever) * d ;
   aperRho := w * (wy + ABS (X^.om)) + TwoM30 * (1.0 + lever) ;
   IF NOT ((xn <= 1.0) AND (xr <= 1.0) AND (base <= MAX (REAL)) AND (perRho <= MAX (REAL))) THEN
      RETURN FALSE
   END ;
   ca := cos (ang1) ;
   sa := sin (ang1) ;
   cb := cos (ang2) ;
   sb := sin (ang2) ;
   FOR j := 0 TO Y^.nv - 1 DO
      e := Y^.v0 + j ;
      nx := cb * Verts^[e].nx - sb * Verts^[e].ny ;
      ny := sb * Verts^[e].nx + cb * Verts^[e].ny ;
      WinEX[j] := nx ;
      WinEY[j] := ny ;
      WinOff[j] := nx * dx + ny * dy - Verts^[e].h ;
      WinSlack[j] := TwoM30 * ABS (Verts^[e].h) ;
      WinAlong[j] := -ny * dx + nx * dy ;
      margin := TwoM30 * (ABS (Verts^[e].s1) + ABS (Verts^[e].s2)) ;
      WinLo[j] := Verts^[e].s1 - margin ;
      WinHi[j] := Verts^[e].s2 + margin
   END ;
   RETURN TRUE
END WindowBound ;


(* The point_edge variants PeCoefficients picks for X's vertices against
   Y's edges now: turning for a vertex off X's centre that turns relative to
   the edge, fixed for the others (rho 0 after the fold).  A variant reads
   only which effects are zero (orbit, acceleration, the two turns), never
   the positions, phases or the line's offset. *)
PROCEDURE PeVariantsOf (X, Y: BodyRef; now: REAL; VAR turning, fixed: INTEGER) ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2, wr, rho: REAL ;
BEGIN
   StateAt (X, now, x1, y1, u1, v1, ang1) ;
   StateAt (Y, now, x2, y2, u2, v2, ang2) ;
   wr := X^.om - Y^.om ;
   fixed := point_edge_variant (x1 - x2, u1 - u2, X^.ax - Y^.ax, y1 - y2, v1 - v2, X^.ay - Y^.ay, 0.0, wr, 0.0,
                                Y^.om, 0.0, 0.0) ;
   IF wr = 0.0 THEN rho := 0.0 ELSE rho := 1.0 END ;
   turning := point_edge_variant (x1 - x2, u1 - u2, X^.ax - Y^.ax, y1 - y2, v1 - v2, X^.ay - Y^.ay, rho, wr, 0.0,
                                  Y^.om, 0.0, 0.0)
END PeVariantsOf ;


(* Every vertex of A against every edge of B within [0, w] after now; the
   pairs WindowBound proves apart are counted, not solved. *)
PROCEDURE VerticesEdges (A, B: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   i, j, vi, cover, turning, fixed, spared: INTEGER ;
   t, ca, sa, base, perRho, abase, aperRho, rx, ry, lim, alim, a: REAL ;
   on, found, spare: BOOLEAN ;
BEGIN
   on := WindowBound (A, B, now, w, ca, sa, base, perRho, abase, aperRho) ;
   turning := -1 ;
   fixed := -1 ;
   IF on THEN PeVariantsOf (A, B, now, turning, fixed) END ;
   FOR i := 0 TO A^.nv - 1 DO
      vi := A^.v0 + i ;
      rx := 0.0 ;
      ry := 0.0 ;
      lim := 0.0 ;
      alim := 0.0 ;
      IF Verts^[vi].rho = 0.0 THEN spared := fixed ELSE spared := turning END ;
      IF on THEN
         rx := ca * Verts^[vi].lx - sa * Verts^[vi].ly ;
         ry := sa * Verts^[vi].lx + ca * Verts^[vi].ly ;
         lim := base + perRho * Verts^[vi].rho ;
         alim := abase + aperRho * Verts^[vi].rho
      END ;
      FOR j := 0 TO B^.nv - 1 DO
         spare := FALSE ;
         IF on THEN
            a := WinAlong[j] - WinEY[j] * rx + WinEX[j] * ry ;
            spare := (ABS (WinOff[j] + WinEX[j] * rx + WinEY[j] * ry) > lim + WinSlack[j])
                     OR (a < WinLo[j] - alim) OR (a > WinHi[j] + alim)
         END ;
         IF spare THEN
            (* far from the line, or beside the edge, all through the window (WindowBound):
               counted, not solved *)
            cover := Verts^[B^.v0 + j].cover ;
            IF NOT ((cover >= 0) AND (cover < NBodies) AND NOT Bodies^[cover].gone) THEN
               IF (spared < 0) OR (spared >= PeVariants) THEN
                  Fails ("point_edge: the scene uses an effect the generated code leaves out")
               ELSE
                  INC (PeCounts^[spared]) ;
                  INC (Stats.features)
               END
            END
         ELSE
            found := PredictPE (A, B, vi, j, now, w, BeforeOf (best.found, best.t), t) ;
            Better (best, found, t, FeatPE, A^.idx, B^.idx, i, j)
         END
      END
   END
END VerticesEdges ;


(* The earliest contact of A's and B's features within [0, w] after now
   (circle-circle, circle-polygon, or A's vertices on B's edges then B's on
   A's): best.found and its fields, else not best.found. *)
PROCEDURE Features (A, B: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   best.found := FALSE ;
   best.t := 0.0 ;
   IF (NOT A^.polygon) AND (NOT B^.polygon) THEN
      found := PredictCC (A, B, -1, B^.r, now, w, Inf, t) ;
      Better (best, found, t, FeatCC, A^.idx, B^.idx, -1, -1)
   ELSIF NOT A^.polygon THEN
      CirclePolygon (A, B, now, w, best)
   ELSIF NOT B^.polygon THEN
      CirclePolygon (B, A, now, w, best)
   ELSE
      VerticesEdges (A, B, now, w, best) ;
      VerticesEdges (B, A, now, w, best)
   END
END Features ;


(* The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
   +infinity when it has none (r <= 0 and q = 0). *)
PROCEDURE clear_root (g, r, q: REAL) : REAL ;
BEGIN
   IF NOT (g > 0.0) THEN RETURN 0.0 END ;
   IF r > 0.0 THEN RETURN 2.0 * g / (r + sqrt (r * r + 2.0 * q * g)) END ;
   IF q > 0.0 THEN RETURN (sqrt (r * r + 2.0 * q * g) - r) / q END ;
   RETURN Inf
END clear_root ;


(* The largest projection of b on the unit axis (nx, ny) at now (a circle:
   its centre's plus its radius). *)
PROCEDURE reach (b: BodyRef; nx, ny, now: REAL) : REAL ;
VAR
   px, py, best, d: REAL ;
   k: INTEGER ;
BEGIN
   IF NOT b^.polygon THEN
      PointAt (b, -1, now, px, py) ;
      RETURN nx * px + ny * py + b^.r
   END ;
   best := -Inf ;
   FOR k := 0 TO b^.nv - 1 DO
      PointAt (b, b^.v0 + k, now, px, py) ;
      d := nx * px + ny * py ;
      IF d > best THEN best := d END        (* Python's max(best, d) *)
   END ;
   RETURN best
END reach ;


(* reach of a polygon whose n vertices now are (xs[k], ys[k]). *)
PROCEDURE reach_points (nx, ny: REAL; VAR xs, ys: ARRAY OF REAL; n: INTEGER) : REAL ;
VAR
   best, d: REAL ;
   k: INTEGER ;
BEGIN
   best := -Inf ;
   FOR k := 0 TO n - 1 DO
      d := nx * xs[k] + ny * ys[k] ;
      IF d > best THEN best := d END        (* Python's max(best, d) *)
   END ;
   RETURN best
END reach_points ;


(* clear_time along each edge normal of P (P does not turn, T does): the
   largest of the times. *)
PROCEDURE clear_axes (T, P: BodyRef; now: REAL) : REAL ;
VAR
   x1, y1, u1, v1, a1, x2, y2, u2, v2, a2, du, dv, dax, day, spin, best, ox, oy, off, c: REAL ;
   j: INTEGER ;
BEGIN
   StateAt (T, now, x1, y1, u1, v1, a1) ;
   StateAt (P, now, x2, y2, u2, v2, a2) ;
   du := u1 - u2 ;
   dv := v1 - v2 ;
   dax := T^.ax - P^.ax ;
   day := T^.ay - P^.ay ;
   spin := T^.bound * TurnRate (T) ;
   best := 0.0 ;
   FOR j := 0 TO P^.nv - 1 DO
      edge_line (P, j, now, ox, oy, off) ;
      c := clear_root (-reach (T, -ox, -oy, now) - off - Tol, spin - (ox * du + oy * dv),
                       ABS (ox * dax + oy * day)) ;
      IF c > best THEN best := c END        (* Python's max(best, c) *)
   END ;
   RETURN best
END clear_axes ;


(* The vertices (xs[k], ys[k]) of polygon b whose centre is at (x, y), from
   the cosine c and sine s of its angle: the rotation of each vertex's place
   (lx, ly) in the body's frame (m). *)
PROCEDURE rotated_points (b: BodyRef; x, y, c, s: REAL; VAR xs, ys: ARRAY OF REAL) ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := 0 TO b^.nv - 1 DO
      xs[k] := x + (c * Verts^[b^.v0 + k].lx - s * Verts^[b^.v0 + k].ly) ;
      ys[k] := y + (s * Verts^[b^.v0 + k].lx + c * Verts^[b^.v0 + k].ly)
   END
END rotated_points ;


(* The velocity (wx[k], wy[k]) (m/s) of each vertex of polygon b about its
   centre from its turn: its offset from the centre (the rotation of its
   place (lx, ly) by the cosine c and sine s of b's angle) turned a quarter
   and times the turn rate. *)
PROCEDURE spin_velocities (b: BodyRef; c, s: REAL; VAR wx, wy: ARRAY OF REAL) ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := 0 TO b^.nv - 1 DO
      wx[k] := -(b^.om * (s * Verts^[b^.v0 + k].lx + c * Verts^[b^.v0 + k].ly)) ;
      wy[k] := b^.om * (c * Verts^[b^.v0 + k].lx - s * Verts^[b^.v0 + k].ly)
   END
END spin_velocities ;


(* The larger of best and the time the other polygon Q (its centre (qx,
   qy)) stays beyond some edge line of P (its centre (px, py), cos c and
   sin s of its angle) by more than the tolerance (s).  Q's n vertices (xs,
   ys) and their velocities from the turn (qwx, qwy) (spin_velocities);
   (du, dv) and (dax, day): Q's velocity and acceleration less P's; spin:
   the bounds times the turn rates; span: the time of one radian of the two
   turns together (s), the reach of the turning bound.

   Along the edge's outward normal o held fixed, every vertex of Q stays
   beyond P's support until the root of the rate bound e - (spin - o . (du,
   dv)) s - |o . (dax, day)| s^2/2 of the nearest vertex's gap e (each
   point of a body moves along o at most its bound times its turn rate
   faster than the centre).  Along the normal n(s) turning with P, P's
   support is the edge's own line, and vertex k's gap g(s) = n(s) . (d(s) +
   r_k(s)) - h (d: Q's centre less P's, r_k: the vertex about Q's centre)
   has, with the turn rates wp and wq, the derivatives g1 = wp n_ . u + n .
   (dv + w_k) and g2 = -wp^2 n . u + 2 wp n_ . (dv + w_k) + n . da - wq^2 n
   . r_k at 0 (u = d + r_k, n_ the normal turned a quarter, w_k the
   vertex's velocity from the turn); over [0, span] the third derivative is
   at most J = |wp|^3 D + 3 wp^2 V + 3 |wp| |da| + bound_Q |wq - wp|^3 and
   the first at most |wp| D + V + bound_Q |wq - wp| (D, V: bounds of |d|
   and |d'| over the span), so g stays above g(0) + g1 s + (g2 - J span/3)
   s^2/2 until that bound's root (at most span).  The axis holds until the
   later of the two; the turning normal is taken only where it can raise
   the axis and best, nearest vertex first, and a vertex whose
   first-derivative bound already lasts past the time so far is not
   solved. *)
PROCEDURE edges_clear (P: BodyRef; px, py, c, s: REAL; Q: BodyRef; qx, qy: REAL;
                       VAR xs, ys, qwx, qwy: ARRAY OF REAL; n: INTEGER;
                       best, spin, span, du, dv, dax, day: REAL) : REAL ;
VAR
   ox, oy, off, g, e, t, m, mt, wp, wr, vel, acc, cx, cy, dist, vmax, aw, dw, jerk, rate,
   ux, uy, vx, vy, g1, g2, qq: REAL ;
   i, j, k, near: INTEGER ;
   stop, turning: BOOLEAN ;
BEGIN
   wp := P^.om ;
   wr := Q^.om ;
   vel := sqrt (du * du + dv * dv) ;
   acc := sqrt (dax * dax + day * day) ;
   cx := qx - px ;
   cy := qy - py ;
   dist := sqrt (cx * cx + cy * cy) + (vel + 0.5 * acc * span) * span ;
   vmax := vel + acc * span ;
   aw := ABS (wp) ;
   dw := ABS (wr - wp) ;
   jerk := (aw * aw * aw * dist + 3.0 * aw * aw * vmax + 3.0 * aw * acc + Q^.bound * dw * dw * dw) * span / 3.0 ;
   rate := aw * dist + vmax + Q^.bound * dw ;
   turning := (span > 0.0) AND (span <= MAX (REAL)) AND (jerk <= MAX (REAL)) AND (rate <= MAX (REAL)) ;
   FOR j := 0 TO P^.nv - 1 DO
      ox := c * Verts^[P^.v0 + j].nx - s * Verts^[P^.v0 + j].ny ;
      oy := s * Verts^[P^.v0 + j].nx + c * Verts^[P^.v0 + j].ny ;
      off := ox * px + oy * py + Verts^[P^.v0 + j].h ;
      g := Inf ;
      near := 0 ;
      k := 0 ;
      stop := FALSE ;
      WHILE (k < n) AND NOT stop DO
         e := ox * xs[k] + oy * ys[k] - off ;
         IF e - Tol <= 0.0 THEN
            stop := TRUE                       (* then g - Tol <= 0 too: x - Tol rises with x *)
         ELSE
            ClrGap[k] := e ;
            IF e < g THEN
               g := e ;
               near := k
            END ;
            INC (k)
         END
      END ;
      (* not apart along this axis: 0, never above best *)
      IF (NOT stop) AND (g - Tol > 0.0) THEN
         m := clear_root (g - Tol, spin - (ox * du + oy * dv), ABS (ox * dax + oy * day)) ;
         IF turning AND (span > m) AND (span > best) THEN
            mt := span ;
            i := 0 ;
            stop := FALSE ;
            WHILE (i < n) AND NOT stop DO
               IF i = 0 THEN
                  k := near
               ELSIF i <= near THEN
                  k := i - 1
               ELSE
                  k := i
               END ;
               e := ClrGap[k] - Tol ;
               (* unless its first-derivative bound alone lasts past mt *)
               IF NOT (e - mt * rate >= 0.0) THEN
                  ux := xs[k] - px ;
                  uy := ys[k] - py ;
                  vx := du + qwx[k] ;
                  vy := dv + qwy[k] ;
                  g1 := wp * (ox * uy - oy * ux) + (ox * vx + oy * vy) ;
                  g2 := -(wp * wp) * (ox * ux + oy * uy) + 2.0 * wp * (ox * vy - oy * vx) + (ox * dax + oy * day)
                        - wr * wr * (ox * (xs[k] - qx) + oy * (ys[k] - qy)) ;
                  qq := jerk - g2 ;
                  IF NOT (qq > 0.0) THEN qq := 0.0 END ;
                  t := clear_root (e, -g1, qq) ;
                  IF NOT (t >= 0.0) THEN t := 0.0 END ;
                  IF t < mt THEN
                     mt := t ;
                     stop := NOT ((mt > m) AND (mt > best))
                  END
               END ;
               INC (i)
            END ;
            IF mt > m THEN m := mt END
         END ;
         IF m > best THEN best := m END
      END
   END ;
   RETURN best
END edges_clear ;


(* The library's clear_time of two polygons (the simulator keeps
   clear_time's own, whose bits its traces pin): every vertex from one
   cosine and sine of its body's angle (rotated_points), and the gap along
   each edge normal of either polygon, held fixed and turning with its
   polygon (edges_clear), as well as along the line of the centres.  Along
   a fixed axis the gap closes at most as fast as the centres' relative
   motion along it plus each bound times its turn rate, along a turning
   edge normal each vertex's gap stays above its Taylor polynomial of order
   2 less the bound of its third derivative, and the gap of the best
   separating axis now is the separation, so this is never shorter than the
   bound through the norms |x| + |y| and never longer than the bodies stay
   apart. *)
PROCEDURE clear_polygons (A, B: BodyRef; now: REAL) : REAL ;
VAR
   x1, y1, u1, v1, a1, x2, y2, u2, v2, a2, dx, dy, d, nx, ny, ca, sa, cb, sb, hi, lo, spin, span,
   du, dv, dax, day, best: REAL ;
BEGIN
   StateAt (A, now, x1, y1, u1, v1, a1) ;
   StateAt (B, now, x2, y2, u2, v2, a2) ;
   dx := x2 - x1 ;
   dy := y2 - y1 ;
   d := sqrt (dx * dx + dy * dy) ;
   IF NOT (d > 0.0) THEN RETURN 0.0 END ;
   nx := dx / d ;
   ny := dy / d ;
   ca := cos (a1) ;
   sa := sin (a1) ;
   cb := cos (a2) ;
   sb := sin (a2) ;
   rotated_points (A, x1, y1, ca, sa, ClrAX, ClrAY) ;
   rotated_points (B, x2, y2, cb, sb, ClrBX, ClrBY) ;
   spin_velocities (A, ca, sa, ClrAWX, ClrAWY) ;
   spin_velocities (B, cb, sb, ClrBWX, ClrBWY) ;
   hi := reach_points (nx, ny, ClrAX, ClrAY, A^.nv) ;
   lo := -reach_points (-nx, -ny, ClrBX, ClrBY, B^.nv) ;
   spin := A^.bound * TurnRate (A) + B^.bound * TurnRate (B) ;
   span := 1.0 / (ABS (A^.om) + ABS (B^.om)) ;
   du := u2 - u1 ;
   dv := v2 - v1 ;
   dax := B^.ax - A^.ax ;
   day := B^.ay - A^.ay ;
   best := clear_root (lo - hi - Tol, spin - (nx * du + ny * dv), ABS (nx * dax + ny * day)) ;
   best := edges_clear (A, x1, y1, ca, sa, B, x2, y2, ClrBX, ClrBY, ClrBWX, ClrBWY, B^.nv, best, spin, span,
                        du, dv, dax, day) ;
   RETURN edges_clear (B, x2, y2, cb, sb, A, x1, y1, ClrAX, ClrAY, ClrAWX, ClrAWY, A^.nv, best, spin, span,
                       u1 - u2, v1 - v2, A^.ax - B^.ax, A^.ay - B^.ay)
END clear_polygons ;


(* How long A and B surely stay more than the tolerance apart, from their
   gap g along a fixed unit axis n now (0 when not apart now): along n the
   gap changes by (dv . n) s + (da . n) s^2/2 from the centres' relative
   motion and closes by at most spin s from the turns (spin: each turning
   body's bound times its turn rate), so it stays above the tolerance for s
   below the positive root of |da . n|/2 s^2 + r s - (g - tol),
   r = spin - dv . n (clear_root).  The axes: P's edge normals when one body
   is a polygon P that does not turn and the other turns (clear_axes); else
   the larger of the line of the centres and the separating axis of
   separation (which may turn: unsigned norms). *)
PROCEDURE clear_time (A, B: BodyRef; now: REAL) : REAL ;
VAR
   x1, y1, u1, v1, a1, x2, y2, u2, v2, a2, dx, dy, d, nx, ny, hi, lo, spin, along, anyway, sep: REAL ;
   shared: BOOLEAN ;
BEGIN
   IF B^.polygon AND (B^.om = 0.0) AND (TurnRate (A) > 0.0) THEN RETURN clear_axes (A, B, now) END ;
   IF A^.polygon AND (A^.om = 0.0) AND (TurnRate (B) > 0.0) THEN RETURN clear_axes (B, A, now) END ;
   IF Library AND A^.polygon AND B^.polygon THEN RETURN clear_polygons (A, B, now) END ;
   StateAt (A, now, x1, y1, u1, v1, a1) ;
   StateAt (B, now, x2, y2, u2, v2, a2) ;
   dx := x2 - x1 ;
   dy := y2 - y1 ;
   d := sqrt (dx * dx + dy * dy) ;
   IF NOT (d > 0.0) THEN RETURN 0.0 END ;
   nx := dx / d ;
   ny := dy / d ;
   shared := A^.polygon AND B^.polygon ;
   IF shared THEN
      (* two polygons: their vertices now, once for reach and the separation *)
      VertexPoints (A, now, ClrAX, ClrAY) ;
      VertexPoints (B, now, ClrBX, ClrBY) ;
      hi := reach_points (nx, ny, ClrAX, ClrAY, A^.nv) ;
      lo := -reach_points (-nx, -ny, ClrBX, ClrBY, B^.nv)
   ELSE
      hi := reach (A, nx, ny, now) ;
      lo := -reach (B, -nx, -ny, now)
   END ;
   spin := A^.bound * TurnRate (A) + B^.bound * TurnRate (B) ;
   along := clear_root (lo - hi - Tol, spin - (nx * (u2 - u1) + ny * (v2 - v1)),
                        ABS (nx * (B^.ax - A^.ax) + ny * (B^.ay - A^.ay))) ;
   (* and along the best separating axis, which may turn: the norms, |x| + |y| *)
   IF shared THEN
      sep := polygons_separation (A, B, now, ClrAX, ClrAY, ClrBX, ClrBY)
   ELSE
      sep := separation (A, B, now)
   END ;
   anyway := clear_root (sep - Tol, spin + ABS (u2 - u1) + ABS (v2 - v1),
                         ABS (B^.ax - A^.ax) + ABS (B^.ay - A^.ay)) ;
   IF anyway > along THEN RETURN anyway END ;     (* Python's max(along, anyway) *)
   RETURN along
END clear_time ;


(* The first contact of A and B after now and before end (the chain of
   cheap steps and Taylor windows of docs/simulator.md): a later meeting of
   the bounds or a clear stretch moves now on, a Taylor window solves the
   features; at most stages steps, of which at most windows Taylor windows.
   1 with the contact (t its time), 0 when there is none before end, 2 when
   the steps ran out at t (where the simulator schedules a horizon). *)
PROCEDURE PairContact (A, B: BodyRef; now, end: REAL; stages, windows: INTEGER;
                       VAR t: REAL; VAR feat, a, b, i, j: INTEGER) : INTEGER ;
VAR
   w, ta, tb, q, meet, clear, lead: REAL ;
   best: Best ;
   found, straight: BOOLEAN ;
   stage, solved: INTEGER ;
BEGIN
   ta := TurnRate (A) ;
   tb := TurnRate (B) ;
   (* the library: a clear stretch of two turning polygons shorter than
      Straight windows leads straight to the window at its end, without
      another bound or clear-stretch test (the simulator: never) *)
   lead := 0.0 ;
   IF Library AND A^.polygon AND B^.polygon AND (ta > 0.0) AND (tb > 0.0) THEN lead := Straight END ;
   straight := FALSE ;
   solved := 0 ;
   stage := 0 ;
   LOOP
      IF stage = stages THEN EXIT END ;
      INC (stage) ;
      w := end - now ;
      IF NOT (w > 0.0) THEN RETURN 0 END ;
      meet := 0.0 ;
      IF (A^.polygon OR B^.polygon) AND NOT straight THEN
         (* bounds that do not turn: until they touch, nothing can *)
         IF B^.polygon AND (ta > 0.0) AND (B^.om = 0.0) THEN
            found := bound_polygon (A, B, now, w, meet)
         ELSIF A^.polygon AND (tb > 0.0) AND (A^.om = 0.0) THEN
            found := bound_polygon (B, A, now, w, meet)
         ELSE
            found := BoundsMeet (A, B, now, w, meet)
         END ;
         IF NOT found THEN RETURN 0 END
      END ;
      IF meet > 0.0 THEN
         now := now + meet              (* the next stage from there *)
      ELSE
         q := w ;
         IF (ta > 0.0) AND (tb > 0.0) THEN
            q := Alpha / (ta + tb)
         ELSIF ta > 0.0 THEN
            q := A^.window / ta         (* only A turns: its own lever's window *)
         ELSIF tb > 0.0 THEN
            q := B^.window / tb
         END ;
         IF q < w THEN w := q END ;     (* Python's min(w, q) *)
         clear := 0.0 ;
         IF ((ta > 0.0) OR (tb > 0.0)) AND NOT straight THEN clear := clear_time (A, B, now) END ;
         IF ((ta > 0.0) OR (tb > 0.0)) AND NOT straight AND (clear >= w) THEN
            (* apart all through the window, whatever the turns do: no roots
               to solve until they may come within the tolerance *)
            now := now + clear ;
            straight := clear < lead * w
         ELSE
            straight := FALSE ;
            IF solved >= windows THEN EXIT END ;   (* the simulator: one Taylor window per prediction *)
            Features (A, B, now, w, best) ;
            IF best.found THEN
               t := now + best.t ;
               feat := best.feat ;
               a := best.a ;
               b := best.b ;
               i := best.i ;
               j := best.j ;
               RETURN 1
            END ;
            IF (ta = 0.0) AND (tb = 0.0) THEN RETURN 0 END ;   (* nothing turns: the window was the whole run *)
            now := now + w ;
            INC (solved)
         END
      END
   END ;
   t := now ;
   RETURN 2
END PairContact ;


(* Schedules the first contact of A and B after now, or a horizon event
   where the Taylor polynomials of their turns stop being good.  Cheap
   steps chain: a later meeting of the bounds or a clear stretch moves now
   on (up to Chain stages, at most one Taylor window, PairContact). *)
PROCEDURE PredictPair (A, B: BodyRef; now: REAL) ;
VAR
   t: REAL ;
   feat, a, b, i, j: INTEGER ;
BEGIN
   IF (A^.sup = B^.idx) OR (B^.sup = A^.idx) THEN
      RETURN      (* the support's edge line separates them (both convex): only leaving ends it *)
   END ;
   IF (A^.asleep AND grounded (B)) OR (B^.asleep AND grounded (A)) THEN
      RETURN      (* a sleeper against a sleeper or an unmoving fixed body: nothing moves *)
   END ;
   INC (Stats.pairs) ;
   CASE PairContact (A, B, now, EndT, Chain, 1, t, feat, a, b, i, j) OF
      1: push_collision (t, feat, ADR (Bodies^[a]), ADR (Bodies^[b]), i, j)
    | 2: IF t < EndT THEN push_horizon (t, A, B) END
   ELSE
   END
END PredictPair ;


(* Predicts b against every other body o in the cells [xlo..xhi] x [ylo..yhi]
   (clipped to the grid) with o.idx > above and o.idx # skip, unless both
   are fixed. *)
PROCEDURE PredictCells (b: BodyRef; xlo, xhi, ylo, yhi, above, skip: INTEGER; now: REAL) ;
VAR
   jx, jy, c, k, oi: INTEGER ;
   o: BodyRef ;
BEGIN
   FOR jy := Max (ylo, 0) TO Min (yhi, GridNY - 1) DO
      FOR jx := Max (xlo, 0) TO Min (xhi, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Cells^[c].n - 1 DO
            oi := Cells^[c].items^[k] ;
            IF (oi # b^.idx) AND (oi > above) AND (oi # skip) THEN
               o := ADR (Bodies^[oi]) ;
               IF NOT (b^.fixed AND o^.fixed) THEN
                  PredictPair (b, o, now)
               END
            END
         END
      END
   END
END PredictCells ;


(* Predicts b against the large bodies near it (large_near) other than
   skip, unless both are fixed. *)
PROCEDURE PredictLarge (b: BodyRef; skip: INTEGER; now: REAL) ;
VAR
   k, n, oi: INTEGER ;
   o: BodyRef ;
BEGIN
   large_near (b, n) ;
   FOR k := 0 TO n - 1 DO
      oi := Near^[k] ;
      IF oi # skip THEN
         o := ADR (Bodies^[oi]) ;
         IF NOT (b^.fixed AND o^.fixed) THEN
            PredictPair (b, o, now)
         END
      END
   END
END PredictLarge ;


PROCEDURE PredictBody (b: BodyRef; now: REAL; skip: INTEGER) ;
BEGIN
   PredictCells (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, -1, skip, now) ;
   PredictLarge (b, skip, now) ;
   ScheduleCell (b, now) ;
   (* a carried body moves with its base: no stop, no leave of its own *)
   IF (b^.sup >= 0) AND (Bodies^[b^.sup].fixed OR Bodies^[b^.sup].asleep) THEN schedule_support (b) END
END PredictBody ;


(* Schedules the first crossing of b's centre over a line a margin past a boundary of its cell. *)
PROCEDURE ScheduleCell (b: BodyRef; now: REAL) ;
VAR
   ulo, uhi, p, v, a, origin, size, bound, lo, u, bu, h, room: REAL ;
   c: ARRAY [0..2] OF REAL ;
   axis, dk, direction, i, n, it, baxis, bdir: INTEGER ;
   found, crossed: BOOLEAN ;
   ev: Event ;
BEGIN
   IF b^.large OR ((b^.vx = 0.0) AND (b^.vy = 0.0) AND (b^.ax = 0.0) AND (b^.ay = 0.0)) THEN
      RETURN
   END ;
   ulo := now - b^.tb ;
   uhi := EndT - b^.tb ;
   (* the margin, or what the cell leaves a body added live that is wider
      than the scene's widest (it must stay within half a cell of its cell) *)
   h := GridMargin ;
   room := HalfCell - b^.bound ;
   IF room < h THEN h := room END ;
   found := FALSE ;
   bu := 0.0 ;
   baxis := 0 ;
   bdir := 0 ;
   FOR axis := 0 TO 1 DO
      IF axis = 0 THEN
         p := b^.px ; v := b^.vx ; a := b^.ax ; i := b^.cx ; n := GridNX ; origin := GridX0 ; size := CellW
      ELSE
         p := b^.py ; v := b^.vy ; a := b^.ay ; i := b^.cy ; n := GridNY ; origin := GridY0 ; size := CellH
      END ;
      FOR dk := 0 TO 1 DO
         IF dk = 0 THEN direction := 1 ELSE direction := -1 END ;
         crossed := FALSE ;
         IF direction = 1 THEN
            IF i < n - 1 THEN
               bound := origin + VAL (REAL, i + 1) * size + h ;
               crossed := TRUE
            END
         ELSIF i > 0 THEN
            bound := origin + VAL (REAL, i) * size - h ;
            crossed := TRUE
         END ;
         IF crossed AND (ulo = 0.0) AND ((p - bound) * VAL (REAL, direction) >= 0.0)
            AND ((v * VAL (REAL, direction) > 0.0) OR ((v = 0.0) AND (a * VAL (REAL, direction) > 0.0))) THEN
            (* on the boundary now, or past it (CellOf's quotient and the
               boundary's sum origin + i size can round apart), and moving or
               accelerating across it: cross at once (the root finder reports
               no root at the interval's start, and none at all for a
               boundary already behind) *)
            IF (NOT found) OR (0.0 < bu) THEN
               found := TRUE ;
               bu := 0.0 ;
               baxis := axis ;
               bdir := direction
            END ;
            crossed := FALSE
         END ;
         IF crossed THEN
            c[0] := p - bound ;
            c[1] := v ;
            c[2] := 0.5 * a ;
            lo := ulo ;
            it := 0 ;
            WHILE (it < 3) AND SmallestRoot (c, 2, lo, uhi, u) DO
               IF (v + a * u) * VAL (REAL, direction) > 0.0 THEN
                  IF (NOT found) OR (u < bu) THEN
                     found := TRUE ;
                     bu := u ;
                     baxis := axis ;
                     bdir := direction
                  END ;
                  it := 3
               ELSE
                  lo := u ;
                  INC (it)
               END
            END
         END
      END
   END ;
   IF found THEN
      ev.t := b^.tb + bu ;
      ev.kind := KCell ;
      ev.cell.body := b^.idx ;
      ev.cell.axis := baxis ;
      ev.cell.direction := bdir ;
      ev.cell.stamp := b^.stamp ;
      push (ev)
   END
END ScheduleCell ;


(* The gap polynomial of the contact's feature (feature, i, j as in a
   CollisionEvent: the one that predicted it), taken again at the contact
   (A's time: both advanced), predicts this contact now (touching_now:
   approaching, c1 < 0, or c2 < 0 and closing again before the gap exceeds
   its kappa).  Its second derivative has the centripetal terms of a turn,
   which pressed leaves out.  FALSE when the generated code leaves the
   effect out (the world has failed). *)
PROCEDURE closing (A, B: BodyRef; feature, i, j: INTEGER) : BOOLEAN ;
VAR
   now, rb, kappa: REAL ;
   pa, pb: CParams ;
   cc: ARRAY [0..CcMaxDegree] OF REAL ;
   pe: ARRAY [0..PeMaxDegree] OF REAL ;
   deg, vb: INTEGER ;
BEGIN
   now := A^.tb ;
   IF feature = FeatCC THEN
      IF j >= 0 THEN
         vb := B^.v0 + j ;
         rb := 0.0
      ELSE
         vb := -1 ;
         rb := B^.r
      END ;
      CircleParamsOf (A, now, -1, pa) ;
      CircleParamsOf (B, now, vb, pb) ;
      deg := circles_gap (pa, A^.r, pb, rb, cc) ;
      kappa := Tol * (2.0 * (A^.r + rb) + Tol) ;
      RETURN (deg >= 1) AND touching_now (cc, deg, kappa)
   END ;
   IF i >= 0 THEN
      deg := PeCoefficients (A, B, Verts^[A^.v0 + i].rho, Verts^[A^.v0 + i].beta, 0.0, j, now, pe)
   ELSE
      deg := PeCoefficients (A, B, A^.orbit, A^.ophase, A^.r, j, now, pe)
   END ;
   RETURN (deg >= 1) AND touching_now (pe, deg, Tol)
END closing ;


PROCEDURE ClearCounts ;
VAR
   k: INTEGER ;
BEGIN
   NCc := CcVariants ;
   NPe := PeVariants ;
   CcCounts := Grow (CcCounts, NCc, SIZE (LONGINT)) ;
   PeCounts := Grow (PeCounts, NPe, SIZE (LONGINT)) ;
   FOR k := 0 TO NCc - 1 DO CcCounts^[k] := 0 END ;
   FOR k := 0 TO NPe - 1 DO PeCounts^[k] := 0 END
END ClearCounts ;


(* Binomial's C(j, i): Pascal's triangle (sums of small integers, exact). *)
PROCEDURE SetBinomial ;
VAR
   j, i: INTEGER ;
BEGIN
   FOR j := 0 TO 8 DO
      FOR i := 0 TO 8 DO
         IF (i = 0) OR (i = j) THEN
            Binomial[j, i] := 1.0
         ELSIF i < j THEN
            Binomial[j, i] := Binomial[j - 1, i - 1] + Binomial[j - 1, i]
         ELSE
            Binomial[j, i] := 0.0
         END
      END
   END
END SetBinomial ;


BEGIN
   SetBinomial ;
   Library := FALSE ;
   EdgePolys := NIL ;
   CapEdgePolys := 0
END SimPredict.
