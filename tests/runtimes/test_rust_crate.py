"""The Rust runtime (runtimes/rust, the crate max2code_rt) as a Rust user
builds it: formatted as `cargo fmt` leaves it, free of clippy's warnings,
and built and tested in cargo's default debug profile (overflow checks and
debug assertions on), where the rest of the suite builds it in release.

The target folder is the one the runtime's own builds use (BUILD/rust,
max2code/toolchain/rust.py, with its RUSTFLAGS=-Dwarnings), so that a
second run rebuilds nothing.  clippy and rustfmt come with rustup's default
profile; scripts/setup adds them when they are missing."""
from __future__ import annotations

import subprocess

import pytest

from max2code.toolchain import rust as runtimes

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def cargo(*args: str, timeout: float = 1800) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(["cargo", *args], cwd=runtimes.RUST_RUNTIME, env=runtimes.rust_env(),
                              stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=timeout)
    except FileNotFoundError:
        raise AssertionError("cargo is not installed (scripts/setup says how to get it)") from None


def check(r: subprocess.CompletedProcess, what: str) -> None:
    assert r.returncode == 0, f"{what} failed (exit {r.returncode}):\n{r.stdout[-4000:]}\n{r.stderr[-4000:]}"


def test_rustfmt_leaves_the_crate_as_it_is():
    assert cargo("fmt", "--version").returncode == 0, "rustfmt is missing: rustup component add rustfmt"
    check(cargo("fmt", "--check"), "cargo fmt --check (run `cargo fmt` in runtimes/rust)")


def test_clippy_has_no_warnings():
    assert cargo("clippy", "--version").returncode == 0, "clippy is missing: rustup component add clippy"
    check(cargo("clippy", "--quiet", "--all-targets", "--", "-D", "warnings"),
          "cargo clippy --all-targets -- -D warnings")


def test_debug_build_and_tests():
    """`cargo build` with no profile is a debug build, as a crate that depends
    on max2code_rt gets it: overflowing arithmetic (also in constant tables)
    is an error there, while release wraps."""
    check(cargo("build", "--quiet", "--all-targets"), "cargo build (debug)")
    check(cargo("test", "--quiet"), "cargo test (debug)")
