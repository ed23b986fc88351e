"""C (C11, <math.h>)."""
from max2code.targets.base import Target


class C(Target):
    name = "c"
    extension = ".c"
    comment = ("/* ", " */")
    line_directive = '#line {line} "{file}"'

    single_type = "float"
    single_calls = {"sin": "sinf({})", "cos": "cosf({})", "sqrt": "sqrtf({})", "abs": "fabsf({})"}
    single_suffix = "f"

    harness_source = "harness.c"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness (warnings are errors)."""
        return [["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off",
                 *[f"-I{d}" for d in include_dirs], src, "-o", exe, *self.runtime_flags(), "-lm"]]

    def runtime_flags(self) -> list[str]:
        from max2code import runtimes
        lib = runtimes.c_library()
        return [f"-I{runtimes.ROOT / 'runtimes' / 'c' / 'include'}", str(lib)]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]
