"""C (C11, <math.h>)."""
import re
from importlib import resources

from max2code.targets.base import Target, c_string, code_point, visible


def _library_names() -> frozenset:
    """The names of c_library.txt (beside this module)."""
    text = resources.files("max2code.targets").joinpath("c_library.txt").read_text(encoding="utf-8")
    return frozenset(w for line in text.splitlines() if not line.startswith("#") for w in line.split())


class C(Target):
    name = "c"
    extension = ".c"
    comment = ("/* ", " */")
    line_directive = '#line {line} "{file}"'
    header_extension = ".h"          # eq.h: every entry's prototype and the degree constants
    gsl_baseline = "gsl"
    requires = "a C11 compiler; GSL (the library's baseline solver)"
    links = "compile eq.c, include eq.h; link libm2c (static or shared) through `pkg-config m2c`"

    words = (
        ("a keyword of C (C11 to C23; C++'s too: the header is for C++ as well)", frozenset("""
            auto break case char const continue default do double else enum extern float for goto if inline int
            long register restrict return short signed sizeof static struct switch typedef union unsigned void
            volatile while _Alignas _Alignof _Atomic _Bool _Complex _Generic _Imaginary _Noreturn _Static_assert
            _Thread_local alignas alignof bool constexpr false nullptr static_assert thread_local true typeof
            typeof_unqual
            and and_eq asm bitand bitor catch char8_t char16_t char32_t class co_await co_return co_yield compl
            concept const_cast consteval constinit decltype delete dynamic_cast explicit export friend mutable
            namespace new noexcept not not_eq operator or or_eq private protected public reinterpret_cast requires
            static_cast template this throw try typeid typename using virtual wchar_t xor xor_eq""".split())),
        ("a name of the C library the generated C sees (<math.h>, <float.h>, <stdint.h>, <string.h>)",
         _library_names()),
        ("a macro GCC predefines (gnu modes)", frozenset({"linux", "unix"})),
        ("a name the generated C uses", frozenset("""
            main errno coef degree mask by_mask lo hi t horizon options out rate pv scale md mo nparams""".split())),
    )
    reserved_prefixes = ("m2c_", "M2C_", "__")

    single_type = "float"
    single_calls = {"sin": "sinf({})", "cos": "cosf({})", "sqrt": "sqrtf({})", "abs": "fabsf({})"}
    single_suffix = "f"

    def escape(self, text: str, where: str) -> str:
        """C's comments (and docs, which are comments) cannot hold a line end
        or '*/' (nor '/*': gcc -Wall warns of it); #line's file name is a
        string literal."""
        if where == "string":
            return c_string(text)
        return re.sub(r"(?<=\*)(?=/)|(?<=/)(?=\*)", " ", visible(text, code_point))


