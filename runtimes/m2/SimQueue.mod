IMPLEMENTATION MODULE SimQueue ;

(* The event queue: a binary heap in a growing array, children of k at
   2k+1 and 2k+2. *)

FROM SYSTEM IMPORT ADDRESS ;
FROM SimC IMPORT realloc ;

CONST
   MaxEvents = 134217728 ;     (* bound of the array type only; storage grows *)

TYPE
   EventArray = ARRAY [0..MaxEvents - 1] OF Event ;
   EventPtr = POINTER TO EventArray ;

VAR
   heap: EventPtr ;
   n, cap: INTEGER ;


(* Whether x leaves the queue before y: (t, kind, seq) compared as Python
   compares tuples. *)
PROCEDURE Before (x, y: Event) : BOOLEAN ;
BEGIN
   IF x.t # y.t
   THEN
      RETURN x.t < y.t
   ELSIF x.kind # y.kind
   THEN
      RETURN x.kind < y.kind
   ELSE
      RETURN x.seq < y.seq
   END
END Before ;


PROCEDURE Grow () : BOOLEAN ;
VAR
   p: ADDRESS ;
   c: INTEGER ;
BEGIN
   IF cap >= MaxEvents THEN RETURN FALSE END ;
   IF cap = 0 THEN c := 1024 ELSE c := cap * 2 END ;
   IF c > MaxEvents THEN c := MaxEvents END ;
   p := realloc (heap, VAL (LONGCARD, c) * VAL (LONGCARD, SIZE (Event))) ;
   IF p = NIL THEN RETURN FALSE END ;
   heap := p ;
   cap := c ;
   RETURN TRUE
END Grow ;


PROCEDURE Push (VAR e: Event) : BOOLEAN ;
VAR
   k, parent: INTEGER ;
BEGIN
   IF (n = cap) AND (NOT Grow ()) THEN RETURN FALSE END ;
   k := n ;
   INC (n) ;
   WHILE k > 0 DO
      parent := (k - 1) DIV 2 ;
      IF NOT Before (e, heap^[parent]) THEN
         heap^[k] := e ;
         RETURN TRUE
      END ;
      heap^[k] := heap^[parent] ;
      k := parent
   END ;
   heap^[0] := e ;
   RETURN TRUE
END Push ;


PROCEDURE Pop (VAR e: Event) : BOOLEAN ;
VAR
   k, child: INTEGER ;
   last: Event ;
BEGIN
   IF n = 0 THEN RETURN FALSE END ;
   e := heap^[0] ;
   DEC (n) ;
   IF n > 0 THEN
      last := heap^[n] ;
      k := 0 ;
      LOOP
         child := 2 * k + 1 ;
         IF child >= n THEN EXIT END ;
         IF (child + 1 < n) AND Before (heap^[child + 1], heap^[child]) THEN
            INC (child)
         END ;
         IF NOT Before (heap^[child], last) THEN EXIT END ;
         heap^[k] := heap^[child] ;
         k := child
      END ;
      heap^[k] := last
   END ;
   RETURN TRUE
END Pop ;


PROCEDURE Top (VAR e: Event) : BOOLEAN ;
BEGIN
   IF n = 0 THEN RETURN FALSE END ;
   e := heap^[0] ;
   RETURN TRUE
END Top ;


PROCEDURE Clear ;
BEGIN
   n := 0
END Clear ;


BEGIN
   heap := NIL ;
   n := 0 ;
   cap := 0
END SimQueue.
