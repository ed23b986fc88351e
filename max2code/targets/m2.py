"""ISO Modula-2 (gm2 -fiso -fcpp): REAL is a C double; sin/cos from RealMath."""
from max2code.targets.base import Target


class Modula2(Target):
    name = "m2"
    extension = ".mxd"
    comment = ("(* ", " *)")
    line_directive = '#line {line} "{file}"'
    line_offset = 1          # gm2 12 reports a line one less than the #line directive gives
    exponent_letter = "E"    # ISO Modula-2 real literal: 1.0E-5
    gsl_baseline = "gsl-m2"
    requires = "gm2 (GCC 12 or later, `-fiso`)"
    links = "`#include` eq.mxd in your module (`gm2 -fcpp`); link Roots.o and ExactToc.o"
    def zero_test(self, names) -> str:
        # AND binds tighter than = in Modula-2: parenthesise each test
        return " AND ".join(f"({n} = {self.real_literal(0.0)})" for n in names)

    calls = {"sin": "sin({})", "cos": "cos({})", "sqrt": "sqrt({})", "abs": "ABS({})"}
    reserved = frozenset("""
        AND ARRAY BEGIN BY CASE CONST DEFINITION DIV DO ELSE ELSIF END EXIT EXPORT FOR FROM IF IMPLEMENTATION IMPORT
        IN LOOP MOD MODULE NOT OF OR POINTER PROCEDURE QUALIFIED RECORD REPEAT RETURN SET THEN TO TYPE UNTIL VAR
        WHILE WITH EXCEPT FINALLY FORWARD PACKEDSET REM RETRY ABSTRACT AS CLASS GENERIC GUARD INHERIT OVERRIDE
        READONLY REVEAL TRACED UNSAFEGUARDED
        ABS BITSET BOOLEAN CAP CARDINAL CHAR CHR CMPLX COMPLEX DEC DISPOSE EXCL FALSE FLOAT HALT HIGH IM INC INCL
        INT INTEGER LENGTH LFLOAT LONGCOMPLEX LONGREAL MAX MIN NEW NIL ODD ORD PROC PROTECTION RE REAL SIZE TRUE
        TRUNC VAL SHORTREAL LONGINT LONGCARD SHORTINT SHORTCARD
        sin cos sqrt RealMath Roots SmallestRoot ExactToc FirstContact Options Motion Defaults
        coef degree mask lo hi t horizon options out rate pv scale md mo nparams maxDegree gapDt""".split())
    single_type = "SHORTREAL"     # gm2 12 has no ShortMath: sin and cos of REAL, rounded
    single_copies = True          # REAL parameters, SHORTREAL copies (no implicit conversion in Modula-2)
    single_calls = {"sin": "VAL(SHORTREAL, sin(VAL(REAL, {})))", "cos": "VAL(SHORTREAL, cos(VAL(REAL, {})))",
                    "sqrt": "VAL(SHORTREAL, sqrt(VAL(REAL, {})))", "abs": "ABS({})"}
