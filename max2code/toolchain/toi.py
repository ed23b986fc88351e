"""The TOI library (docs/toi.md) for each runtime: the runtime's pair
computation (C runtimes/c/src/m2c_toi.c, Python max2code_rt.toi, Rust
max2code_rt::toi, Modula-2 Toi) with the generated circle_circle and
point_edge entries of every effect (acceleration, orbit) at a Taylor order,
built as the simulator of those effects is (max2code/sim/simulate.py,
cached under build/sim/LANG/acceleration-orbit-oN/)."""
from __future__ import annotations

import functools
import importlib.util
import os
import subprocess
from pathlib import Path

from max2code.generate.variants import WORLD_EFFECTS
from max2code.paths import BUILD, RUNTIMES
from max2code.sim.simulate import build_simulator, effects_world_library

ORDER = 4       # the Taylor order of the library's generated polynomials (the simulator's default)


def _module(path: str, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@functools.lru_cache(maxsize=None)
def python_toi(order: int = ORDER, tol: float = 1e-9):
    """A max2code_rt.toi.Toi over the generated Python modules of every effect."""
    try:
        from max2code_rt.toi import Toi
    except ImportError:
        import sys
        sys.path.insert(0, str(RUNTIMES / "python"))
        from max2code_rt.toi import Toi
    build = build_simulator("python", WORLD_EFFECTS, order)
    return Toi(_module(build.generated["circle_circle"], "m2c_toi_circle_circle"),
               _module(build.generated["point_edge"], "m2c_toi_point_edge"), tol=tol, taylor_order=order)


def c_library(order: int = ORDER) -> Path:
    """The shared library holding m2c_toi (m2c_toi.h) with the generated C
    of every effect: the simulator build's libm2c_world.so, which exports it."""
    return effects_world_library("c", WORLD_EFFECTS, order)


def c_program(source: Path, name: str, order: int = ORDER) -> Path:
    """A C program (source) linked with c_library(order), built under
    build/toi/c/ when its source or the library changed."""
    lib = c_library(order)
    out = BUILD / "toi" / "c" / f"{name}-o{order}"
    out.parent.mkdir(parents=True, exist_ok=True)
    newest = max(os.path.getmtime(source), os.path.getmtime(lib), os.path.getmtime(RUNTIMES / "c" / "include" /
                                                                                   "m2c_toi.h"))
    if not out.exists() or os.path.getmtime(out) < newest:
        cmd = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off",
               f"-I{RUNTIMES / 'c' / 'include'}", str(source), "-o", str(out), str(lib),
               f"-Wl,-rpath,{lib.parent}", "-lm"]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}\n{proc.stderr[-3000:]}")
    return out


RUST_MAIN = """\
// The TOI library's conformance testee with the generated contact equations
// of every effect (written by max2code/toolchain/toi.py: do not edit).
#[path = {cc}]
#[allow(dead_code)]
mod circle_circle;
#[path = {pe}]
#[allow(dead_code)]
mod point_edge;

max2code_rt::sim_equations!(circle_circle, point_edge);

fn main() {{
    ::std::process::exit(max2code_rt::toi::testee_main::<GeneratedEquations>());
}}
"""


def rust_testee(order: int = ORDER) -> Path:
    """The Rust TOI testee (max2code_rt::toi::testee_main over the generated
    Rust of every effect), built under build/toi/rust/ when its inputs changed."""
    from max2code.toolchain.rust import RustToolchain, _rust_str
    build = build_simulator("rust", WORLD_EFFECTS, order)
    work = BUILD / "toi" / "rust" / f"o{order}"
    work.mkdir(parents=True, exist_ok=True)
    main = work / "main.rs"
    text = RUST_MAIN.format(cc=_rust_str(build.generated["circle_circle"]), pe=_rust_str(build.generated["point_edge"]))
    if not main.exists() or main.read_text(encoding="utf-8") != text:
        main.write_text(text, encoding="utf-8")
    exe = work / "m2c_toi_testee"
    flags = RustToolchain().runtime_flags(sim=True)
    rlib = Path(flags[1].split("=", 1)[1])
    newest = max(os.path.getmtime(main), os.path.getmtime(rlib), *(os.path.getmtime(g) for g in build.generated.values()))
    if not exe.exists() or os.path.getmtime(exe) < newest:
        cmd = ["rustc", "--edition", "2021", "-D", "warnings", "-C", "opt-level=3", "-C", "codegen-units=1", *flags,
               str(main), "-o", str(exe)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}\n{proc.stderr[-3000:]}")
    return exe


def m2_testee(order: int = ORDER) -> Path:
    """The Modula-2 TOI testee (runtimes/m2/ToiTestee.mod over the library
    module Toi) linked with the simulator build of every effect (its modules
    and the part modules of the generated code), built under build/toi/m2/ when its
    inputs changed.  The commands run in that folder: gm2 writes the
    program's objects to the current folder and looks them up along -I,
    where that folder comes first."""
    from max2code.toolchain.m2 import M2_RUNTIME, SIM_FLAGS, SIM_GENERATED, SIM_MODULES, Modula2Toolchain, m2_objects
    from max2code.toolchain.tools import gsl_libs
    build = build_simulator("m2", WORLD_EFFECTS, order)
    work = BUILD / "toi" / "m2" / f"o{order}"
    work.mkdir(parents=True, exist_ok=True)
    exe = work / "toi_testee"
    objs = m2_objects("Roots", "RootsGsl", "Wire")
    sim_objs = [Path(build.workdir) / f"{m}.o"
                for m in (*SIM_MODULES, SIM_GENERATED, *Modula2Toolchain.sim_parts(build.workdir))]
    sources = [M2_RUNTIME / "Toi.mod", M2_RUNTIME / "Toi.def", M2_RUNTIME / "ToiTestee.mod"]
    newest = max(os.path.getmtime(p) for p in (*sources, *objs, *sim_objs))
    if not exe.exists() or os.path.getmtime(exe) < newest:
        incs = [f"-I{work}", f"-I{build.workdir}", f"-I{M2_RUNTIME}", f"-I{M2_RUNTIME / 'src'}"]
        toi_o = work / "Toi.o"
        cmds = [["gm2", *SIM_FLAGS, *incs, "-c", str(M2_RUNTIME / "Toi.mod"), "-o", str(toi_o)],
                ["gm2", *SIM_FLAGS, *incs, str(M2_RUNTIME / "ToiTestee.mod"), str(toi_o), *map(str, sim_objs),
                 *map(str, objs), "-o", str(exe), *gsl_libs(), "-lm"]]
        for cmd in cmds:
            proc = subprocess.run(cmd, cwd=work, capture_output=True, text=True)
            if proc.returncode != 0:
                raise RuntimeError(f"{' '.join(cmd)}\n{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
    return exe
