IMPLEMENTATION MODULE Toi ;

(* The library over the simulator's pair computation: the two bodies are
   made simulator bodies (clock at 0, no support, awake) in tables of this
   module's own, which stand in for SimScene's for the query; the windows
   are sized as docs/toi.md says; SimPredict.PairContact finds the contact
   and SimContact.contact_frame its point and normal.  The same IEEE double
   operations in the same order as m2c_toi.c (libm's atan2, pow, sin, cos). *)

FROM SYSTEM IMPORT ADR ;
FROM CMath IMPORT atan2, pow, sqrt ;
FROM RealMath IMPORT cos, sin ;
FROM SimScene IMPORT Body, BodyArray, BodyRef, Grow, RestSlots, Vertex, VertexArray ;
IMPORT SimScene ;
FROM SimWorld IMPORT NCc ;
FROM SimMotion IMPORT rebase, StateAt, TurnRate ;
FROM SimOverlap IMPORT polygons_separation, separation ;
FROM SimContact IMPORT contact_frame ;
FROM SimPredict IMPORT ClearCounts, PairContact ;
IMPORT SimPredict ;

CONST
   MaxReal = 1.7976931348623157E308 ;
   Pi = 3.141592653589793 ;      (* pi rounded to double *)
   MaxSteps = 10000000 ;         (* the most steps (and Taylor windows) of one query *)
   TwoM30 = 1.0 / 1073741824.0 ; (* 2^-30 *)

VAR
   Two: BodyArray ;              (* the query's bodies A (0) and B (1) *)
   TwoVerts: VertexArray ;       (* their vertices: A's, then B's *)
   SepAX, SepAY, SepBX, SepBY: ARRAY [0..MaxVertices - 1] OF REAL ;    (* LibrarySeparation's vertices (m) *)


PROCEDURE Defaults (VAR o: Options) ;
BEGIN
   o.tol := 1.0E-9 ;
   o.taylorOrder := 4
END Defaults ;


(* x is neither infinite nor NaN: x - x is 0 exactly then, NaN otherwise. *)
PROCEDURE Finite (x: REAL) : BOOLEAN ;
VAR
   d: REAL ;
BEGIN
   d := x - x ;
   RETURN d = 0.0
END Finite ;


PROCEDURE Circle (VAR s: Shape; radius: REAL) : BOOLEAN ;
BEGIN
   IF NOT ((radius > 0.0) AND (radius <= MaxReal)) THEN RETURN FALSE END ;
   s.nverts := 0 ;
   s.radius := radius ;
   s.bound := radius ;
   RETURN TRUE
END Circle ;


PROCEDURE Polygon (VAR s: Shape; xy: ARRAY OF REAL; n: INTEGER) : BOOLEAN ;
VAR
   k, k1, k2: INTEGER ;
   bound, x0, y0, x1, y1, x2, y2, ex, ey, ln, nx, ny, tx, ty, turn, d: REAL ;
BEGIN
   IF (n < 3) OR (n > MaxVertices) OR (VAL (INTEGER, HIGH (xy)) < 2 * n - 1) THEN RETURN FALSE END ;
   FOR k := 0 TO 2 * n - 1 DO
      IF NOT Finite (xy[k]) THEN RETURN FALSE END
   END ;
   bound := 0.0 ;
   FOR k := 0 TO n - 1 DO
      k1 := (k + 1) MOD n ;
      k2 := (k + 2) MOD n ;
      x0 := xy[2 * k] ;
      y0 := xy[2 * k + 1] ;
      x1 := xy[2 * k1] ;
      y1 := xy[2 * k1 + 1] ;
      x2 := xy[2 * k2] ;
      y2 := xy[2 * k2 + 1] ;
      ex := x1 - x0 ;
      ey := y1 - y0 ;
      (* strictly convex, counter-clockwise: every turn left *)
      IF NOT (ex * (y2 - y1) - ey * (x2 - x1) > 0.0) THEN RETURN FALSE END ;
      ln := sqrt (ex * ex + ey * ey) ;
      nx := ey / ln ;            (* outward: the polygon is counter-clockwise *)
      ny := -ex / ln ;
      tx := ex / ln ;
      ty := ey / ln ;
      s.verts[k].lx := x0 ;
      s.verts[k].ly := y0 ;
      s.verts[k].rho := sqrt (x0 * x0 + y0 * y0) ;
      s.verts[k].beta := atan2 (y0, x0) ;
      s.verts[k].psi := atan2 (ny, nx) ;
      s.verts[k].h := nx * x0 + ny * y0 ;
      s.verts[k].s1 := tx * x0 + ty * y0 ;
      s.verts[k].s2 := tx * x1 + ty * y1 ;
      s.verts[k].nx := nx ;
      s.verts[k].ny := ny ;
      s.verts[k].cover := -1 ;
      IF s.verts[k].rho > bound THEN bound := s.verts[k].rho END
   END ;
   (* the edges wind once around the centre of rotation's side: the turns sum to 2 pi *)
   turn := 0.0 ;
   FOR k := 0 TO n - 1 DO
      d := s.verts[(k + 1) MOD n].psi - s.verts[k].psi ;
      WHILE d <= 0.0 DO d := d + 2.0 * Pi END ;
      turn := turn + d
   END ;
   IF NOT (turn < 3.0 * Pi) THEN RETURN FALSE END ;
   s.nverts := n ;
   s.radius := 0.0 ;
   s.bound := bound ;
   RETURN TRUE
END Polygon ;


(* The largest angle (at most 0.5 rad) whose order-n Taylor remainder of
   sin and cos, a^(n+1)/(n+1)!, times the lever (m) stays below tol. *)
PROCEDURE AngleFor (lever: REAL; n: INTEGER; tol: REAL) : REAL ;
VAR
   f, a: REAL ;
   k: INTEGER ;
BEGIN
   f := 1.0 ;
   FOR k := 2 TO n + 1 DO f := f * VAL (REAL, k) END ;
   a := pow (f * tol / lever, 1.0 / VAL (REAL, n + 1)) ;
   IF a < 0.5 THEN RETURN a END ;
   RETURN 0.5
END AngleFor ;


PROCEDURE FiniteMotion (VAR q: Motion) : BOOLEAN ;
BEGIN
   RETURN Finite (q.x) AND Finite (q.y) AND Finite (q.vx) AND Finite (q.vy) AND Finite (q.ax)
          AND Finite (q.ay) AND Finite (q.angle) AND Finite (q.omega) AND Finite (q.orbit)
          AND Finite (q.orbitPhase) AND (q.orbit >= 0.0)
END FiniteMotion ;


(* The simulator's body idx of shape s moving as q (its clock at 0), its
   vertices copied to TwoVerts^[v0 ..]. *)
PROCEDURE BodyOf (VAR s: Shape; VAR q: Motion; idx, v0: INTEGER) ;
VAR
   b: BodyRef ;
   k: INTEGER ;
BEGIN
   b := ADR (Two^[idx]) ;
   b^.idx := idx ;
   b^.polygon := s.nverts > 0 ;
   b^.fixed := FALSE ;
   b^.large := FALSE ;
   b^.invM := 0.0 ;
   b^.invI := 0.0 ;
   b^.e := 0.0 ;
   b^.mu := 0.0 ;
   b^.px := q.x ;
   b^.py := q.y ;
   b^.vx := q.vx ;
   b^.vy := q.vy ;
   b^.ax := q.ax ;
   b^.ay := q.ay ;
   b^.fax := q.ax ;
   b^.fay := q.ay ;
   b^.ang := q.angle ;
   b^.om := q.omega ;
   b^.tb := 0.0 ;
   IF b^.polygon THEN
      b^.r := 0.0 ;
      b^.orbit := 0.0 ;
      b^.ophase := 0.0 ;
      b^.bound := s.bound
   ELSE
      b^.r := s.radius ;
      b^.orbit := q.orbit ;
      b^.ophase := q.orbitPhase ;
      b^.bound := b^.orbit + b^.r
   END ;
   b^.window := 0.0 ;
   b^.v0 := v0 ;
   b^.nv := s.nverts ;
   FOR k := 0 TO s.nverts - 1 DO TwoVerts^[v0 + k] := s.verts[k] END ;
   b^.stamp := 0 ;
   b^.cx := 0 ;
   b^.cy := 0 ;
   b^.sup := -1 ;
   b^.sup_edge := -1 ;
   b^.tx := 0.0 ;
   b^.ty := 0.0 ;
   b^.load := 0.0 ;
   b^.at := 0.0 ;
   b^.gone := FALSE ;
   b^.asleep := FALSE ;
   b^.island := -1 ;
   b^.non := 0 ;
   FOR k := 0 TO RestSlots - 1 DO b^.rc[k].other1 := 0 END ;
   b^.placed := FALSE ;
   b^.seen := 0 ;
   b^.carry := 0 ;
   b^.rest := -1
END BodyOf ;


(* separation of A and B at 0 (the query's tables in place); of two
   polygons with every vertex from one cosine and sine of its body's angle,
   its place (lx, ly) in the body's frame rotated: the library's own values
   (the simulator keeps separation's), as SimPredict's clear_polygons takes
   them. *)
PROCEDURE LibrarySeparation (A, B: BodyRef) : REAL ;
VAR
   x, y, vx, vy, ang, c, s: REAL ;
   k: INTEGER ;
BEGIN
   IF NOT (A^.polygon AND B^.polygon) THEN RETURN separation (A, B, 0.0) END ;
   StateAt (A, 0.0, x, y, vx, vy, ang) ;
   c := cos (ang) ;
   s := sin (ang) ;
   FOR k := 0 TO A^.nv - 1 DO
      SepAX[k] := x + (c * SimScene.Verts^[A^.v0 + k].lx - s * SimScene.Verts^[A^.v0 + k].ly) ;
      SepAY[k] := y + (s * SimScene.Verts^[A^.v0 + k].lx + c * SimScene.Verts^[A^.v0 + k].ly)
   END ;
   StateAt (B, 0.0, x, y, vx, vy, ang) ;
   c := cos (ang) ;
   s := sin (ang) ;
   FOR k := 0 TO B^.nv - 1 DO
      SepBX[k] := x + (c * SimScene.Verts^[B^.v0 + k].lx - s * SimScene.Verts^[B^.v0 + k].ly) ;
      SepBY[k] := y + (s * SimScene.Verts^[B^.v0 + k].lx + c * SimScene.Verts^[B^.v0 + k].ly)
   END ;
   RETURN polygons_separation (A, B, 0.0, SepAX, SepAY, SepBX, SepBY)
END LibrarySeparation ;


(* A and B at 0 are farther apart than their bounds and the tolerance tol,
   so that their separation exceeds tol (each body lies within its bound
   about its centre of rotation) and the overlap test can be spared: the
   centres' distance less the bounds, with a margin of 2^-30 of the sizes
   for every rounding. *)
PROCEDURE BoundsApart (A, B: BodyRef; tol: REAL) : BOOLEAN ;
VAR
   dx, dy, r, d: REAL ;
BEGIN
   dx := B^.px - A^.px ;
   dy := B^.py - A^.py ;
   r := A^.bound + B^.bound ;
   d := sqrt (dx * dx + dy * dy) ;
   RETURN d - r > tol + TwoM30 * (d + r + ABS (A^.px) + ABS (A^.py) + ABS (B^.px) + ABS (B^.py))
END BoundsApart ;


PROCEDURE TimeOfImpact (VAR a: Shape; VAR ma: Motion; VAR b: Shape; VAR mb: Motion; horizon: REAL;
                        VAR o: Options; VAR r: Result) : INTEGER ;
VAR
   A, B: BodyRef ;
   savedBodies: BodyArray ;
   savedVerts: VertexArray ;
   savedN, savedNV: INTEGER ;
   savedTol, savedAlpha: REAL ;
   tol, ta, tb, big, alpha, t, px, py, nx, ny: REAL ;
   found, feat, fa, fb, fi, fj: INTEGER ;
BEGIN
   r.status := Error ;
   r.t := 0.0 ;
   r.feature := 0 ;
   r.first := 0 ;
   r.i := -1 ;
   r.j := -1 ;
   r.px := 0.0 ;
   r.py := 0.0 ;
   r.nx := 0.0 ;
   r.ny := 0.0 ;
   IF NOT ((o.tol > 0.0) AND (o.tol <= MaxReal)) OR (o.taylorOrder < 1) OR (o.taylorOrder > 7) THEN
      RETURN Error
   END ;
   IF NOT ((horizon >= 0.0) AND (horizon <= MaxReal)) OR NOT FiniteMotion (ma) OR NOT FiniteMotion (mb) THEN
      RETURN Error
   END ;
   IF ((a.nverts > 0) AND (ma.orbit # 0.0)) OR ((b.nverts > 0) AND (mb.orbit # 0.0)) THEN RETURN Error END ;
   IF (a.nverts < 0) OR (a.nverts > MaxVertices) OR (b.nverts < 0) OR (b.nverts > MaxVertices) THEN
      RETURN Error
   END ;
   IF NCc = 0 THEN ClearCounts END ;    (* the variant counters, when no world has made them *)
   BodyOf (a, ma, 0, 0) ;
   BodyOf (b, mb, 1, a.nverts) ;
   A := ADR (Two^[0]) ;
   B := ADR (Two^[1]) ;
   tol := o.tol ;
   (* the windows (docs/simulator.md, "Taylor windows"): both turn, a lever
      of twice the larger bound plus the larger bound; one turns, its bound
      plus a circle partner's radius *)
   ta := TurnRate (A) ;
   tb := TurnRate (B) ;
   IF A^.bound > B^.bound THEN big := A^.bound ELSE big := B^.bound END ;
   alpha := 0.5 ;
   IF (ta > 0.0) AND (tb > 0.0) THEN
      alpha := AngleFor (2.0 * big + big, o.taylorOrder, tol)
   ELSIF ta > 0.0 THEN
      A^.window := AngleFor (A^.bound + B^.r, o.taylorOrder, tol)
   ELSIF tb > 0.0 THEN
      B^.window := AngleFor (B^.bound + A^.r, o.taylorOrder, tol)
   END ;
   (* the simulator's tables stand aside for the query *)
   savedBodies := SimScene.Bodies ;
   savedVerts := SimScene.Verts ;
   savedN := SimScene.NBodies ;
   savedNV := SimScene.NVerts ;
   savedTol := SimScene.Tol ;
   savedAlpha := SimScene.Alpha ;
   SimScene.Bodies := Two ;
   SimScene.Verts := TwoVerts ;
   SimScene.NBodies := 2 ;
   SimScene.NVerts := a.nverts + b.nverts ;
   SimScene.Tol := tol ;
   SimScene.Alpha := alpha ;
   SimPredict.Library := TRUE ;
   IF NOT BoundsApart (A, B, tol) AND (LibrarySeparation (A, B) < -tol) THEN
      r.status := Overlapped
   ELSE
      found := PairContact (A, B, 0.0, horizon, MaxSteps, MaxSteps, t, feat, fa, fb, fi, fj) ;
      IF found = 0 THEN
         r.status := None
      ELSIF found = 1 THEN
         r.status := Hit ;
         r.t := t ;
         r.feature := feat ;
         IF fa = 1 THEN r.first := 1 ELSE r.first := 0 END ;
         r.i := fi ;
         r.j := fj ;
         (* the contact frame of the bodies at t *)
         rebase (A, t) ;
         rebase (B, t) ;
         contact_frame (t, feat, ADR (Two^[fa]), ADR (Two^[fb]), fi, fj, px, py, nx, ny) ;
         r.px := px ;
         r.py := py ;
         r.nx := nx ;
         r.ny := ny
      END
   END ;
   SimScene.Bodies := savedBodies ;
   SimScene.Verts := savedVerts ;
   SimScene.NBodies := savedN ;
   SimScene.NVerts := savedNV ;
   SimScene.Tol := savedTol ;
   SimScene.Alpha := savedAlpha ;
   SimPredict.Library := FALSE ;
   RETURN r.status
END TimeOfImpact ;


BEGIN
   Still.x := 0.0 ;
   Still.y := 0.0 ;
   Still.vx := 0.0 ;
   Still.vy := 0.0 ;
   Still.ax := 0.0 ;
   Still.ay := 0.0 ;
   Still.angle := 0.0 ;
   Still.omega := 0.0 ;
   Still.orbit := 0.0 ;
   Still.orbitPhase := 0.0 ;
   Two := Grow (NIL, 2, SIZE (Body)) ;
   TwoVerts := Grow (NIL, 2 * MaxVertices, SIZE (Vertex))
END Toi.
