"""C (C11, <math.h>)."""
import os
import re
from importlib import resources

from max2code.targets.base import Target, c_string, code_point, visible

# flags of every C build: warnings are errors, no FMA contraction (the
# simulator performs the same operations as the Python reference)
# the shared library of the world API that the sim build makes beside the program
WORLD_LIBRARY = "libm2c_world.so"
FLAGS = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off"]
# the simulator's builds: link-time optimisation inlines the generated
# NAME_variant / NAME_coefficients (24 double arguments, most on the stack)
# into the simulator's predictions (9 % fewer instructions per event), -O3
# 6 % fewer again (4 % less CPU time, alternating runs); the same operations
# in the same order (no FMA, no reassociation either way)
SIM_FLAGS = [*("-O3" if f == "-O2" else f for f in FLAGS), "-flto=auto"]


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
    world_library = WORLD_LIBRARY
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

    harness_source = "harness.c"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness (warnings are errors)."""
        return [[*FLAGS, *[f"-I{d}" for d in include_dirs], src, "-o", exe, *self.runtime_flags(), "-lm"]]

    def runtime_flags(self) -> list[str]:
        from max2code.harness import runtimes
        lib = runtimes.c_library()
        return [f"-I{runtimes.C_INCLUDE}", str(lib)]

    def testee(self, baseline: bool = False) -> list[str]:
        from max2code.harness import runtimes
        exe = runtimes.BUILD / "c" / "m2c_testee"
        runtimes.make_c(exe)
        return [str(exe)] + (["--gsl"] if baseline else [])

    def install_runtime(self, prefix: str) -> str:
        from max2code.harness import runtimes
        prefix = os.path.abspath(prefix)
        runtimes.run(["make", "-s", "-C", str(runtimes.C_RUNTIME), f"BUILD={runtimes.BUILD / 'c-install'}",
                      f"PREFIX={prefix}", "install"], runtimes.C_RUNTIME)
        return (f"installed libm2c (static and shared), m2c_roots.h, m2c_exact.h and m2c.pc under {prefix}; build with\n"
                f"  export PKG_CONFIG_PATH={prefix}/lib/pkgconfig\n"
                "  cc main.c eq.c $(pkg-config --cflags --libs m2c) -Wl,-rpath,$(pkg-config --variable=libdir m2c)")

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        from max2code.harness import runtimes
        return [[*FLAGS, f"-I{runtimes.C_INCLUDE}", f"-I{workdir}", src, "-o", exe, str(runtimes.c_library()),
                 *runtimes.gsl_libs(), "-lm"]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Compile the generated circle_circle.c and point_edge.c (checked
        against the declarations of m2c_sim_equations.h), then the simulator
        (runtimes/c/src/m2c_sim*.c) with its program, told how many variants
        each NAME_variant counts, and link them with libm2c.a into workdir/sim;
        the same world (m2c_world.h) with libm2c's position-independent
        objects into workdir/libm2c_world.so."""
        from max2code.harness import runtimes
        c = runtimes.C_RUNTIME
        lib = runtimes.c_library()
        inc = c / "include"
        cmds, objs = [], []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".o")
            # the generated coef[N] has this build's largest degree as its
            # bound, which the header cannot know (the bound is no part of the type)
            cmds.append([*SIM_FLAGS, "-Wno-array-parameter", f"-I{inc}", "-include", str(inc / "m2c_sim_equations.h"),
                         "-c", generated[eq], "-o", obj])
            objs.append(obj)
        counts = [f"-DM2C_SIM_CC_VARIANTS={variants['circle_circle']}",
                  f"-DM2C_SIM_PE_VARIANTS={variants['point_edge']}"]
        sources = sorted(str(p) for p in (c / "src").glob("m2c_sim*.c"))
        cmds.append([*SIM_FLAGS, f"-I{inc}", *counts, *sources, str(c / "tools" / "m2c_sim_main.c"), *objs,
                     "-o", os.path.join(workdir, "sim"), str(lib), "-lm"])
        # the same world as a shared library, for ctypes and other programs (m2c_world.h)
        pic_objs = []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".pic.o")
            cmds.append([*SIM_FLAGS, "-fPIC", "-Wno-array-parameter", f"-I{inc}", "-include",
                         str(inc / "m2c_sim_equations.h"), "-c", generated[eq], "-o", obj])
            pic_objs.append(obj)
        cmds.append([*SIM_FLAGS, "-fPIC", "-shared", f"-I{inc}", *counts, *sources, *pic_objs, "-o",
                     os.path.join(workdir, WORLD_LIBRARY), str(runtimes.c_pic_library()), "-lm"])
        return cmds

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
