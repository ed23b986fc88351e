MODULE SimMain ;

(* The discrete-event simulator of docs/simulator.md in Modula-2: reads a
   compiled scene on standard input and writes the flat trace on standard
   output.  A transcription of the Python reference
   (runtimes/python/max2code_rt/sim.py), procedure for procedure, with the
   same IEEE double operations in the same order (no FMA: built with
   -ffp-contract=off; sin and cos are libm's through RealMath, floor and
   sqrt libm's through C), so that it writes the same bytes.  Numbers are
   written by SimOut as "%.17g" writes them.

   Every prediction goes through the generated entries of
   equations/circle-circle.mxm and equations/point-edge.mxm, included below
   from the build directory, and through Roots.SmallestRoot.  The build
   defines SIM_CC_VARIANTS and SIM_PE_VARIANTS, the number of variants each
   NAME_variant counts (max2code/targets/m2.py reads them from the generated
   files). *)

FROM SYSTEM IMPORT ADDRESS, ADR ;
FROM RealMath IMPORT sin, cos ;
FROM Roots IMPORT SmallestRoot ;
FROM CMath IMPORT sqrt, getchar ;
FROM SimC IMPORT floor, strtod, realloc, exit ;
FROM SimHeap IMPORT Event, Push, Pop ;
FROM SimOut IMPORT Str, Int, Real, SpReal, Ln, Flush ;

#include "circle_circle.mxd"
#include "point_edge.mxd"

CONST
   HalfPi = 1.5707963267948966 ;   (* pi/2 rounded to double (cos x = sin(x + pi/2)) *)
   (* event kinds, in the order they are handled at equal times *)
   KInput = 0 ;
   KCollision = 1 ;
   KCell = 2 ;
   KHorizon = 3 ;
   KFrame = 4 ;
   (* contact features *)
   FeatCC = 0 ;
   FeatPE = 1 ;
   (* statistics, in the order of the N lines *)
   StCollisions = 0 ;
   StInputs = 1 ;
   StFrames = 2 ;
   StCells = 3 ;
   StHorizons = 4 ;
   StStale = 5 ;
   StPairs = 6 ;
   StFeatures = 7 ;
   NStats = 8 ;
   CcVariants = SIM_CC_VARIANTS ;
   PeVariants = SIM_PE_VARIANTS ;
   CcMaxDegree = circle_circle_coefficients_max_degree ;
   PeMaxDegree = point_edge_coefficients_max_degree ;
   (* bounds of the array types only: storage is allocated as needed *)
   MaxItems = 16777216 ;
   TokLen = 255 ;

TYPE
   (* One vertex of a polygon and the edge that starts at it (to the next
      vertex), in the body's frame: all precomputed by the scene compiler. *)
   Vertex = RECORD
      lx, ly, rho, beta, psi, h, s1, s2: REAL ;
   END ;
   Body = RECORD
      idx: INTEGER ;
      polygon, fixed, large: BOOLEAN ;
      invM, invI, e, px, py, vx, vy, ax, ay, ang, om, tb,
      r, orbit, ophase, bound: REAL ;
      v0, nv: INTEGER ;        (* its vertices: Verts^[v0 .. v0 + nv - 1] *)
      stamp: LONGINT ;         (* motion counter (lazy invalidation) *)
      cx, cy: INTEGER ;        (* grid cell *)
   END ;
   BodyRef = POINTER TO Body ;
   InputRec = RECORD
      t, vx, vy: REAL ;
      body, mode: INTEGER ;
   END ;
   IntList = POINTER TO ARRAY [0..MaxItems - 1] OF INTEGER ;
   CellRec = RECORD
      n, cap: INTEGER ;
      items: IntList ;         (* body indices *)
   END ;
   BodyArray = POINTER TO ARRAY [0..MaxItems - 1] OF Body ;
   VertexArray = POINTER TO ARRAY [0..MaxItems - 1] OF Vertex ;
   InputArray = POINTER TO ARRAY [0..MaxItems - 1] OF InputRec ;
   CellArray = POINTER TO ARRAY [0..MaxItems - 1] OF CellRec ;
   Token = ARRAY [0..TokLen] OF CHAR ;

VAR
   (* the scene *)
   EndT, FrameDt, Tol, RestSpeed, Alpha: REAL ;
   MaxSame: LONGINT ;
   GridX0, GridY0, CellW, CellH: REAL ;
   GridNX, GridNY: INTEGER ;
   NBodies, NVerts, NInputs, NLarge: INTEGER ;
   Bodies: BodyArray ;
   Verts: VertexArray ;
   Inputs: InputArray ;
   (* the simulator *)
   Cells: CellArray ;
   Large: IntList ;
   Seq: LONGINT ;
   Stats: ARRAY [0..NStats - 1] OF LONGINT ;
   CcCounts: ARRAY [0..CcVariants - 1] OF LONGINT ;
   PeCounts: ARRAY [0..PeVariants - 1] OF LONGINT ;
   (* the point-edge check of the prediction under way (predict_pe's inside) *)
   ChkX, ChkY: BodyRef ;
   ChkV, ChkEdge: INTEGER ;
   ChkNow: REAL ;
   (* reading *)
   Pending: INTEGER ;
   Tok: Token ;


(* ---- output and errors ------------------------------------------------ *)

(* The end of a stuck or bad scene: "X message" was written; status 1. *)
PROCEDURE Fail ;
BEGIN
   Flush ;
   exit (1)
END Fail ;


PROCEDURE FailMsg (msg: ARRAY OF CHAR) ;
BEGIN
   Str ("X ") ;
   Str (msg) ;
   Ln ;
   Fail
END FailMsg ;


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


(* ---- reading the flat scene ------------------------------------------- *)

PROCEDURE NextChar () : INTEGER ;
VAR
   ch: INTEGER ;
BEGIN
   IF Pending # -2 THEN
      ch := Pending ;
      Pending := -2 ;
      RETURN ch
   END ;
   RETURN getchar ()
END NextChar ;


(* The next whitespace-delimited token into Tok; its length. *)
PROCEDURE Word () : INTEGER ;
VAR
   ch, k: INTEGER ;
BEGIN
   REPEAT
      ch := NextChar ()
   UNTIL (ch < 0) OR (ch > 32) ;
   IF ch < 0 THEN FailMsg ("scene: unexpected end of input") END ;
   k := 0 ;
   WHILE ch > 32 DO
      IF k >= TokLen THEN FailMsg ("scene: token too long") END ;
      Tok[k] := CHR (ch) ;
      INC (k) ;
      ch := NextChar ()
   END ;
   Tok[k] := 0C ;
   Pending := ch ;
   RETURN k
END Word ;


(* Reads the next token, which must be expect. *)
PROCEDURE Expect (expect: ARRAY OF CHAR) ;
VAR
   k, n: INTEGER ;
   same: BOOLEAN ;
BEGIN
   n := Word () ;
   same := TRUE ;
   k := 0 ;
   WHILE same AND (k <= n) DO
      IF (VAL (CARDINAL, k) > HIGH (expect)) THEN
         same := Tok[k] = 0C
      ELSIF Tok[k] # expect[k] THEN
         same := FALSE
      ELSIF expect[k] = 0C THEN
         k := n
      END ;
      INC (k)
   END ;
   IF NOT same THEN
      Str ("X scene: expected '") ;
      Str (expect) ;
      Str ("', found '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END
END Expect ;


PROCEDURE Num () : REAL ;
VAR
   n: INTEGER ;
   x: REAL ;
   endp: ADDRESS ;
BEGIN
   n := Word () ;
   endp := NIL ;
   x := strtod (Tok, endp) ;
   IF endp # ADR (Tok[n]) THEN
      Str ("X scene: not a number: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END ;
   RETURN x
END Num ;


(* The next token as a whole number (up to 18 digits). *)
PROCEDURE ReadLongInt () : LONGINT ;
VAR
   n, k: INTEGER ;
   v: LONGINT ;
   neg, ok: BOOLEAN ;
BEGIN
   n := Word () ;
   k := 0 ;
   neg := FALSE ;
   IF (Tok[0] = '-') OR (Tok[0] = '+') THEN
      neg := Tok[0] = '-' ;
      k := 1
   END ;
   ok := (k < n) AND (n - k <= 18) ;
   v := 0 ;
   WHILE ok AND (k < n) DO
      IF (Tok[k] >= '0') AND (Tok[k] <= '9') THEN
         v := v * 10 + VAL (LONGINT, ORD (Tok[k]) - ORD ('0'))
      ELSE
         ok := FALSE
      END ;
      INC (k)
   END ;
   IF NOT ok THEN
      Str ("X scene: not an integer: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END ;
   IF neg THEN RETURN -v END ;
   RETURN v
END ReadLongInt ;


(* The next token as a count or index (INTEGER range). *)
PROCEDURE ReadInt () : INTEGER ;
VAR
   v: LONGINT ;
BEGIN
   v := ReadLongInt () ;
   IF (v > VAL (LONGINT, MAX (INTEGER))) OR (v < VAL (LONGINT, MIN (INTEGER))) THEN
      Str ("X scene: integer out of range: '") ;
      Str (Tok) ;
      Str ("'") ;
      Ln ;
      Fail
   END ;
   RETURN VAL (INTEGER, v)
END ReadInt ;


PROCEDURE ReadScene ;
VAR
   i, k, nv, capVerts: INTEGER ;
   b: BodyRef ;
   v: Vertex ;
BEGIN
   Expect ("m2c-scene") ;
   IF ReadInt () # 1 THEN FailMsg ("scene: unknown version") END ;
   Expect ("end") ; EndT := Num () ;
   Expect ("frame") ; FrameDt := Num () ;
   Expect ("tolerance") ; Tol := Num () ;
   Expect ("rest_speed") ; RestSpeed := Num () ;
   Expect ("window_angle") ; Alpha := Num () ;
   Expect ("max_same_time") ; MaxSame := ReadLongInt () ;
   Expect ("grid") ;
   GridX0 := Num () ; GridY0 := Num () ; CellW := Num () ; CellH := Num () ;
   GridNX := ReadInt () ; GridNY := ReadInt () ;
   IF (GridNX < 1) OR (GridNY < 1) OR (GridNX > MaxItems DIV GridNY) THEN FailMsg ("scene: bad grid") END ;
   Expect ("bodies") ;
   NBodies := ReadInt () ;
   Bodies := Grow (NIL, NBodies, SIZE (Body)) ;
   NVerts := 0 ;
   capVerts := 16 ;
   Verts := Grow (NIL, capVerts, SIZE (Vertex)) ;
   FOR i := 0 TO NBodies - 1 DO
      Expect ("body") ;
      b := ADR (Bodies^[i]) ;
      b^.idx := i ;
      b^.polygon := ReadInt () = 1 ;
      b^.fixed := ReadInt () = 1 ;
      b^.invM := Num () ; b^.invI := Num () ; b^.e := Num () ;
      b^.px := Num () ; b^.py := Num () ; b^.vx := Num () ; b^.vy := Num () ;
      b^.ax := Num () ; b^.ay := Num () ;
      b^.ang := Num () ; b^.om := Num () ;
      b^.r := Num () ; b^.orbit := Num () ; b^.ophase := Num () ; b^.bound := Num () ;
      b^.large := ReadInt () = 1 ;
      nv := ReadInt () ;
      IF nv < 0 THEN FailMsg ("scene: negative vertex count") END ;
      b^.v0 := NVerts ;
      b^.nv := nv ;
      IF NVerts + nv > capVerts THEN
         WHILE NVerts + nv > capVerts DO capVerts := 2 * capVerts END ;
         Verts := Grow (Verts, capVerts, SIZE (Vertex))
      END ;
      FOR k := 0 TO nv - 1 DO
         Expect ("v") ;
         v.lx := Num () ; v.ly := Num () ; v.rho := Num () ; v.beta := Num () ;
         v.psi := Num () ; v.h := Num () ; v.s1 := Num () ; v.s2 := Num () ;
         Verts^[NVerts] := v ;
         INC (NVerts)
      END ;
      b^.tb := 0.0 ;
      b^.stamp := 0 ;
      b^.cx := 0 ;
      b^.cy := 0
   END ;
   Expect ("inputs") ;
   NInputs := ReadInt () ;
   Inputs := Grow (NIL, NInputs, SIZE (InputRec)) ;
   FOR i := 0 TO NInputs - 1 DO
      Expect ("input") ;
      Inputs^[i].t := Num () ;
      Inputs^[i].body := ReadInt () ;
      Inputs^[i].mode := ReadInt () ;
      Inputs^[i].vx := Num () ;
      Inputs^[i].vy := Num () ;
      IF (Inputs^[i].body < 0) OR (Inputs^[i].body >= NBodies) THEN
         FailMsg ("scene: input of an unknown body")
      END
   END ;
   Expect ("end")
END ReadScene ;


(* ---- motion ------------------------------------------------------------ *)

PROCEDURE Advance (b: BodyRef; t: REAL) ;
VAR
   dt: REAL ;
BEGIN
   dt := t - b^.tb ;
   b^.px := b^.px + (b^.vx + 0.5 * b^.ax * dt) * dt ;
   b^.py := b^.py + (b^.vy + 0.5 * b^.ay * dt) * dt ;
   b^.vx := b^.vx + b^.ax * dt ;
   b^.vy := b^.vy + b^.ay * dt ;
   b^.ang := b^.ang + b^.om * dt ;
   b^.tb := t
END Advance ;


(* Centre, velocity and angle at time t (the body is not changed). *)
PROCEDURE StateAt (b: BodyRef; t: REAL; VAR x, y, vx, vy, ang: REAL) ;
VAR
   dt: REAL ;
BEGIN
   dt := t - b^.tb ;
   x := b^.px + (b^.vx + 0.5 * b^.ax * dt) * dt ;
   y := b^.py + (b^.vy + 0.5 * b^.ay * dt) * dt ;
   vx := b^.vx + b^.ax * dt ;
   vy := b^.vy + b^.ay * dt ;
   ang := b^.ang + b^.om * dt
END StateAt ;


PROCEDURE TurnRate (b: BodyRef) : REAL ;
BEGIN
   IF b^.polygon OR (b^.orbit > 0.0) THEN
      RETURN ABS (b^.om)
   END ;
   RETURN 0.0
END TurnRate ;


(* ---- the event queue --------------------------------------------------- *)

PROCEDURE Schedule (t: REAL; kind, a, b, feat, i, j: INTEGER) ;
VAR
   ev: Event ;
BEGIN
   ev.t := t ;
   ev.kind := kind ;
   ev.seq := Seq ;
   ev.a := a ;
   ev.b := b ;
   ev.feat := feat ;
   ev.i := i ;
   ev.j := j ;
   IF a >= 0 THEN ev.sa := Bodies^[a].stamp ELSE ev.sa := 0 END ;
   IF b >= 0 THEN ev.sb := Bodies^[b].stamp ELSE ev.sb := 0 END ;
   IF NOT Push (ev) THEN FailMsg ("out of memory (event queue)") END ;
   INC (Seq)
END Schedule ;


(* ---- grid ---------------------------------------------------------------- *)

PROCEDURE Clamp (f: REAL; n: INTEGER) : INTEGER ;
BEGIN
   IF f < 0.0 THEN
      RETURN 0
   ELSIF f > VAL (REAL, n - 1) THEN
      RETURN n - 1
   END ;
   RETURN VAL (INTEGER, f)
END Clamp ;


PROCEDURE CellOf (x, y: REAL; VAR ix, iy: INTEGER) ;
BEGIN
   ix := Clamp (floor ((x - GridX0) / CellW), GridNX) ;
   iy := Clamp (floor ((y - GridY0) / CellH), GridNY)
END CellOf ;


(* Removes b from its cell: the last element moves into the hole. *)
PROCEDURE CellRemove (b: BodyRef) ;
VAR
   c: INTEGER ;
   k: INTEGER ;
BEGIN
   c := b^.cy * GridNX + b^.cx ;
   k := 0 ;
   WHILE Cells^[c].items^[k] # b^.idx DO INC (k) END ;
   DEC (Cells^[c].n) ;
   IF k < Cells^[c].n THEN
      Cells^[c].items^[k] := Cells^[c].items^[Cells^[c].n]
   END
END CellRemove ;


PROCEDURE CellAdd (b: BodyRef) ;
VAR
   c: INTEGER ;
BEGIN
   c := b^.cy * GridNX + b^.cx ;
   IF Cells^[c].n = Cells^[c].cap THEN
      IF Cells^[c].cap = 0 THEN Cells^[c].cap := 4 ELSE Cells^[c].cap := 2 * Cells^[c].cap END ;
      Cells^[c].items := Grow (Cells^[c].items, Cells^[c].cap, SIZE (INTEGER))
   END ;
   Cells^[c].items^[Cells^[c].n] := b^.idx ;
   INC (Cells^[c].n)
END CellAdd ;


PROCEDURE Max (a, b: INTEGER) : INTEGER ;
BEGIN
   IF a > b THEN RETURN a END ;
   RETURN b
END Max ;


PROCEDURE Min (a, b: INTEGER) : INTEGER ;
BEGIN
   IF a < b THEN RETURN a END ;
   RETURN b
END Min ;


(* ---- first valid root of one feature ----------------------------------- *)

(* The point-edge check of predict_pe: whether the contact at s lies on the
   edge (within the tolerance); the prediction sets Chk*. *)
PROCEDURE Inside (s: REAL) : BOOLEAN ;
VAR
   t, px, py, qx, qy, qvx, qvy, qa, th, along: REAL ;
   ed: Vertex ;
BEGIN
   ed := Verts^[ChkEdge] ;
   t := ChkNow + s ;
   PointAt (ChkX, ChkV, t, px, py) ;
   StateAt (ChkY, t, qx, qy, qvx, qvy, qa) ;
   th := qa + ed.psi ;
   along := (px - qx) * (-sin (th)) + (py - qy) * cos (th) ;
   RETURN (ed.s1 - Tol <= along) AND (along <= ed.s2 + Tol)
END Inside ;


PROCEDURE Check (edge: BOOLEAN; s: REAL) : BOOLEAN ;
BEGIN
   IF edge THEN RETURN Inside (s) END ;
   RETURN TRUE
END Check ;


(* The smallest s in [0, w] where the gap c(s) reaches zero while
   decreasing and the check holds (edge: Inside, else always).  At s = 0
   the gap counts as zero within kappa: approaching means contact now,
   separating never. *)
PROCEDURE FirstContact (VAR c: ARRAY OF REAL; deg: INTEGER; w, kappa: REAL; edge: BOOLEAN;
                        VAR s: REAL) : BOOLEAN ;
VAR
   lo, d: REAL ;
   it, k: INTEGER ;
BEGIN
   IF (deg >= 1) AND (ABS (c[0]) <= kappa) AND (c[1] < 0.0) AND Check (edge, 0.0) THEN
      s := 0.0 ;
      RETURN TRUE
   END ;
   lo := 0.0 ;
   FOR it := 0 TO deg + 1 DO
      IF NOT SmallestRoot (c, deg, lo, w, s) THEN RETURN FALSE END ;
      d := 0.0 ;
      FOR k := deg TO 1 BY -1 DO
         d := d * s + VAL (REAL, k) * c[k]
      END ;
      IF (d < 0.0) AND Check (edge, s) THEN RETURN TRUE END ;
      lo := s
   END ;
   RETURN FALSE
END FirstContact ;


(* ---- features ------------------------------------------------------------ *)

(* World position of a circle's centre (v < 0) or of vertex v, at t. *)
PROCEDURE PointAt (b: BodyRef; v: INTEGER; t: REAL; VAR x, y: REAL) ;
VAR
   vx, vy, ang, d, beta: REAL ;
BEGIN
   StateAt (b, t, x, y, vx, vy, ang) ;
   IF v < 0 THEN
      d := b^.orbit ;
      beta := b^.ophase
   ELSE
      d := Verts^[v].rho ;
      beta := Verts^[v].beta
   END ;
   IF d = 0.0 THEN RETURN END ;
   x := x + d * cos (ang + beta) ;
   y := y + d * sin (ang + beta)
END PointAt ;


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
      FailMsg ("circle_circle: the scene uses an effect the generated code leaves out")
   END ;
   INC (CcCounts[idx]) ;
   INC (Stats[StFeatures]) ;
   RETURN circle_circle_coefficients (a, b, c, d, e, f, m, n, o, p, q, g, h, i, j, k, l, r, s, u, v, w, x, z,
                                      coef)
END CcCoefficients ;


(* Circle of A against circle of B (vb < 0, radius rb) or vertex vb of B
   (radius 0). *)
PROCEDURE PredictCC (A, B: BodyRef; vb: INTEGER; rb, now, w: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   a, b, c, d, e, f, m, n, o, p, q: REAL ;
   g, h, i, j, k, l, r, s, u, v, ww: REAL ;
   kappa: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   CircleParams (A, now, -1, a, b, c, d, e, f, m, n, o, p, q) ;
   CircleParams (B, now, vb, g, h, i, j, k, l, r, s, u, v, ww) ;
   (* only differences of the centres' motions matter: circle 1 moves
      relative to circle 2's centre of rotation *)
   deg := CcCoefficients (a - g, b - h, c - i, d, e, f, m - r, n - s, o - u, p, q,
                          0.0, 0.0, 0.0, j, k, l, 0.0, 0.0, 0.0, v, ww, A^.r, rb, coef) ;
   kappa := Tol * (2.0 * (A^.r + rb) + Tol) ;
   RETURN FirstContact (coef, deg, w, kappa, FALSE, t)
END PredictCC ;


(* Point of X (circle centre with radius, vx < 0, or vertex vx) against the
   line of edge j of Y. *)
PROCEDURE PredictPE (X, Y: BodyRef; vx, j: INTEGER; now, w: REAL; VAR t: REAL) : BOOLEAN ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2: REAL ;
   rho, beta, rad, phn, wr, phr, h: REAL ;
   ed: INTEGER ;
   idx, deg: INTEGER ;
   a1, a2, a3, a4, a5, a6: REAL ;
   coef: ARRAY [0..PeMaxDegree] OF REAL ;
BEGIN
   ed := Y^.v0 + j ;
   StateAt (X, now, x1, y1, u1, v1, ang1) ;
   StateAt (Y, now, x2, y2, u2, v2, ang2) ;
   IF vx < 0 THEN
      rho := X^.orbit ;
      beta := X^.ophase ;
      rad := X^.r
   ELSE
      rho := Verts^[vx].rho ;
      beta := Verts^[vx].beta ;
      rad := 0.0
   END ;
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
      FailMsg ("point_edge: the scene uses an effect the generated code leaves out")
   END ;
   INC (PeCounts[idx]) ;
   INC (Stats[StFeatures]) ;
   deg := point_edge_coefficients (a1, a2, a3, a4, a5, a6, rho, wr, phr, Y^.om, phn, h, coef) ;
   ChkX := X ;
   ChkY := Y ;
   ChkV := vx ;
   ChkEdge := ed ;
   ChkNow := now ;
   RETURN FirstContact (coef, deg, w, Tol, TRUE, t)
END PredictPE ;


(* ---- pairs ----------------------------------------------------------------- *)

(* The best contact of a pair so far. *)
TYPE
   Best = RECORD
      found: BOOLEAN ;
      t: REAL ;
      feat, a, b, i, j: INTEGER ;
   END ;


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


(* When the bounding circles first touch within (0, w]: TRUE and meet = 0.0
   when they overlap or touch now (within the tolerance), TRUE and meet > 0
   when they touch later, FALSE when they do not meet (exact: bounding
   circles do not turn). *)
PROCEDURE BoundsMeet (A, B: BodyRef; now, w: REAL; VAR meet: REAL) : BOOLEAN ;
VAR
   x1, y1, u1, v1, ang1, x2, y2, u2, v2, ang2: REAL ;
   coef: ARRAY [0..CcMaxDegree] OF REAL ;
   deg: INTEGER ;
BEGIN
   StateAt (A, now, x1, y1, u1, v1, ang1) ;
   StateAt (B, now, x2, y2, u2, v2, ang2) ;
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
      found := PredictPE (C, P, -1, j, now, w, t) ;
      Better (best, found, t, FeatPE, C^.idx, P^.idx, -1, j)
   END ;
   FOR k := 0 TO P^.nv - 1 DO
      found := PredictCC (C, P, P^.v0 + k, 0.0, now, w, t) ;
      Better (best, found, t, FeatCC, C^.idx, P^.idx, -1, k)
   END
END CirclePolygon ;


PROCEDURE VerticesEdges (A, B: BodyRef; now, w: REAL; VAR best: Best) ;
VAR
   i, j: INTEGER ;
   t: REAL ;
   found: BOOLEAN ;
BEGIN
   FOR i := 0 TO A^.nv - 1 DO
      FOR j := 0 TO B^.nv - 1 DO
         found := PredictPE (A, B, A^.v0 + i, j, now, w, t) ;
         Better (best, found, t, FeatPE, A^.idx, B^.idx, i, j)
      END
   END
END VerticesEdges ;


(* Schedules the first contact of A and B after now, or a horizon event
   where the Taylor polynomials of their turns stop being good. *)
PROCEDURE PredictPair (A, B: BodyRef; now: REAL) ;
VAR
   w, turn, q, t, meet: REAL ;
   best: Best ;
   found: BOOLEAN ;
BEGIN
   INC (Stats[StPairs]) ;
   w := EndT - now ;
   IF NOT (w > 0.0) THEN RETURN END ;
   IF A^.polygon OR B^.polygon THEN
      (* the bounding circles do not turn: until they touch, nothing can *)
      IF NOT BoundsMeet (A, B, now, w, meet) THEN RETURN END ;
      IF meet > 0.0 THEN
         Schedule (now + meet, KHorizon, A^.idx, B^.idx, -1, -1, -1) ;
         RETURN
      END
   END ;
   turn := TurnRate (A) + TurnRate (B) ;
   IF turn > 0.0 THEN
      q := Alpha / turn ;
      IF q < w THEN w := q END       (* Python's min(w, q) *)
   END ;
   best.found := FALSE ;
   best.t := 0.0 ;
   IF (NOT A^.polygon) AND (NOT B^.polygon) THEN
      found := PredictCC (A, B, -1, B^.r, now, w, t) ;
      Better (best, found, t, FeatCC, A^.idx, B^.idx, -1, -1)
   ELSIF NOT A^.polygon THEN
      CirclePolygon (A, B, now, w, best)
   ELSIF NOT B^.polygon THEN
      CirclePolygon (B, A, now, w, best)
   ELSE
      VerticesEdges (A, B, now, w, best) ;
      VerticesEdges (B, A, now, w, best)
   END ;
   IF best.found THEN
      Schedule (now + best.t, KCollision, best.a, best.b, best.feat, best.i, best.j)
   ELSIF now + w < EndT THEN
      Schedule (now + w, KHorizon, A^.idx, B^.idx, -1, -1, -1)
   END
END PredictPair ;


(* ---- per body -------------------------------------------------------------- *)

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


(* Predicts b against the large bodies other than b and skip, unless both
   are fixed. *)
PROCEDURE PredictLarge (b: BodyRef; skip: INTEGER; now: REAL) ;
VAR
   k, oi: INTEGER ;
   o: BodyRef ;
BEGIN
   FOR k := 0 TO NLarge - 1 DO
      oi := Large^[k] ;
      IF (oi # b^.idx) AND (oi # skip) THEN
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
   ScheduleCell (b, now)
END PredictBody ;


(* Schedules the first crossing of b's centre over a boundary of its cell. *)
PROCEDURE ScheduleCell (b: BodyRef; now: REAL) ;
VAR
   ulo, uhi, p, v, a, origin, size, bound, lo, u, bu: REAL ;
   c: ARRAY [0..2] OF REAL ;
   axis, dk, direction, i, n, it, baxis, bdir: INTEGER ;
   found, crossed: BOOLEAN ;
BEGIN
   IF b^.large OR ((b^.vx = 0.0) AND (b^.vy = 0.0) AND (b^.ax = 0.0) AND (b^.ay = 0.0)) THEN
      RETURN
   END ;
   ulo := now - b^.tb ;
   uhi := EndT - b^.tb ;
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
               bound := origin + VAL (REAL, i + 1) * size ;
               crossed := TRUE
            END
         ELSIF i > 0 THEN
            bound := origin + VAL (REAL, i) * size ;
            crossed := TRUE
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
      Schedule (b^.tb + bu, KCell, b^.idx, -1, -1, baxis, bdir)
   END
END ScheduleCell ;


(* ---- handling events --------------------------------------------------------- *)

PROCEDURE EmitState (b: BodyRef) ;
BEGIN
   Str ("S ") ;
   Int (b^.idx) ;
   SpReal (b^.tb) ;
   SpReal (b^.px) ;
   SpReal (b^.py) ;
   SpReal (b^.vx) ;
   SpReal (b^.vy) ;
   SpReal (b^.ang) ;
   SpReal (b^.om) ;
   Ln
END EmitState ;


PROCEDURE Collide (t: REAL; feat: INTEGER; A, B: BodyRef; i, j: INTEGER) ;
VAR
   vA, vB: INTEGER ;
   pax, pay, pbx, pby, dx, dy, dist, nx, ny, cx, cy, px, py, th, rad: REAL ;
   uax, uay, ubx, uby, vn, imp, ran, rbn, k, e, sep, m1, mn, me: REAL ;
BEGIN
   Advance (A, t) ;
   Advance (B, t) ;
   IF i >= 0 THEN vA := A^.v0 + i ELSE vA := -1 END ;
   IF feat = FeatCC THEN
      PointAt (A, -1, t, pax, pay) ;
      IF j >= 0 THEN vB := B^.v0 + j ELSE vB := -1 END ;
      PointAt (B, vB, t, pbx, pby) ;
      dx := pbx - pax ;
      dy := pby - pay ;
      dist := sqrt (dx * dx + dy * dy) ;
      IF dist > 0.0 THEN
         nx := dx / dist ;
         ny := dy / dist
      ELSE
         nx := 1.0 ;
         ny := 0.0
      END ;
      cx := pax + A^.r * nx ;
      cy := pay + A^.r * ny
   ELSE
      PointAt (A, vA, t, px, py) ;
      th := B^.ang + Verts^[B^.v0 + j].psi ;
      (* from A to B: against the edge's outward normal *)
      nx := -cos (th) ;
      ny := -sin (th) ;
      IF vA < 0 THEN rad := A^.r ELSE rad := 0.0 END ;
      cx := px + rad * nx ;
      cy := py + rad * ny
   END ;
   (* velocities of the material points at the contact *)
   uax := A^.vx - A^.om * (cy - A^.py) ;
   uay := A^.vy + A^.om * (cx - A^.px) ;
   ubx := B^.vx - B^.om * (cy - B^.py) ;
   uby := B^.vy + B^.om * (cx - B^.px) ;
   vn := (ubx - uax) * nx + (uby - uay) * ny ;
   imp := 0.0 ;
   IF vn < 0.0 THEN
      ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
      rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
      k := A^.invM + B^.invM + A^.invI * ran * ran + B^.invI * rbn * rbn ;
      e := A^.e * B^.e ;
      (* sep = max(e * -vn, min(-vn, rest_speed)) as Python's min and max pick *)
      m1 := -vn ;
      IF RestSpeed < m1 THEN mn := RestSpeed ELSE mn := m1 END ;
      me := e * (-vn) ;
      IF mn > me THEN sep := mn ELSE sep := me END ;
      imp := (sep - vn) / k ;
      A^.vx := A^.vx - imp * A^.invM * nx ;
      A^.vy := A^.vy - imp * A^.invM * ny ;
      A^.om := A^.om - imp * A^.invI * ran ;
      B^.vx := B^.vx + imp * B^.invM * nx ;
      B^.vy := B^.vy + imp * B^.invM * ny ;
      B^.om := B^.om + imp * B^.invI * rbn
   END ;
   Str ("E collision ") ;
   Real (t) ;
   Str (" ") ; Int (A^.idx) ;
   Str (" ") ; Int (B^.idx) ;
   Str (" ") ; Int (feat) ;
   Str (" ") ; Int (i) ;
   Str (" ") ; Int (j) ;
   SpReal (cx) ;
   SpReal (cy) ;
   SpReal (nx) ;
   SpReal (ny) ;
   SpReal (imp) ;
   Ln ;
   IF NOT A^.fixed THEN
      INC (A^.stamp) ;
      EmitState (A)
   END ;
   IF NOT B^.fixed THEN
      INC (B^.stamp) ;
      EmitState (B)
   END ;
   IF NOT A^.fixed THEN
      PredictBody (A, t, -1)
   END ;
   IF NOT B^.fixed THEN
      IF NOT A^.fixed THEN
         PredictBody (B, t, A^.idx)
      ELSE
         PredictBody (B, t, -1)
      END
   END
END Collide ;


PROCEDURE Stat (name: ARRAY OF CHAR; count: LONGINT) ;
BEGIN
   Str ("N ") ;
   Str (name) ;
   Str (" ") ;
   Int (count) ;
   Ln
END Stat ;


PROCEDURE Run ;
VAR
   i, k, col, row: INTEGER ;
   b: BodyRef ;
   ev: Event ;
   lastT, nxt: REAL ;
   same: LONGINT ;
   stale: BOOLEAN ;
BEGIN
   Cells := Grow (NIL, GridNX * GridNY, SIZE (CellRec)) ;
   FOR k := 0 TO GridNX * GridNY - 1 DO
      Cells^[k].n := 0 ;
      Cells^[k].cap := 0 ;
      Cells^[k].items := NIL
   END ;
   Large := Grow (NIL, NBodies, SIZE (INTEGER)) ;
   NLarge := 0 ;
   FOR i := 0 TO NBodies - 1 DO
      IF Bodies^[i].large THEN
         Large^[NLarge] := i ;
         INC (NLarge)
      END
   END ;
   Seq := 0 ;
   FOR k := 0 TO NStats - 1 DO Stats[k] := 0 END ;
   FOR k := 0 TO CcVariants - 1 DO CcCounts[k] := 0 END ;
   FOR k := 0 TO PeVariants - 1 DO PeCounts[k] := 0 END ;

   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF NOT b^.large THEN
         CellOf (b^.px, b^.py, b^.cx, b^.cy) ;
         CellAdd (b)
      END
   END ;
   FOR k := 0 TO NInputs - 1 DO
      Schedule (Inputs^[k].t, KInput, Inputs^[k].body, -1, -1, k, Inputs^[k].mode)
   END ;
   IF (FrameDt > 0.0) AND (FrameDt <= EndT) THEN
      Schedule (FrameDt, KFrame, -1, -1, -1, 1, -1)
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      IF NOT b^.large THEN
         PredictCells (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, b^.idx, -1, 0.0) ;
         PredictLarge (b, -1, 0.0) ;
         ScheduleCell (b, 0.0)
      END
   END ;

   lastT := -1.0 ;
   same := 0 ;
   WHILE Pop (ev) AND (ev.t <= EndT) DO
      stale := FALSE ;
      (* an input is scripted, not predicted: it happens whatever the body did before *)
      IF ev.kind # KInput THEN
         IF (ev.a >= 0) AND (Bodies^[ev.a].stamp # ev.sa) THEN stale := TRUE END ;
         IF (ev.b >= 0) AND (Bodies^[ev.b].stamp # ev.sb) THEN stale := TRUE END
      END ;
      IF stale THEN
         INC (Stats[StStale]) ;
         ev.kind := -1
      ELSIF ev.t = lastT THEN
         INC (same) ;
         IF same > MaxSame THEN
            Str ("X more than ") ;
            Int (MaxSame) ;
            Str (" events at t = ") ;
            Real (ev.t) ;
            Str (": the scene is stuck") ;
            Ln ;
            Fail
         END
      ELSE
         lastT := ev.t ;
         same := 0
      END ;
      IF ev.kind = -1 THEN
         (* stale: dropped *)
      ELSIF ev.kind = KCollision THEN
         INC (Stats[StCollisions]) ;
         Collide (ev.t, ev.feat, ADR (Bodies^[ev.a]), ADR (Bodies^[ev.b]), ev.i, ev.j)
      ELSIF ev.kind = KInput THEN
         INC (Stats[StInputs]) ;
         b := ADR (Bodies^[ev.a]) ;
         Advance (b, ev.t) ;
         IF Inputs^[ev.i].mode = 0 THEN
            b^.vx := Inputs^[ev.i].vx ;
            b^.vy := Inputs^[ev.i].vy
         ELSE
            b^.vx := b^.vx + Inputs^[ev.i].vx ;
            b^.vy := b^.vy + Inputs^[ev.i].vy
         END ;
         INC (b^.stamp) ;
         Str ("E input ") ;
         Real (ev.t) ;
         Str (" ") ;
         Int (ev.a) ;
         Str (" -1 -1 ") ;
         Int (ev.i) ;
         Str (" -1 0 0 0 0 0") ;
         Ln ;
         EmitState (b) ;
         PredictBody (b, ev.t, -1)
      ELSIF ev.kind = KCell THEN
         INC (Stats[StCells]) ;
         b := ADR (Bodies^[ev.a]) ;
         CellRemove (b) ;
         IF ev.i = 0 THEN
            b^.cx := b^.cx + ev.j ;
            col := b^.cx + ev.j ;
            CellAdd (b) ;
            PredictCells (b, col, col, b^.cy - 1, b^.cy + 1, -1, -1, ev.t)
         ELSE
            b^.cy := b^.cy + ev.j ;
            row := b^.cy + ev.j ;
            CellAdd (b) ;
            PredictCells (b, b^.cx - 1, b^.cx + 1, row, row, -1, -1, ev.t)
         END ;
         ScheduleCell (b, ev.t)
      ELSIF ev.kind = KHorizon THEN
         INC (Stats[StHorizons]) ;
         PredictPair (ADR (Bodies^[ev.a]), ADR (Bodies^[ev.b]), ev.t)
      ELSIF ev.kind = KFrame THEN
         INC (Stats[StFrames]) ;
         Str ("E frame ") ;
         Real (ev.t) ;
         Str (" -1 -1 -1 -1 -1 0 0 0 0 0") ;
         Ln ;
         nxt := VAL (REAL, ev.i + 1) * FrameDt ;
         IF nxt <= EndT THEN
            Schedule (nxt, KFrame, -1, -1, -1, ev.i + 1, -1)
         END
      END
   END ;

   FOR i := 0 TO NBodies - 1 DO
      Advance (ADR (Bodies^[i]), EndT)
   END ;
   FOR i := 0 TO NBodies - 1 DO
      b := ADR (Bodies^[i]) ;
      Str ("F ") ;
      Int (i) ;
      SpReal (b^.px) ;
      SpReal (b^.py) ;
      SpReal (b^.vx) ;
      SpReal (b^.vy) ;
      SpReal (b^.ang) ;
      SpReal (b^.om) ;
      Ln
   END ;
   Stat ("collisions", Stats[StCollisions]) ;
   Stat ("inputs", Stats[StInputs]) ;
   Stat ("frames", Stats[StFrames]) ;
   Stat ("cells", Stats[StCells]) ;
   Stat ("horizons", Stats[StHorizons]) ;
   Stat ("stale", Stats[StStale]) ;
   Stat ("pairs", Stats[StPairs]) ;
   Stat ("features", Stats[StFeatures]) ;
   FOR k := 0 TO CcVariants - 1 DO
      Str ("V circle_circle ") ;
      Int (k) ;
      Str (" ") ;
      Int (CcCounts[k]) ;
      Ln
   END ;
   FOR k := 0 TO PeVariants - 1 DO
      Str ("V point_edge ") ;
      Int (k) ;
      Str (" ") ;
      Int (PeCounts[k]) ;
      Ln
   END ;
   Flush
END Run ;


BEGIN
   Pending := -2 ;
   ReadScene ;
   Run
END SimMain.
