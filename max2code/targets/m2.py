"""ISO Modula-2 (gm2 -fiso -fcpp): REAL is a C double; sin/cos from RealMath."""
import os
import re

from max2code.targets.base import Target, c_string, code_point, visible

# flags of every simulator build: ISO dialect, warnings are errors, no FMA
# contraction (the same operations as the Python reference, docs/simulator.md)
SIM_FLAGS = ["-fiso", "-fcpp", "-Wall", "-Werror", "-O2", "-ffp-contract=off"]
# the simulator's library modules (runtimes/m2), compiled into the workdir
SIM_MODULES = ("SimOut", "SimScene", "SimGrid", "SimHeap")


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

    harness_source = "harness.mod"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness: gm2 -fiso -fcpp, warnings are errors."""
        return [["gm2", "-fiso", "-fcpp", "-Wall", "-Werror", "-O2",
                 *[f"-I{d}" for d in include_dirs], *self.runtime_flags(), src, "-o", exe, "-lm"]]

    def runtime_flags(self) -> list[str]:
        from max2code.harness import runtimes
        objs = runtimes.m2_objects()
        return [f"-I{runtimes.M2_RUNTIME}", *map(str, objs)]

    def testee(self, baseline: bool = False) -> list[str]:
        from max2code.harness import runtimes
        exe = runtimes.BUILD / "m2" / ("roots_gsl_testee" if baseline else "roots_testee")
        runtimes.make_m2(exe)
        return [str(exe)]

    def install_runtime(self, prefix: str) -> str:
        from max2code.harness import runtimes
        prefix = os.path.abspath(prefix)
        runtimes.run(["make", "-s", "-C", str(runtimes.M2_RUNTIME), f"BUILD={runtimes.BUILD / 'm2-install'}",
                      f"PREFIX={prefix}", "install"], runtimes.M2_RUNTIME)
        d = f"{prefix}/lib/max2code/m2"
        return (f"installed Roots, ExactToc (and RootsGsl, Wire) .def/.mod/.o in {d}; build with\n"
                f"  gm2 -fiso -fcpp -I{d} prog.mod {d}/Roots.o {d}/ExactToc.o -o prog -lm")

    harness_rows_fixed = True     # the exact harness reads its rows into a static array

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        from max2code.harness import runtimes
        m2 = runtimes.M2_RUNTIME
        objs = runtimes.m2_objects("Roots", "RootsGsl", "ExactToc")
        return [["gm2", "-fiso", "-fcpp", "-Wall", "-Werror", "-O2", f"-I{m2}", f"-I{m2 / 'src'}", f"-I{workdir}",
                 *map(str, objs), src, "-o", exe, *runtimes.gsl_libs(), "-lm"]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Compile the simulator's library modules (SIM_MODULES: trace
        writer, scene, grid, event queue), the live world (SimWorld, which
        #includes the generated circle_circle.mxd and point_edge.mxd from
        workdir) and the batch simulator (SimMain, its thin user), and link
        them with the Roots runtime into workdir/sim.
        The commands run in workdir: gm2 writes SimMain.o to the current
        directory and its linking step looks the program module's object up
        along the -I path, where workdir comes first, so it finds this one."""
        return [*self.sim_world_build(workdir, variants),
                self.sim_program_build(workdir, os.path.join(str(self._m2()), "SimMain.mod"),
                                       os.path.join(workdir, "sim"))]

    @staticmethod
    def _m2():
        from max2code.harness import runtimes
        return runtimes.M2_RUNTIME

    def sim_world_build(self, workdir: str, variants: dict[str, int]) -> list[list[str]]:
        """Commands (run in workdir) that compile SIM_MODULES and SimWorld
        into workdir/NAME.o, with the generated .mxd files from workdir."""
        m2 = self._m2()
        libs = [os.path.join(workdir, f"{m}.o") for m in SIM_MODULES]
        counts = [f"-DSIM_CC_VARIANTS={variants['circle_circle']}",
                  f"-DSIM_PE_VARIANTS={variants['point_edge']}"]
        incs = [f"-I{workdir}", f"-I{m2}", f"-I{m2 / 'src'}"]
        return [*[["gm2", *SIM_FLAGS, *incs, "-c", str(m2 / f"{m}.mod"), "-o", o] for m, o in zip(SIM_MODULES, libs)],
                ["gm2", *SIM_FLAGS, *counts, *incs, "-c", str(m2 / "SimWorld.mod"),
                 "-o", os.path.join(workdir, "SimWorld.o")]]

    def sim_program_build(self, workdir: str, program: str, exe: str) -> list[str]:
        """The command (run in workdir) that compiles a program module using
        SimWorld and links it with the objects sim_world_build made."""
        from max2code.harness import runtimes
        m2 = self._m2()
        objs = runtimes.m2_objects()
        libs = [os.path.join(workdir, f"{m}.o") for m in (*SIM_MODULES, "SimWorld")]
        incs = [f"-I{workdir}", f"-I{m2}", f"-I{m2 / 'src'}"]
        return ["gm2", *SIM_FLAGS, *incs, program, *libs, *map(str, objs), "-o", exe, "-lm"]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
