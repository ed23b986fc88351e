MODULE SimMain ;

(* The batch simulator (docs/simulator.md): reads a compiled scene on
   standard input and writes the flat trace on standard output; a thin
   user of the live world SimWorld.  On a stuck or bad scene it writes
   "X message" and ends with status 1. *)

FROM SimWorld IMPORT FromStdin, Run, Error ;
FROM SimOut IMPORT SetOn, Str, Ln, Fail ;

VAR
   msg: ARRAY [0..511] OF CHAR ;
BEGIN
   IF NOT (FromStdin (TRUE) AND Run ()) THEN
      Error (msg) ;
      SetOn (TRUE) ;
      Str ("X ") ;
      Str (msg) ;
      Ln ;
      Fail
   END
END SimMain.
