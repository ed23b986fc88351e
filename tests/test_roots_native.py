"""The native runtimes' own checks: the C library builds warning-free and
passes its API test, the Rust crate's unit tests pass with -Dwarnings, and the
Modula-2 programs build (their answers are checked by test_conformance.py)."""
from __future__ import annotations

import subprocess

from max2code.conformance import runner as R
from max2code.harness import runtimes


def run(cmd, cwd, env=None):
    r = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert r.returncode == 0, r.stdout[-4000:]
    return r.stdout


def test_c_library_and_api():
    out = run(["make", "-s", f"BUILD={R.BUILD / 'c'}", "WERROR=-Werror", "check"], runtimes.C_RUNTIME)
    assert "15 passed, 0 failed" in out


def test_c_library_builds_with_user_flags(tmp_path):
    """A user's optimisation flags build the library (no -Werror outside our CI),
    here without a single warning."""
    out = run(["make", f"BUILD={tmp_path}", "CFLAGS=-O3 -march=native", "lib"], runtimes.C_RUNTIME)
    assert (tmp_path / "libm2c.a").exists() and (tmp_path / "libm2c.so").exists()
    assert "warning" not in out, out


def test_rust_unit_tests():
    out = run(["cargo", "test", "--release", "--quiet", "--lib"], runtimes.RUST_RUNTIME, R.rust_env())
    assert "test result: ok" in out


def test_m2_programs_build():
    run(["make", "-s", f"BUILD={R.BUILD / 'm2'}"], runtimes.M2_RUNTIME)
    for prog in ("roots_testee", "roots_gsl_testee", "roots_bench"):
        assert (R.BUILD / "m2" / prog).exists()


def test_m2_gsl_baseline_answers():
    cmd = R.build_testee("gsl-m2")
    line = R.RootsOp().wire({"coeffs": [-0.375, 0.0, 0.0, 1.0], "lo": 0.0, "hi": 1.0}, 7)
    out = subprocess.run(cmd, input=line + "\n", stdout=subprocess.PIPE, text=True, check=True).stdout.split()
    assert out[0] == "7" and abs(R.float_of(out[1]) - 0.375 ** (1 / 3)) < 1e-12
