"""Build this checkout's runtime libraries (into build/, incrementally) so
that generated code calling a root solver can be compiled and linked."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

from max2code.paths import BUILD, ROOT  # noqa: F401  (re-exported for the targets)


class RuntimeBuildError(RuntimeError):
    """A runtime library did not build; the message holds the tool's output."""


def run(cmd: list[str], cwd: Path, env: dict | None = None) -> None:
    r = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        raise RuntimeBuildError(f"{' '.join(cmd)}\n{r.stdout[-3000:]}")


def c_library() -> Path:
    """build/c/libm2c.a (make, up to date in a few ms)."""
    run(["make", "-s", "-C", str(ROOT / "runtimes" / "c"), f"BUILD={BUILD / 'c'}", str(BUILD / "c" / "libm2c.a")], ROOT)
    return BUILD / "c" / "libm2c.a"


def rust_library() -> Path:
    """The max2code_rt rlib (cargo, release, warnings denied)."""
    env = dict(os.environ, CARGO_TARGET_DIR=str(BUILD / "rust"), RUSTFLAGS="-Dwarnings")
    run(["cargo", "build", "--release", "--quiet", "--lib"], ROOT / "runtimes" / "rust", env)
    return BUILD / "rust" / "release" / "libmax2code_rt.rlib"


def m2_objects() -> list[Path]:
    """The Roots module's object (make with gm2 -fiso)."""
    obj = BUILD / "m2" / "Roots.o"
    run(["make", "-s", "-C", str(ROOT / "runtimes" / "m2"), f"BUILD={BUILD / 'm2'}", str(obj)], ROOT)
    return [obj]
