"""Build the bundled runtime libraries (into paths.BUILD, incrementally) so
that generated code calling a root solver can be compiled and linked.
Our own builds deny warnings (the C Makefile's WERROR, cargo's RUSTFLAGS);
a user's `make` does not."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

from max2code.errors import Max2CodeError
from max2code.paths import BUILD, RUNTIMES  # noqa: F401  (re-exported for the targets)

C_RUNTIME = RUNTIMES / "c"
C_INCLUDE = C_RUNTIME / "include"
M2_RUNTIME = RUNTIMES / "m2"
RUST_RUNTIME = RUNTIMES / "rust"


class RuntimeBuildError(Max2CodeError):
    """A runtime library did not build; the message holds the tool's output."""


def run(cmd: list[str], cwd: Path, env: dict | None = None) -> None:
    try:
        r = subprocess.run(cmd, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
    except FileNotFoundError:
        raise RuntimeBuildError(f"max2code: error: {cmd[0]} is needed to build the runtime and was not found") from None
    if r.returncode != 0:
        raise RuntimeBuildError(f"max2code: error: the runtime did not build: {' '.join(map(str, cmd))}\n{r.stdout[-3000:]}")


def gsl_libs() -> list[str]:
    """GSL's link flags (pkg-config, else the usual three)."""
    out = subprocess.run(["pkg-config", "--libs", "gsl"], stdin=subprocess.DEVNULL, capture_output=True, text=True)
    return out.stdout.split() if out.returncode == 0 else ["-lgsl", "-lgslcblas", "-lm"]


def make_c(*targets: str | Path) -> None:
    """make in runtimes/c with our flags (warnings are errors), outputs under BUILD/c."""
    run(["make", "-s", "-C", str(C_RUNTIME), f"BUILD={BUILD / 'c'}", "WERROR=-Werror", *map(str, targets)], C_RUNTIME)


def make_m2(*targets: str | Path) -> None:
    """make in runtimes/m2, outputs under BUILD/m2.  Without WERROR: gm2 12 warns of an
    unused VAR parameter it reads (Roots.Variations) and of GSL's output array (RootsGsl)."""
    run(["make", "-s", "-C", str(M2_RUNTIME), f"BUILD={BUILD / 'm2'}", *map(str, targets)], M2_RUNTIME)


def rust_env() -> dict:
    return dict(os.environ, CARGO_TARGET_DIR=str(BUILD / "rust"), RUSTFLAGS="-Dwarnings")


def cargo(*args: str) -> None:
    """cargo in runtimes/rust (release, warnings denied), target folder BUILD/rust."""
    run(["cargo", *args], RUST_RUNTIME, rust_env())


def c_library() -> Path:
    """BUILD/c/libm2c.a (make, up to date in a few ms)."""
    make_c(BUILD / "c" / "libm2c.a")
    return BUILD / "c" / "libm2c.a"


def c_pic_library() -> Path:
    """BUILD/c/libm2c_pic.a: libm2c's position-independent objects, for shared libraries."""
    make_c(BUILD / "c" / "libm2c_pic.a")
    return BUILD / "c" / "libm2c_pic.a"


def rust_library() -> Path:
    """The max2code_rt rlib (cargo, release, warnings denied)."""
    cargo("build", "--release", "--quiet", "--lib")
    return BUILD / "rust" / "release" / "libmax2code_rt.rlib"


def rust_sim_library() -> Path:
    """The max2code_rt rlib for the simulator's builds (cargo, the crate's
    `sim` profile: release at opt-level 3, warnings denied)."""
    cargo("build", "--profile", "sim", "--quiet", "--lib")
    return BUILD / "rust" / "sim" / "libmax2code_rt.rlib"


def m2_objects(*modules: str) -> list[Path]:
    """Objects of the Modula-2 runtime's modules (default: Roots), made with gm2 -fiso."""
    objs = [BUILD / "m2" / f"{m}.o" for m in (modules or ("Roots",))]
    make_m2(*objs)
    return objs
