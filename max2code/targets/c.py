"""C (C11, <math.h>)."""
import os

from max2code.targets.base import Target

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
        inc, src = c / "include", c / "src"
        cmds, objs = [], []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".o")
            # the generated coef[N] has this build's largest degree as its
            # bound, which the header cannot know (the bound is no part of the type)
            cmds.append([*SIM_FLAGS, "-Wno-array-parameter", f"-I{inc}", "-include", str(src / "m2c_sim_equations.h"),
                         "-c", generated[eq], "-o", obj])
            objs.append(obj)
        counts = [f"-DM2C_SIM_CC_VARIANTS={variants['circle_circle']}",
                  f"-DM2C_SIM_PE_VARIANTS={variants['point_edge']}"]
        sources = sorted(str(p) for p in src.glob("m2c_sim*.c"))
        cmds.append([*SIM_FLAGS, f"-I{inc}", f"-I{src}", *counts, *sources, str(c / "tools" / "m2c_sim_main.c"),
                     *objs, "-o", os.path.join(workdir, "sim"), str(lib), "-lm"])
        # the same world as a shared library, for ctypes and other programs (m2c_world.h)
        pic_objs = []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".pic.o")
            cmds.append([*SIM_FLAGS, "-fPIC", "-Wno-array-parameter", f"-I{inc}", "-include",
                         str(src / "m2c_sim_equations.h"), "-c", generated[eq], "-o", obj])
            pic_objs.append(obj)
        cmds.append([*SIM_FLAGS, "-fPIC", "-shared", f"-I{inc}", *counts, *sources, *pic_objs, "-o",
                     os.path.join(workdir, WORLD_LIBRARY), str(runtimes.c_pic_library()), "-lm"])
        return cmds

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
