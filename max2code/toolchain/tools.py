"""Running the build tools of the bundled runtime libraries (make, cargo),
with the tool's output kept for the error, and GSL's link flags.  Our own
builds deny warnings (the C Makefile's WERROR, cargo's RUSTFLAGS); a user's
`make` does not."""
from __future__ import annotations

import contextlib
import functools
import os
import shutil
import subprocess
from pathlib import Path

try:
    import fcntl
except ImportError:     # not on Windows: there builds are not guarded against each other
    fcntl = None

from max2code.errors import Max2CodeError


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


@contextlib.contextmanager
def build_lock(folder: Path):
    """Hold the exclusive lock of `folder` (its file `.lock`) while building
    into it: two processes that build the same thing at once (two commands,
    or the test suite's parallel workers) take turns, and the second finds
    the first's outputs up to date instead of overwriting them half made."""
    if fcntl is None:
        yield
        return
    folder.mkdir(parents=True, exist_ok=True)
    fd = os.open(folder / ".lock", os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)        # releases the lock


def gsl_libs() -> list[str]:
    """GSL's link flags (pkg-config, else the usual three)."""
    out = subprocess.run(["pkg-config", "--libs", "gsl"], stdin=subprocess.DEVNULL, capture_output=True, text=True)
    return out.stdout.split() if out.returncode == 0 else ["-lgsl", "-lgslcblas", "-lm"]


@functools.lru_cache(maxsize=None)
def tool_version(tool: str) -> str:
    """What names a build tool's version: its `--version` text (rustup's
    proxies and compiler drivers print the real toolchain's)."""
    try:
        proc = subprocess.run([tool, "--version"], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                              timeout=60)
    except OSError as exc:
        return f"{tool}: {exc}"
    return f"{shutil.which(tool) or tool}\n{proc.stdout}{proc.stderr}"
