"""Modula-2's toolchain: gm2 builds of the harnesses and of the simulator
(its library modules, one per concept, and programs using the live world SimLive), and
make in runtimes/m2 for the runtime's objects, the testees and the install."""
from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
from pathlib import Path

from max2code import paths
from max2code.paths import BUILD, RUNTIMES
from max2code.toolchain.base import Toolchain
from max2code.toolchain.tools import RuntimeBuildError, build_lock, gsl_libs, run, tool_version

M2_RUNTIME = RUNTIMES / "m2"

# flags of every simulator build: ISO dialect, warnings are errors, no FMA
# contraction (the same operations as the Python reference, docs/simulator.md)
SIM_FLAGS = ["-fiso", "-fcpp", "-Wall", "-Werror", "-O2", "-ffp-contract=off"]
# the simulator's library modules (runtimes/m2, one per concept), compiled into the workdir;
# SIM_GENERATED includes the generated code (compiled with the variant counts defined)
SIM_MODULES = ("SimOut", "SimScene", "SimQueue", "SimGrid", "SimMotion", "SimWorld", "SimContact", "SimSupport",
               "SimSleep", "SimOverlap", "SimCluster", "SimHandlers", "SimLive")
SIM_GENERATED = "SimPredict"
# the folder (in the simulator's workdir) of the texts SIM_GENERATED includes
# in place of the generated files, and the list of their part modules (m2_split.py)
SPLIT = "split"
PARTS_LIST = "parts.txt"
HARNESS_FLAGS = ["-fiso", "-fcpp", "-Wall", "-Werror", "-O2"]


def _split_harness(src: str) -> tuple[list[str], list[str]]:
    """The harness source `src` made to include its generated file as part
    modules (m2_split.py): the part modules written beside it, the include
    turned to the text that imports them (GENERATED.parts).  Returns the
    commands' pieces: the parts' sources and their objects (none when the
    harness includes no generated file beside it)."""
    if not (src.endswith(".mod") and os.path.isfile(src)):
        return [], []
    workdir = os.path.dirname(os.path.abspath(src))
    with open(src, encoding="utf-8") as fh:
        text = fh.read()
    found = re.search(r'^#include "([\w.-]+\.mxd)(?:\.parts)?"$', text, re.M)     # .parts: split before
    if found is None or not os.path.isfile(os.path.join(workdir, found.group(1))):
        return [], []
    name = found.group(1)
    from max2code.toolchain.m2_split import split_files
    parts = split_files([os.path.join(workdir, name)], workdir, workdir, ".parts")
    if not parts:
        return [], []
    text = text.replace(found.group(0), f'#include "{name}.parts"')
    with open(src, "w", encoding="utf-8") as fh:
        fh.write(text)
    return ([os.path.join(workdir, f"{m}.mod") for m in parts], [os.path.join(workdir, f"{m}.o") for m in parts])


def _part_builds(flags: list[str], incs: list[str], sources: list[str]) -> list[list[str]]:
    """The commands that compile part modules (each SOURCE.mod into SOURCE.o)."""
    return [["gm2", *flags, *incs, "-c", m, "-o", m[:-4] + ".o"] for m in sources]


def make_m2(*targets: str | Path) -> None:
    """make in runtimes/m2, outputs under BUILD/m2.  Without WERROR: gm2 12 warns of an
    unused VAR parameter it reads (Roots.Variations) and of GSL's output array (RootsGsl)."""
    with build_lock(BUILD / "m2"):
        run(["make", "-s", "-C", str(M2_RUNTIME), f"BUILD={BUILD / 'm2'}", *map(str, targets)], M2_RUNTIME)


def m2_objects(*modules: str) -> list[Path]:
    """Objects of the Modula-2 runtime's modules (default: Roots), made with gm2 -fiso."""
    objs = [BUILD / "m2" / f"{m}.o" for m in (modules or ("Roots",))]
    make_m2(*objs)
    return objs


def sim_library_objects() -> Path:
    """The folder of SIM_MODULES' objects, compiled once for every simulator
    build: they read no generated code (only SIM_GENERATED does), so the
    objects are the same bytes whatever the effects and the variant counts.
    The folder is BUILD/m2/sim-lib/KEY, KEY the digest of the runtime sources,
    the flags and gm2's version; it is made in a temporary folder and renamed
    into place whole, under a lock, so parallel builds take turns and a
    folder that exists holds every object."""
    h = hashlib.sha256()
    for part in (paths.sources_digest(), "\0".join(SIM_FLAGS), tool_version("gm2"), "\0".join(SIM_MODULES)):
        h.update(part.encode() + b"\0")
    base = BUILD / "m2" / "sim-lib"
    final = base / h.hexdigest()[:32]
    if final.is_dir():
        return final
    with build_lock(base):
        if final.is_dir():
            return final
        tmp = base / f"{final.name}.{os.getpid()}.tmp"
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir(parents=True)
        incs = [f"-I{tmp}", f"-I{M2_RUNTIME}", f"-I{M2_RUNTIME / 'src'}"]
        for m in SIM_MODULES:
            proc = subprocess.run(["gm2", *SIM_FLAGS, *incs, "-c", str(M2_RUNTIME / f"{m}.mod"), "-o", str(tmp / f"{m}.o")],
                                  cwd=tmp, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=1800)
            if proc.returncode != 0:
                shutil.rmtree(tmp, ignore_errors=True)
                raise RuntimeBuildError(f"max2code: error: the Modula-2 simulator module {m} did not build\n"
                                        f"{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
        os.replace(tmp, final)
    return final


class Modula2Toolchain(Toolchain):
    name = "m2"
    tools = ("gm2", "pkg-config")
    harness_source = "harness.mod"

    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness: gm2 -fiso -fcpp, warnings are errors;
        the runtime's src folder (cstdio.def, which the harness imports) follows
        `include_dirs` on the search path."""
        incs = [f"-I{d}" for d in (*include_dirs, M2_RUNTIME / "src")]
        sources, objs = _split_harness(src)
        return [*_part_builds(HARNESS_FLAGS, [*incs, f"-I{M2_RUNTIME}"], sources),
                ["gm2", *HARNESS_FLAGS, *incs, *self.runtime_flags(), *objs, src, "-o", exe, "-lm"]]

    def runtime_flags(self) -> list[str]:
        objs = m2_objects()
        return [f"-I{M2_RUNTIME}", *map(str, objs)]

    def testee(self, baseline: bool = False) -> list[str]:
        exe = BUILD / "m2" / ("roots_gsl_testee" if baseline else "roots_testee")
        make_m2(exe)
        return [str(exe)]

    def install_runtime(self, prefix: str) -> str:
        prefix = os.path.abspath(prefix)
        with build_lock(BUILD / "m2-install"):
            run(["make", "-s", "-C", str(M2_RUNTIME), f"BUILD={BUILD / 'm2-install'}",
                 f"PREFIX={prefix}", "install"], M2_RUNTIME)
        d = f"{prefix}/lib/max2code/m2"
        return (f"installed Roots, ExactToc (and RootsGsl, Wire) .def/.mod/.o in {d}; build with\n"
                f"  gm2 -fiso -fcpp -I{d} prog.mod {d}/Roots.o {d}/ExactToc.o -o prog -lm")

    harness_rows_fixed = True     # the exact harness reads its rows into a static array

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        m2 = M2_RUNTIME
        objs = m2_objects("Roots", "RootsGsl", "ExactToc")
        incs = [f"-I{m2}", f"-I{m2 / 'src'}", f"-I{workdir}"]
        sources, parts = _split_harness(os.path.join(workdir, src))
        return [*_part_builds(HARNESS_FLAGS, incs, sources),
                ["gm2", *HARNESS_FLAGS, *incs, *map(str, objs), *parts, src, "-o", exe, *gsl_libs(), "-lm"]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Compile the simulator's library modules (SIM_MODULES, and
        SIM_GENERATED, which #includes the generated circle_circle.mxd and
        point_edge.mxd from workdir, split into part modules by
        sim_world_build) and the batch simulator (SimMain, a thin
        user of the live world SimLive), and link
        them with the Roots runtime into workdir/sim.
        The commands run in workdir: gm2 writes SimMain.o to the current
        directory and its linking step looks the program module's object up
        along the -I path, where workdir comes first, so it finds this one."""
        return [*self.sim_world_build(workdir, variants),
                self.sim_program_build(workdir, os.path.join(str(self._m2()), "SimMain.mod"),
                                       os.path.join(workdir, "sim"))]

    @staticmethod
    def _m2():
        return M2_RUNTIME

    def sim_world_build(self, workdir: str, variants: dict[str, int]) -> list[list[str]]:
        """Commands (run in workdir) that put SIM_MODULES' objects into
        workdir/NAME.o (copies of sim_library_objects', compiled once for all
        the simulators) and compile SIM_GENERATED there, with the generated
        .mxd files from workdir: their coefficient procedures as part
        modules (m2_split.py; gm2's time grows with the square of a module's
        length), SIM_GENERATED including the rest (workdir/split/NAME.mxd)."""
        m2 = self._m2()
        shared = sim_library_objects()
        counts = [f"-DSIM_CC_VARIANTS={variants['circle_circle']}",
                  f"-DSIM_PE_VARIANTS={variants['point_edge']}"]
        from max2code.toolchain.m2_split import split_files
        parts = split_files([os.path.join(workdir, f"{eq}.mxd") for eq in ("circle_circle", "point_edge")],
                            workdir, os.path.join(workdir, SPLIT))
        with open(os.path.join(workdir, SPLIT, PARTS_LIST), "w", encoding="utf-8") as fh:
            fh.write("".join(f"{m}\n" for m in parts))
        incs = [f"-I{os.path.join(workdir, SPLIT)}", f"-I{workdir}", f"-I{m2}", f"-I{m2 / 'src'}"]
        return [["cp", *[str(shared / f"{m}.o") for m in SIM_MODULES], workdir],
                *_part_builds(SIM_FLAGS, incs, [os.path.join(workdir, f"{m}.mod") for m in parts]),
                ["gm2", *SIM_FLAGS, *counts, *incs, "-c", str(m2 / f"{SIM_GENERATED}.mod"),
                 "-o", os.path.join(workdir, f"{SIM_GENERATED}.o")]]

    @staticmethod
    def sim_parts(workdir: str) -> list[str]:
        """The part modules of the generated code in a simulator's workdir (sim_world_build's)."""
        try:
            with open(os.path.join(workdir, SPLIT, PARTS_LIST), encoding="utf-8") as fh:
                return fh.read().split()
        except OSError:
            return []

    def sim_program_build(self, workdir: str, program: str, exe: str) -> list[str]:
        """The command (run in workdir) that compiles a program module using
        the live world SimLive and links it with the objects sim_world_build made."""
        m2 = self._m2()
        objs = m2_objects()
        libs = [os.path.join(workdir, f"{m}.o") for m in (*SIM_MODULES, SIM_GENERATED, *self.sim_parts(workdir))]
        incs = [f"-I{workdir}", f"-I{m2}", f"-I{m2 / 'src'}"]
        return ["gm2", *SIM_FLAGS, *incs, program, *libs, *map(str, objs), "-o", exe, "-lm"]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [os.path.join(workdir, "sim")]
