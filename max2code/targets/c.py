"""C (C11, <math.h>)."""
import os
import re

from max2code.targets.base import Target

# flags of every C build: warnings are errors, no FMA contraction (the
# simulator performs the same operations as the Python reference)
FLAGS = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off"]


def variant_count(path: str, name: str) -> int:
    """How many variants NAME_variant of a generated .c file counts: its
    comment lists them as `/*   K = VARIANT (degree D) */`, K = 0, 1, ..."""
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    head = text.find(f"/* {name}_variant: ")
    if head < 0:
        raise ValueError(f"{path}: no {name}_variant in the generated code")
    body = text[head:text.find(f"int {name}_variant(", head)]
    ks = [int(k) for k in re.findall(r"^/\*   (\d+) = \w+ \(degree \d+\) \*/$", body, re.M)]
    if not ks or ks != list(range(len(ks))):
        raise ValueError(f"{path}: cannot read the variant list of {name}_variant")
    return len(ks)


class C(Target):
    name = "c"
    extension = ".c"
    comment = ("/* ", " */")
    line_directive = '#line {line} "{file}"'

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
        return [f"-I{runtimes.ROOT / 'runtimes' / 'c' / 'include'}", str(lib)]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str]) -> list[list[str]]:
        """Compile the generated circle_circle.c and point_edge.c (checked
        against the declarations of m2c_sim_equations.h), then the simulator
        (runtimes/c/src/m2c_sim*.c) with its program, told how many variants
        each NAME_variant counts, and link them with libm2c.a into workdir/sim."""
        from max2code.harness import runtimes
        c = runtimes.ROOT / "runtimes" / "c"
        lib = runtimes.c_library()
        inc = c / "include"
        cmds, objs = [], []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".o")
            # the generated coef[N] has this build's largest degree as its
            # bound, which the header cannot know (the bound is no part of the type)
            cmds.append([*FLAGS, "-Wno-array-parameter", f"-I{inc}", "-include", str(inc / "m2c_sim_equations.h"),
                         "-c", generated[eq], "-o", obj])
            objs.append(obj)
        counts = [f"-DM2C_SIM_CC_VARIANTS={variant_count(generated['circle_circle'], 'circle_circle')}",
                  f"-DM2C_SIM_PE_VARIANTS={variant_count(generated['point_edge'], 'point_edge')}"]
        sources = sorted(str(p) for p in (c / "src").glob("m2c_sim*.c"))
        cmds.append([*FLAGS, f"-I{inc}", *counts, *sources, str(c / "tools" / "m2c_sim_main.c"), *objs,
                     "-o", os.path.join(workdir, "sim"), str(lib), "-lm"])
        return cmds

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
