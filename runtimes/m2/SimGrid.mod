IMPLEMENTATION MODULE SimGrid ;

(* The broad phase: cells, walls and the large list (SimGrid.def). *)

FROM SimC IMPORT floor, free ;
FROM SimScene IMPORT Bodies, BodyRef, CellH, CellW, GridNX, GridNY, GridX0, GridY0, Grow, NBodies ;
FROM SimMotion IMPORT PointAt ;


VAR
   NCells: INTEGER ;           (* the cells InitGrid made *)
   CapLarge: INTEGER ;         (* Large's room *)
   CapNear: INTEGER ;          (* Near's room *)


PROCEDURE InitGrid ;
VAR
   k: INTEGER ;
BEGIN
   IF Cells # NIL THEN
      FOR k := 0 TO NCells - 1 DO
         free (Cells^[k].items) ;
         free (Walls^[k].items)
      END ;
      free (Cells) ;
      free (Walls) ;
      free (Large)
   END ;
   NCells := GridNX * GridNY ;
   Cells := Grow (NIL, NCells, SIZE (CellRec)) ;
   Walls := Grow (NIL, NCells, SIZE (CellRec)) ;
   FOR k := 0 TO GridNX * GridNY - 1 DO
      Cells^[k].n := 0 ;
      Cells^[k].cap := 0 ;
      Cells^[k].items := NIL ;
      Walls^[k].n := 0 ;
      Walls^[k].cap := 0 ;
      Walls^[k].items := NIL
   END ;
   CapLarge := NBodies + 1 ;
   Large := Grow (NIL, CapLarge, SIZE (INTEGER)) ;
   NLarge := 0
END InitGrid ;


PROCEDURE WallAdd (c, i: INTEGER) ;
BEGIN
   IF Walls^[c].n = Walls^[c].cap THEN
      IF Walls^[c].cap = 0 THEN Walls^[c].cap := 4 ELSE Walls^[c].cap := 2 * Walls^[c].cap END ;
      Walls^[c].items := Grow (Walls^[c].items, Walls^[c].cap, SIZE (INTEGER))
   END ;
   Walls^[c].items^[Walls^[c].n] := i ;
   INC (Walls^[c].n)
END WallAdd ;


PROCEDURE WallRemove (c, i: INTEGER) ;
VAR
   k: INTEGER ;
BEGIN
   k := 0 ;
   WHILE (k < Walls^[c].n) AND (Walls^[c].items^[k] # i) DO INC (k) END ;
   IF k = Walls^[c].n THEN RETURN END ;
   DEC (Walls^[c].n) ;
   WHILE k < Walls^[c].n DO
      Walls^[c].items^[k] := Walls^[c].items^[k + 1] ;
      INC (k)
   END
END WallRemove ;


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


PROCEDURE LargeAdd (i: INTEGER) ;
BEGIN
   IF NLarge = CapLarge THEN
      CapLarge := 2 * CapLarge ;
      Large := Grow (Large, CapLarge, SIZE (INTEGER))
   END ;
   Large^[NLarge] := i ;
   INC (NLarge)
END LargeAdd ;


PROCEDURE LargeRemove (i: INTEGER) ;
VAR
   k: INTEGER ;
BEGIN
   k := 0 ;
   WHILE (k < NLarge) AND (Large^[k] # i) DO INC (k) END ;
   IF k = NLarge THEN RETURN END ;
   DEC (NLarge) ;
   WHILE k < NLarge DO
      Large^[k] := Large^[k + 1] ;
      INC (k)
   END
END LargeRemove ;


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


(* A large body into the grid's walls when it is fixed and does not move
   (v = a = 0): its box (a polygon that does not turn: its vertices at its
   time; else its centre +- bound) in cells, every cell from CellOf (the
   box's low corner) to CellOf (its high corner), each cell's list in the
   order bodies are placed; else into the large list. *)
PROCEDURE place_large (b: BodyRef) ;
VAR
   x0, y0, x1, y1, x, y: REAL ;
   k, i0, j0, i1, j1, jx, jy: INTEGER ;
BEGIN
   IF NOT (b^.fixed AND (b^.vx = 0.0) AND (b^.vy = 0.0) AND (b^.ax = 0.0) AND (b^.ay = 0.0)) THEN
      LargeAdd (b^.idx) ;
      RETURN
   END ;
   IF b^.polygon AND (b^.om = 0.0) THEN
      PointAt (b, b^.v0, b^.tb, x0, y0) ;
      x1 := x0 ;
      y1 := y0 ;
      FOR k := 0 TO b^.nv - 1 DO
         PointAt (b, b^.v0 + k, b^.tb, x, y) ;
         (* Python's min and max: the first unless the second is beyond it *)
         IF x < x0 THEN x0 := x END ;
         IF x > x1 THEN x1 := x END ;
         IF y < y0 THEN y0 := y END ;
         IF y > y1 THEN y1 := y END
      END
   ELSE
      x0 := b^.px - b^.bound ;
      x1 := b^.px + b^.bound ;
      y0 := b^.py - b^.bound ;
      y1 := b^.py + b^.bound
   END ;
   CellOf (x0, y0, i0, j0) ;
   CellOf (x1, y1, i1, j1) ;
   b^.placed := TRUE ;
   b^.wi0 := i0 ;
   b^.wi1 := i1 ;
   b^.wj0 := j0 ;
   b^.wj1 := j1 ;
   FOR jy := j0 TO j1 DO
      FOR jx := i0 TO i1 DO
         WallAdd (jy * GridNX + jx, b^.idx)
      END
   END
END place_large ;


(* A large body out of the walls of its cells, or out of the large list. *)
PROCEDURE unplace_large (b: BodyRef) ;
VAR
   jx, jy: INTEGER ;
BEGIN
   IF NOT b^.placed THEN
      LargeRemove (b^.idx) ;
      RETURN
   END ;
   FOR jy := b^.wj0 TO b^.wj1 DO
      FOR jx := b^.wi0 TO b^.wi1 DO
         WallRemove (jy * GridNX + jx, b^.idx)
      END
   END
END unplace_large ;


(* Appends body i to Near^[n], n + 1. *)
PROCEDURE NearAdd (VAR n: INTEGER; i: INTEGER) ;
BEGIN
   IF n >= CapNear THEN
      IF CapNear = 0 THEN CapNear := 16 ELSE CapNear := 2 * CapNear END ;
      Near := Grow (Near, CapNear, SIZE (INTEGER))
   END ;
   Near^[n] := i ;
   INC (n)
END NearAdd ;


(* The placed large bodies listed in the cells xlo..xhi, ylo..yhi (clamped
   to the grid, rows then columns), but b and those already carrying the
   current mark, are marked and (keep) appended to Near^[n..]. *)
PROCEDURE walls_in (b: BodyRef; xlo, xhi, ylo, yhi: INTEGER; keep: BOOLEAN; VAR n: INTEGER) ;
VAR
   jx, jy, c, k, oi: INTEGER ;
BEGIN
   FOR jy := Max (ylo, 0) TO Min (yhi, GridNY - 1) DO
      FOR jx := Max (xlo, 0) TO Min (xhi, GridNX - 1) DO
         c := jy * GridNX + jx ;
         FOR k := 0 TO Walls^[c].n - 1 DO
            oi := Walls^[c].items^[k] ;
            IF (Bodies^[oi].seen # Mark) AND (oi # b^.idx) THEN
               Bodies^[oi].seen := Mark ;
               IF keep THEN NearAdd (n, oi) END
            END
         END
      END
   END
END walls_in ;


(* Near^[0 .. n - 1] in index order (the indices differ). *)
PROCEDURE SortNear (n: INTEGER) ;
VAR
   i, k, v: INTEGER ;
BEGIN
   FOR i := 1 TO n - 1 DO
      v := Near^[i] ;
      k := i ;
      WHILE (k > 0) AND (Near^[k - 1] > v) DO
         Near^[k] := Near^[k - 1] ;
         DEC (k)
      END ;
      Near^[k] := v
   END
END SortNear ;


(* The large bodies b predicts against, in Near^[0 .. n - 1]: those placed
   in its 3x3 cells and every one in the large list, each once, but b, in
   index order. *)
PROCEDURE large_near (b: BodyRef; VAR n: INTEGER) ;
VAR
   k: INTEGER ;
BEGIN
   INC (Mark) ;
   n := 0 ;
   walls_in (b, b^.cx - 1, b^.cx + 1, b^.cy - 1, b^.cy + 1, TRUE, n) ;
   FOR k := 0 TO NLarge - 1 DO
      IF Large^[k] # b^.idx THEN NearAdd (n, Large^[k]) END
   END ;
   SortNear (n)
END large_near ;


BEGIN
   CapLarge := 0 ;
   NCells := 0 ;
   Cells := NIL ;
   Walls := NIL ;
   Large := NIL ;
   NLarge := 0 ;
   Near := NIL ;
   CapNear := 0 ;
   Mark := 0
END SimGrid.
