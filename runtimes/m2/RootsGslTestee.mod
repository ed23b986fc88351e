MODULE RootsGslTestee ;

(* Conformance testee of the Modula-2 GSL baseline (wire format: Wire.def). *)

FROM Wire IMPORT Serve ;

BEGIN
   Serve (TRUE)
END RootsGslTestee.
