"""ISO Modula-2 (gm2 -fiso -fcpp): REAL is a C double; sin/cos from RealMath."""
import os
import re

from max2code.targets.base import Target

# flags of every simulator build: ISO dialect, warnings are errors, no FMA
# contraction (the same operations as the Python reference, docs/simulator.md)
SIM_FLAGS = ["-fiso", "-fcpp", "-Wall", "-Werror", "-O2", "-ffp-contract=off"]
# the simulator's library modules (runtimes/m2), compiled into the workdir
SIM_MODULES = ("SimOut", "SimScene", "SimGrid", "SimHeap")


def variant_count(path: str, name: str) -> int:
    """How many variants NAME_variant of a generated .mxd file counts: its
    comment lists them as `(*   K = VARIANT (degree D) *)`, K = 0, 1, ..."""
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    head = text.find(f"(* {name}_variant: ")
    if head < 0:
        raise ValueError(f"{path}: no {name}_variant in the generated code")
    body = text[head:text.find(f"PROCEDURE {name}_variant ", head)]
    ks = [int(k) for k in re.findall(r"^\(\*   (\d+) = \w+ \(degree \d+\) \*\)$", body, re.M)]
    if not ks or ks != list(range(len(ks))):
        raise ValueError(f"{path}: cannot read the variant list of {name}_variant")
    return len(ks)


class Modula2(Target):
    name = "m2"
    extension = ".mxd"
    comment = ("(* ", " *)")
    line_directive = '#line {line} "{file}"'
    line_offset = 1          # gm2 12 reports a line one less than the #line directive gives
    exponent_letter = "E"    # ISO Modula-2 real literal: 1.0E-5
    def zero_test(self, names) -> str:
        # AND binds tighter than = in Modula-2: parenthesise each test
        return " AND ".join(f"({n} = {self.real_literal(0.0)})" for n in names)

    calls = {"sin": "sin({})", "cos": "cos({})", "sqrt": "sqrt({})", "abs": "ABS({})"}
    single_type = "SHORTREAL"     # gm2 12 has no ShortMath: sin and cos of REAL, rounded
    single_copies = True          # REAL parameters, SHORTREAL copies (no implicit conversion in Modula-2)
    single_calls = {"sin": "VAL(SHORTREAL, sin(VAL(REAL, {})))", "cos": "VAL(SHORTREAL, cos(VAL(REAL, {})))",
                    "sqrt": "VAL(SHORTREAL, sqrt(VAL(REAL, {})))", "abs": "ABS({})"}

    harness_source = "harness.mod"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness: gm2 -fiso -fcpp, warnings are errors."""
        return [["gm2", "-fiso", "-fcpp", "-Wall", "-Werror", "-O2",
                 *[f"-I{d}" for d in include_dirs], *self.runtime_flags(), src, "-o", exe, "-lm"]]

    def runtime_flags(self) -> list[str]:
        from max2code.harness import runtimes
        objs = runtimes.m2_objects()
        return [f"-I{runtimes.ROOT / 'runtimes' / 'm2'}", *map(str, objs)]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str]) -> list[list[str]]:
        """Compile the simulator's library modules (SIM_MODULES: trace
        writer, scene, grid, event queue) and the simulator (SimMain, which
        #includes the generated circle_circle.mxd and point_edge.mxd from
        workdir) and link them with the Roots runtime into workdir/sim.
        The commands run in workdir: gm2 writes SimMain.o to the current
        directory and its linking step looks the program module's object up
        along the -I path, where workdir comes first, so it finds this one."""
        from max2code.harness import runtimes
        m2 = runtimes.ROOT / "runtimes" / "m2"
        objs = runtimes.m2_objects()
        libs = [os.path.join(workdir, f"{m}.o") for m in SIM_MODULES]
        counts = [f"-DSIM_CC_VARIANTS={variant_count(generated['circle_circle'], 'circle_circle')}",
                  f"-DSIM_PE_VARIANTS={variant_count(generated['point_edge'], 'point_edge')}"]
        incs = [f"-I{workdir}", f"-I{m2}", f"-I{m2 / 'src'}"]
        return [*[["gm2", *SIM_FLAGS, *incs, "-c", str(m2 / f"{m}.mod"), "-o", o] for m, o in zip(SIM_MODULES, libs)],
                ["gm2", *SIM_FLAGS, *counts, *incs, str(m2 / "SimMain.mod"), *libs, *map(str, objs),
                 "-o", os.path.join(workdir, "sim"), "-lm"]]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
