IMPLEMENTATION MODULE SimGrid ;

FROM SimC IMPORT floor, free ;
FROM SimScene IMPORT NBodies, GridX0, GridY0, CellW, CellH, GridNX, GridNY, Grow ;


VAR
   NCells: INTEGER ;           (* the cells InitGrid made *)
   CapLarge: INTEGER ;         (* Large's room *)


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


BEGIN
   CapLarge := 0 ;
   NCells := 0 ;
   Cells := NIL ;
   Walls := NIL ;
   Large := NIL ;
   NLarge := 0
END SimGrid.
