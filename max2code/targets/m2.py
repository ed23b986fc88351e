"""ISO Modula-2 (gm2 -fiso -fcpp): REAL is a C double; sin/cos from RealMath."""
import re

from max2code.targets.base import Target, c_string, code_point, visible


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
    # gm2 12's front end takes time in the square of a module's length: circle-circle's window entry
    # (its 64 variants again) makes the including module compile in about 260 s of CPU instead of 56 s,
    # for about 10 % less time per exact query
    window_entry = False
    def zero_test(self, names) -> str:
        # AND binds tighter than = in Modula-2: parenthesise each test
        return " AND ".join(f"({n} = {self.real_literal(0.0)})" for n in names)

    calls = {"sin": "sin({})", "cos": "cos({})", "sqrt": "sqrt({})", "abs": "ABS({})"}
    words = (
        ("a reserved word of Modula-2 (ISO, with its generic and object-oriented extensions)", frozenset("""
            AND ARRAY BEGIN BY CASE CONST DEFINITION DIV DO ELSE ELSIF END EXIT EXPORT FOR FROM IF IMPLEMENTATION
            IMPORT IN LOOP MOD MODULE NOT OF OR POINTER PROCEDURE QUALIFIED RECORD REPEAT RETURN SET THEN TO TYPE
            UNTIL VAR WHILE WITH EXCEPT FINALLY FORWARD PACKEDSET REM RETRY ABSTRACT AS CLASS GENERIC GUARD INHERIT
            OVERRIDE READONLY REVEAL TRACED UNSAFEGUARDED""".split())),
        ("a pervasive identifier of Modula-2", frozenset("""
            ABS BITSET BOOLEAN CAP CARDINAL CHAR CHR CMPLX COMPLEX DEC DISPOSE EXCL FALSE FLOAT HALT HIGH IM INC INCL
            INT INTEGER LENGTH LFLOAT LONGCOMPLEX LONGREAL MAX MIN NEW NIL ODD ORD PROC PROTECTION RE REAL SIZE TRUE
            TRUNC VAL SHORTREAL LONGINT LONGCARD SHORTINT SHORTCARD SHORTCOMPLEX LOC BYTE WORD ADDRESS
            ADR SYSTEM""".split())),
        ("a name the module that includes the generated Modula-2 imports (RealMath, Roots, ExactToc, ShortMath)",
         frozenset("""sin cos sqrt RealMath Roots SmallestRoot ExactToc FirstContact Options Motion Defaults
                      ShortMath sinf cosf sqrtf""".split())),
        ("a macro of the C preprocessor that gm2 -fcpp runs", frozenset({"linux", "unix"})),
        ("a name the generated Modula-2 uses", frozenset("""
            coef degree mask lo hi t horizon options out rate pv scale md mo nparams maxDegree gapDt""".split())),
    )
    single_type = "SHORTREAL"
    single_copies = True          # REAL parameters, SHORTREAL copies (no implicit conversion in Modula-2)
    # the C library's sinf, cosf, sqrtf (runtimes/m2/ShortMath.def), which C and Rust call too: the
    # same bits in all three (sin and cos of the REAL value, rounded, differ in about one case in 200)
    single_calls = {"sin": "sinf({})", "cos": "cosf({})", "sqrt": "sqrtf({})", "abs": "ABS({})"}

    def escape(self, text: str, where: str) -> str:
        """Modula-2's comments nest and have no escape, so '(*' and '*)' are
        split by a space; gm2 -fcpp runs the C preprocessor first, which would
        take '/*' for a C comment (split too), and reads #line's file name as a
        C string literal."""
        if where == "string":
            return c_string(text)
        return re.sub(r"(?<=\()(?=\*)|(?<=\*)(?=\))|(?<=/)(?=\*)", " ", visible(text, code_point))


