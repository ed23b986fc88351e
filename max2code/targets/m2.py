"""ISO Modula-2 (gm2 -fiso -fcpp): REAL is a C double; sin/cos from RealMath."""
from max2code.targets.base import Target


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
    single_calls = {"sin": "VAL(SHORTREAL, sin(VAL(REAL, {})))", "cos": "VAL(SHORTREAL, cos(VAL(REAL, {})))",
                    "sqrt": "VAL(SHORTREAL, sqrt(VAL(REAL, {})))", "abs": "ABS({})"}

    harness_source = "harness.mod"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness: gm2 -fiso -fcpp, warnings are errors."""
        return [["gm2", "-fiso", "-fcpp", "-Wall", "-Werror", "-O2",
                 *[f"-I{d}" for d in include_dirs], *self.runtime_flags(), src, "-o", exe, "-lm"]]

    def runtime_flags(self) -> list[str]:
        from max2code import runtimes
        objs = runtimes.m2_objects()
        return [f"-I{runtimes.ROOT / 'runtimes' / 'm2'}", *map(str, objs)]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]
