IMPLEMENTATION MODULE SimOverlap ;

(* Overlap: the Python reference's overlapping, separation, edge_line,
   edges_separation and circle_separation, operation for operation. *)

FROM SYSTEM IMPORT ADR ;
FROM RealMath IMPORT cos, sin ;
FROM CMath IMPORT sqrt ;
FROM SimScene IMPORT Bodies, BodyRef, MAX_VERTICES, NBodies, Tol, Verts ;
FROM SimWorld IMPORT Inf ;
FROM SimMotion IMPORT PointAt, StateAt ;

VAR
   (* separation's vertices of its two polygons *)
   SepAX, SepAY, SepBX, SepBY: ARRAY [0..MAX_VERTICES - 1] OF REAL ;


(* The first body (by index) that A, with its centre moved to (x, y) at time
   t, would overlap by more than the tolerance; -1 when none. *)
PROCEDURE overlapping (A: BodyRef; x, y, t: REAL) : INTEGER ;
VAR
   spx, spy, svx, svy, sang, stb: REAL ;
   ax, ay, vx, vy, ang, bx, by, bvx, bvy, bang, dx, dy, reach: REAL ;
   k, found: INTEGER ;
   B: BodyRef ;
BEGIN
   spx := A^.px ; spy := A^.py ; svx := A^.vx ; svy := A^.vy ; sang := A^.ang ; stb := A^.tb ;
   StateAt (A, t, ax, ay, vx, vy, ang) ;
   (* A at t, moved (restored below) *)
   A^.px := x ; A^.py := y ; A^.vx := vx ; A^.vy := vy ; A^.ang := ang ; A^.tb := t ;
   found := -1 ;
   k := 0 ;
   WHILE (found < 0) AND (k < NBodies) DO
      B := ADR (Bodies^[k]) ;
      IF (B # A) AND NOT B^.gone THEN
         StateAt (B, t, bx, by, bvx, bvy, bang) ;
         dx := bx - x ;
         dy := by - y ;
         reach := A^.bound + B^.bound + Tol ;
         IF (NOT (dx * dx + dy * dy > reach * reach)) AND (separation (A, B, t) < -Tol) THEN
            found := B^.idx
         END
      END ;
      INC (k)
   END ;
   A^.px := spx ; A^.py := spy ; A^.vx := svx ; A^.vy := svy ; A^.ang := sang ; A^.tb := stb ;
   RETURN found
END overlapping ;


(* The largest gap between A and B at t along a separating axis: negative
   by the depth they overlap (edge normals of either polygon, and for a
   circle the line from the nearest vertex; circles: the distance of the
   centres less the radii). *)
PROCEDURE separation (A, B: BodyRef; t: REAL) : REAL ;
VAR
   ax, ay, bx, by: REAL ;
BEGIN
   IF (NOT A^.polygon) AND (NOT B^.polygon) THEN
      PointAt (A, -1, t, ax, ay) ;
      PointAt (B, -1, t, bx, by) ;
      RETURN sqrt ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A^.r + B^.r)
   END ;
   IF NOT A^.polygon THEN RETURN circle_separation (A, B, t) END ;
   IF NOT B^.polygon THEN RETURN circle_separation (B, A, t) END ;
   VertexPoints (A, t, SepAX, SepAY) ;
   VertexPoints (B, t, SepBX, SepBY) ;
   RETURN polygons_separation (A, B, t, SepAX, SepAY, SepBX, SepBY)
END separation ;


(* separation of two polygons whose vertices at t are (pax[k], pay[k]) and
   (pbx[k], pby[k]). *)
PROCEDURE polygons_separation (A, B: BodyRef; t: REAL; VAR pax, pay, pbx, pby: ARRAY OF REAL) : REAL ;
VAR
   s1, s2: REAL ;
BEGIN
   s1 := edges_separation (A, t, pbx, pby, B^.nv) ;
   s2 := edges_separation (B, t, pax, pay, A^.nv) ;
   IF s2 > s1 THEN RETURN s2 END ;     (* Python's max: the first unless the second is larger *)
   RETURN s1
END polygons_separation ;


(* The vertices (xs[k], ys[k]) (m) of polygon b at t. *)
PROCEDURE VertexPoints (b: BodyRef; t: REAL; VAR xs, ys: ARRAY OF REAL) ;
VAR
   k: INTEGER ;
BEGIN
   FOR k := 0 TO b^.nv - 1 DO
      PointAt (b, b^.v0 + k, t, xs[k], ys[k])
   END
END VertexPoints ;


(* Outward unit normal (ox, oy) of edge j of P at t and the offset of its
   line, (ox, oy) . point = off. *)
PROCEDURE edge_line (P: BodyRef; j: INTEGER; t: REAL; VAR ox, oy, off: REAL) ;
VAR
   px, py, vx, vy, ang, c, s, enx, eny: REAL ;
BEGIN
   enx := Verts^[P^.v0 + j].nx ;
   eny := Verts^[P^.v0 + j].ny ;
   StateAt (P, t, px, py, vx, vy, ang) ;
   c := cos (ang) ;
   s := sin (ang) ;
   ox := c * enx - s * eny ;
   oy := s * enx + c * eny ;
   off := ox * px + oy * py + Verts^[P^.v0 + j].h
END edge_line ;


(* Along the edge normals of P: the largest over P's edges of the smallest
   distance of the nq vertices (qx[k], qy[k]) at t of the other polygon
   beyond the edge's line.  P's lines are edge_line's, with the cos and sin
   of P's angle taken once. *)
PROCEDURE edges_separation (P: BodyRef; t: REAL; VAR qx, qy: ARRAY OF REAL; nq: INTEGER) : REAL ;
VAR
   best, lo, d, ox, oy, off, px, py, vx, vy, ang, c, s: REAL ;
   j, v, e: INTEGER ;
BEGIN
   StateAt (P, t, px, py, vx, vy, ang) ;
   c := cos (ang) ;
   s := sin (ang) ;
   best := -Inf ;
   FOR j := 0 TO P^.nv - 1 DO
      e := P^.v0 + j ;
      ox := c * Verts^[e].nx - s * Verts^[e].ny ;
      oy := s * Verts^[e].nx + c * Verts^[e].ny ;
      off := ox * px + oy * py + Verts^[e].h ;
      lo := Inf ;
      FOR v := 0 TO nq - 1 DO
         d := ox * qx[v] + oy * qy[v] - off ;
         IF d < lo THEN lo := d END
      END ;
      IF lo > best THEN best := lo END
   END ;
   RETURN best
END edges_separation ;


(* Circle C against polygon P: along P's edge normals and the line from
   P's nearest vertex to C's centre. *)
PROCEDURE circle_separation (C, P: BodyRef; t: REAL) : REAL ;
VAR
   cx, cy, best, ox, oy, off, g, qx, qy, e2, d2, d, ux, uy, hi, nqx, nqy: REAL ;
   j, k: INTEGER ;
BEGIN
   PointAt (C, -1, t, cx, cy) ;
   best := -Inf ;
   FOR j := 0 TO P^.nv - 1 DO
      edge_line (P, j, t, ox, oy, off) ;
      g := ox * cx + oy * cy - off - C^.r ;
      IF g > best THEN best := g END
   END ;
   d2 := Inf ;
   PointAt (P, P^.v0, t, nqx, nqy) ;    (* vertex 0 unless a nearer one is found *)
   FOR k := 0 TO P^.nv - 1 DO
      PointAt (P, P^.v0 + k, t, qx, qy) ;
      e2 := (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy) ;
      IF e2 < d2 THEN
         d2 := e2 ;
         nqx := qx ;
         nqy := qy
      END
   END ;
   IF d2 > 0.0 THEN
      d := sqrt (d2) ;
      ux := (cx - nqx) / d ;
      uy := (cy - nqy) / d ;
      hi := -Inf ;
      FOR k := 0 TO P^.nv - 1 DO
         PointAt (P, P^.v0 + k, t, qx, qy) ;
         g := ux * qx + uy * qy ;
         IF g > hi THEN hi := g END
      END ;
      g := ux * cx + uy * cy - C^.r - hi ;
      IF g > best THEN best := g END
   END ;
   RETURN best
END circle_separation ;


END SimOverlap.
