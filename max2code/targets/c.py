"""C (C11, <math.h>)."""
from max2code.targets.base import Target


class C(Target):
    name = "c"
    extension = ".c"
    comment = ("/* ", " */")
    line_directive = '#line {line} "{file}"'
    header_extension = ".h"          # eq.h: every entry's prototype and the degree constants
    gsl_baseline = "gsl"
    requires = "a C11 compiler; GSL (the library's baseline solver)"
    links = "compile eq.c, include eq.h; link libm2c (static or shared) through `pkg-config m2c`"

    reserved = frozenset("""
        auto break case char const continue default do double else enum extern float for goto if inline int long
        register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
        _Alignas _Alignof _Atomic _Bool _Complex _Generic _Imaginary _Noreturn _Static_assert _Thread_local
        sin cos sqrt fabs sinf cosf sqrtf fabsf main errno NULL
        coef degree mask by_mask lo hi t horizon options out rate pv scale md mo nparams""".split())
    reserved_prefixes = ("m2c_", "M2C_", "__")

    single_type = "float"
    single_calls = {"sin": "sinf({})", "cos": "cosf({})", "sqrt": "sqrtf({})", "abs": "fabsf({})"}
    single_suffix = "f"
