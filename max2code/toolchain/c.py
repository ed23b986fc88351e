"""C's toolchain: gcc builds of the harnesses and of the simulator with its
world library, and make in runtimes/c for the runtime library (libm2c), the
testee and the install."""
from __future__ import annotations

import os
from pathlib import Path

from max2code.paths import BUILD, RUNTIMES
from max2code.toolchain.base import Toolchain
from max2code.toolchain.tools import build_lock, gsl_libs, run

C_RUNTIME = RUNTIMES / "c"
C_INCLUDE = C_RUNTIME / "include"

# the shared library of the world API that the sim build makes beside the program
WORLD_LIBRARY = "libm2c_world.so"
# flags of every C build: warnings are errors, no FMA contraction (the
# simulator performs the same operations as the Python reference)
FLAGS = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off"]
# the simulator's builds: link-time optimisation inlines the generated
# NAME_variant / NAME_coefficients (24 double arguments, most on the stack)
# into the simulator's predictions (9 % fewer instructions per event), -O3
# 6 % fewer again (4 % less CPU time, alternating runs); the same operations
# in the same order (no FMA, no reassociation either way)
SIM_FLAGS = [*("-O3" if f == "-O2" else f for f in FLAGS), "-flto=auto"]


def make_c(*targets: str | Path) -> None:
    """make in runtimes/c with our flags (warnings are errors), outputs under BUILD/c."""
    with build_lock(BUILD / "c"):
        run(["make", "-s", "-C", str(C_RUNTIME), f"BUILD={BUILD / 'c'}", "WERROR=-Werror", *map(str, targets)], C_RUNTIME)


def c_library() -> Path:
    """BUILD/c/libm2c.a (make, up to date in a few ms)."""
    make_c(BUILD / "c" / "libm2c.a")
    return BUILD / "c" / "libm2c.a"


def c_pic_library() -> Path:
    """BUILD/c/libm2c_pic.a: libm2c's position-independent objects, for shared libraries."""
    make_c(BUILD / "c" / "libm2c_pic.a")
    return BUILD / "c" / "libm2c_pic.a"


def _variant_counts(variants: dict[str, int]) -> list[str]:
    """The defines that tell the simulator how many variants each generated NAME_variant counts."""
    return [f"-DM2C_SIM_CC_VARIANTS={variants['circle_circle']}", f"-DM2C_SIM_PE_VARIANTS={variants['point_edge']}"]


def _sim_sources() -> list[str]:
    """The simulator's sources (runtimes/c/src/m2c_sim*.c) and the pair computation it shares with the TOI library."""
    src = C_RUNTIME / "src"
    return sorted(str(p) for p in src.glob("m2c_sim*.c")) + [str(src / "m2c_toi.c")]


class CToolchain(Toolchain):
    name = "c"
    tools = ("gcc", "pkg-config")
    harness_source = "harness.c"
    world_library = WORLD_LIBRARY

    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness (warnings are errors)."""
        return [[*FLAGS, *[f"-I{d}" for d in include_dirs], src, "-o", exe, *self.runtime_flags(), "-lm"]]

    def runtime_flags(self) -> list[str]:
        lib = c_library()
        return [f"-I{C_INCLUDE}", str(lib)]

    def testee(self, baseline: bool = False) -> list[str]:
        exe = BUILD / "c" / "m2c_testee"
        make_c(exe)
        return [str(exe)] + (["--gsl"] if baseline else [])

    def install_runtime(self, prefix: str) -> str:
        prefix = os.path.abspath(prefix)
        with build_lock(BUILD / "c-install"):
            # m2c.pc holds PREFIX, and make remakes it only when the Makefile changed: an
            # install to another prefix from the same build folder writes it again
            (BUILD / "c-install" / "m2c.pc").unlink(missing_ok=True)
            run(["make", "-s", "-C", str(C_RUNTIME), f"BUILD={BUILD / 'c-install'}",
                 f"PREFIX={prefix}", "install"], C_RUNTIME)
        return (f"installed libm2c (static and shared), m2c_roots.h, m2c_exact.h and m2c.pc under {prefix}; build with\n"
                f"  export PKG_CONFIG_PATH={prefix}/lib/pkgconfig\n"
                "  cc main.c eq.c $(pkg-config --cflags --libs m2c) -Wl,-rpath,$(pkg-config --variable=libdir m2c)")

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        return [[*FLAGS, f"-I{C_INCLUDE}", f"-I{workdir}", src, "-o", exe, str(c_library()),
                 *gsl_libs(), "-lm"]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Compile the generated circle_circle.c and point_edge.c (checked
        against the declarations of m2c_sim_equations.h), then the simulator
        (runtimes/c/src/m2c_sim*.c and the pair computation it shares with the
        TOI library, m2c_toi.c) with its program, told how many variants
        each NAME_variant counts, and link them with libm2c.a into workdir/sim
        (the shared library of the world is world_build's, made only when
        asked for)."""
        c = C_RUNTIME
        lib = c_library()
        inc, src = c / "include", c / "src"
        cmds, objs = [], []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".o")
            # the generated coef[N] has this build's largest degree as its
            # bound, which the header cannot know (the bound is no part of the type)
            cmds.append([*SIM_FLAGS, "-Wno-array-parameter", f"-I{inc}", "-include", str(src / "m2c_sim_equations.h"),
                         "-c", generated[eq], "-o", obj])
            objs.append(obj)
        cmds.append([*SIM_FLAGS, f"-I{inc}", f"-I{src}", *_variant_counts(variants), *_sim_sources(),
                     str(c / "tools" / "m2c_sim_main.c"), *objs, "-o", os.path.join(workdir, "sim"), str(lib), "-lm"])
        return cmds

    def world_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Commands that build the world of sim_build's program (m2c_world.h)
        as a shared library, for ctypes and other programs: the same sources
        and generated files, compiled position-independent and linked with
        libm2c's position-independent objects into workdir/libm2c_world.so."""
        inc, src = C_RUNTIME / "include", C_RUNTIME / "src"
        cmds, pic_objs = [], []
        for eq in ("circle_circle", "point_edge"):
            obj = os.path.join(workdir, eq + ".pic.o")
            cmds.append([*SIM_FLAGS, "-fPIC", "-Wno-array-parameter", f"-I{inc}", "-include",
                         str(src / "m2c_sim_equations.h"), "-c", generated[eq], "-o", obj])
            pic_objs.append(obj)
        cmds.append([*SIM_FLAGS, "-fPIC", "-shared", f"-I{inc}", f"-I{src}", *_variant_counts(variants),
                     *_sim_sources(), *pic_objs, "-o", os.path.join(workdir, WORLD_LIBRARY), str(c_pic_library()),
                     "-lm"])
        return cmds

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
