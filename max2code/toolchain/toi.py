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
from max2code.sim.simulate import build_simulator

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
    build = build_simulator("c", WORLD_EFFECTS, order)
    return Path(build.workdir) / "libm2c_world.so"


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
