MODULE RootsTestee ;

(* Conformance testee of the Modula-2 runtime (wire format: Wire.def). *)

FROM Wire IMPORT Serve ;

BEGIN
   Serve (FALSE)
END RootsTestee.
