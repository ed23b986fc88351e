"""C (C11, <math.h>)."""
import re
from importlib import resources

from max2code.paths import TEMPLATES
from max2code.targets.base import Target, c_string, code_point, visible


def _library_names() -> dict[str, frozenset]:
    """The names of c_library.txt (beside this module), by kind: macros, functions, types."""
    text = resources.files("max2code.targets").joinpath("c_library.txt").read_text(encoding="utf-8")
    groups: dict[str, set] = {}
    kind = None
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        if line.startswith("["):
            kind = line.strip()[1:-1]
            groups[kind] = set()
        else:
            groups[kind].update(line.split())
    return {k: frozenset(v) for k, v in groups.items()}


LIBRARY = _library_names()
CALLS = {"sin": "sin({})", "cos": "cos({})", "sqrt": "sqrt({})", "abs": "fabs({})"}
SINGLE_CALLS = {"sin": "sinf({})", "cos": "cosf({})", "sqrt": "sqrtf({})", "abs": "fabsf({})"}
C_STATEMENTS = frozenset({"if", "for", "while", "switch", "return", "sizeof"})


def _file_templates() -> list[str]:
    """The templates of the generated C (file.j2, header.j2, fragment.j2 and
    what they include), as text."""
    todo, seen, texts = ["c/file.j2", "c/header.j2", "c/fragment.j2"], set(), []
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        text = (TEMPLATES / name).read_text(encoding="utf-8")
        texts.append(text)
        todo += re.findall(r"\{%-?\s*include\s+\"([^\"]+)\"", text)
    return texts


def _called() -> frozenset:
    """The functions the generated C calls: the printer's (double and float)
    and those the templates of the generated file call."""
    names = {re.match(r"\w+", f).group(0) for f in (*CALLS.values(), *SINGLE_CALLS.values())}
    for text in _file_templates():
        text = re.sub(r"\{\{.*?\}\}|\{%.*?%\}|\{#.*?#\}", " @ ", text, flags=re.S)     # Jinja's own text
        names.update(re.findall(r"\b([A-Za-z_]\w*)\s*\(", text))
    return frozenset(names - C_STATEMENTS)


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
        ("a macro of the C library the generated C sees (<math.h>, <float.h>, <stdint.h>, <string.h>, and "
         "<stdio.h>, <stdlib.h>, <time.h> of the harness programs)", LIBRARY["macros"]),
        ("a type of the C library the generated C sees", LIBRARY["types"]),
        ("a function the generated C calls", _called()),
        ("a macro GCC predefines (gnu modes)", frozenset({"linux", "unix"})),
        ("a name the generated C uses", frozenset("""
            main errno coef degree mask by_mask lo hi t horizon options out rate pv scale md mo nparams""".split())),
    )
    # a parameter may hide a function of the library (C's scopes: an ordinary identifier declared in a
    # block or a parameter list hides one of file scope; gcc -Wshadow does not warn of it); the equation's
    # and the `exact` functions' names are declared at file scope beside the library's
    file_scope_words = (("a function of the C library the generated C sees, declared at file scope as the "
                         "generated functions are", LIBRARY["functions"]),)
    reserved_prefixes = ("m2c_", "M2C_", "__")

    calls = CALLS
    single_type = "float"
    single_calls = SINGLE_CALLS
    single_suffix = "f"

    def escape(self, text: str, where: str) -> str:
        """C's comments (and docs, which are comments) cannot hold a line end
        or '*/' (nor '/*': gcc -Wall warns of it); #line's file name is a
        string literal."""
        if where == "string":
            return c_string(text)
        return re.sub(r"(?<=\*)(?=/)|(?<=/)(?=\*)", " ", visible(text, code_point))


