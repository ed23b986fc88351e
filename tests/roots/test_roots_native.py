"""The native runtimes' own checks: the C library builds warning-free and
passes its API test, the Rust crate's unit tests pass with -Dwarnings, and the
Modula-2 programs build (their answers are checked by test_conformance.py)."""
from __future__ import annotations

import math
import random
import subprocess

import pytest

from max2code.conformance import runner as R
from max2code.toolchain.c import C_RUNTIME, make_c
from max2code.toolchain.m2 import M2_RUNTIME, make_m2
from max2code.toolchain.rust import RUST_RUNTIME
from max2code.toolchain.tools import build_lock

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def run(cmd, cwd, env=None):
    r = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert r.returncode == 0, r.stdout[-4000:]
    return r.stdout


def test_c_library_and_api():
    with build_lock(R.BUILD / "c"):     # the folder other tests (and parallel workers) build into
        out = run(["make", "-s", f"BUILD={R.BUILD / 'c'}", "WERROR=-Werror", "check"], C_RUNTIME)
    assert "15 passed, 0 failed" in out


def test_c_library_builds_with_user_flags(tmp_path):
    """A user's optimisation flags build the library (no -Werror outside our CI),
    here without a single warning."""
    out = run(["make", f"BUILD={tmp_path}", "CFLAGS=-O3 -march=native", "lib"], C_RUNTIME)
    assert (tmp_path / "libm2c.a").exists() and (tmp_path / "libm2c.so").exists()
    assert "warning" not in out, out


def test_rust_unit_tests():
    out = run(["cargo", "test", "--release", "--quiet", "--lib"], RUST_RUNTIME, R.rust_env())
    assert "test result: ok" in out


def test_m2_programs_build():
    with build_lock(R.BUILD / "m2"):
        run(["make", "-s", f"BUILD={R.BUILD / 'm2'}"], M2_RUNTIME)
    for prog in ("roots_testee", "roots_gsl_testee", "roots_bench"):
        assert (R.BUILD / "m2" / prog).exists()


def test_bench_drivers_count_alike():
    """The benchmark drivers of C and Modula-2 count the same found roots per
    degree as the Python reference on the benchmark's own polynomials (a few per
    degree), and the Modula-2 driver refuses a header without REPS instead of
    reading the first case's "roots" as REPS and dropping that case."""
    from max2code.conformance.bench import polynomials, wire
    from max2code_rt.roots import smallest_root
    polys = polynomials(40)
    text = wire(polys)
    make_c(R.BUILD / "c" / "m2c_bench")
    make_m2(R.BUILD / "m2" / "roots_bench")
    want = {d: sum(1 for c in ps if smallest_root(c, 0.0, 1.0) is not None) for d, ps in polys.items()}

    def counts(cmd, stdin):
        out = subprocess.run(cmd, input=stdin, stdout=subprocess.PIPE, text=True, check=True).stdout
        return {int(f[0]): int(f[2]) for f in (ln.split() for ln in out.splitlines())}
    assert counts([str(R.BUILD / "c" / "m2c_bench"), "m2c", "3"], text) == want
    assert counts([str(R.BUILD / "m2" / "roots_bench")], "bench m2 3\n" + text) == want
    for header in ("bench m2", "bench m2 3 4", "bench m2 0", "bench x 3"):
        r = subprocess.run([str(R.BUILD / "m2" / "roots_bench")], input=header + "\n" + text,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert r.returncode == 2 and r.stdout == "" and "line 1: expected the header" in r.stderr, (header, r)


def test_m2_gsl_baseline_answers():
    cmd = R.build_testee("gsl-m2")
    line = R.RootsOp().wire({"coeffs": [-0.375, 0.0, 0.0, 1.0], "lo": 0.0, "hi": 1.0}, 7)
    out = subprocess.run(cmd, input=line + "\n", stdout=subprocess.PIPE, text=True, check=True).stdout.split()
    assert out[0] == "7" and abs(R.float_of(out[1]) - 0.375 ** (1 / 3)) < 1e-12


def _quadratic_shortcut_cases(count: int, seed: int = 12) -> list[tuple[list[float], float, float]]:
    """Quadratics aimed at the degree-2 fast path's shortcuts for lo >= 0
    (docs/roots.md step 1): no sign change (at any magnitude, zeros and
    infinities among them), c0 c2 < 0 with the positive root
    at, just inside or just beyond hi or lo, both roots of one sign, double
    and near-double roots, b = +-0, and magnitudes at the admission's edges."""
    rng = random.Random(seed)
    edges = [1.0, 2.0 ** -200, 2.0 ** -199.5, 2.0 ** 198, 2.0 ** 199.9, 1e-30, 1e30]
    wide = [0.0, 2.0 ** -1074, 1e-310, 1e-300, 1e300, 1.7e308, math.inf]
    cases = []
    for _ in range(count):
        lo = rng.choice([0.0, -0.0, 0.0, 0.25, 1e-300, 2.0 ** -1074, -0.5])
        hi = lo + rng.choice([1.0, 1.0, 0.5, 3.0, 1e-290, 2.0 ** -1074, 1e300])
        r = rng.choice([hi, lo, 0.0, 0.5 * (lo + hi), math.nextafter(hi, math.inf), math.nextafter(hi, -math.inf),
                        math.nextafter(lo, math.inf), hi * (1 + 2.0 ** -rng.randint(40, 52)), rng.uniform(-3.0, 3.0)])
        s = rng.choice([r, -r, 2 * r, math.nextafter(r, math.inf), -rng.uniform(0.0, 3.0), rng.uniform(0.0, 3.0)])
        a = rng.choice([1.0, -1.0, 0.75, -3.0]) * rng.choice(edges)
        kind = rng.random()
        if kind < 0.4:      # from the roots r and s
            c = [a * r * s, -a * (r + s), a]
        elif kind < 0.6:    # no sign change, at any magnitude (the entry's test comes before the admission)
            sg = rng.choice([1.0, -1.0])
            c = [sg * abs(rng.gauss(0, 1)) * rng.choice(edges + wide), sg * abs(rng.gauss(0, 1)) * rng.choice(edges + wide),
                 sg * abs(a) * rng.choice([1.0, 1.0, 1e-300, 1e300])]
        elif kind < 0.8:    # c0 c2 < 0
            c = [-math.copysign(abs(rng.gauss(0, 1)) * rng.choice(edges), a), rng.choice([0.0, -0.0, rng.gauss(0, 1)]), a]
        else:               # near-double roots: b^2 close to 4ac
            b = -2 * a * r
            c = [math.nextafter(a * r * r, rng.choice([math.inf, -math.inf])), b, a]
        if not any(math.isnan(v) for v in c):
            cases.append((c, lo, hi))
    return cases


def _every_runtime_answers(tmp_path, cases, expect):
    """C (inline entry and out of line), Rust and Modula-2 print expect's
    lines for cases (coefficients, lo, hi), and both answers, a root and
    none, are well represented."""
    lines = "".join(R.RootsOp().wire({"coeffs": c, "lo": lo, "hi": hi}, k) + "\n" for k, (c, lo, hi) in enumerate(cases))
    outline = tmp_path / "testee_outline"
    run(["cc", "-std=c11", "-O2", "-ffp-contract=off", "-DM2C_NO_INLINE_ENTRY", "-Iinclude", "tools/m2c_testee.c",
         str(R.BUILD / "c" / "libm2c.a"), "-lgsl", "-lgslcblas", "-lm", "-o", str(outline)], C_RUNTIME)
    for cmd in (R.build_testee("c"), R.build_testee("rust"), R.build_testee("m2"), [str(outline)]):
        out = subprocess.run(cmd, input=lines, stdout=subprocess.PIPE, text=True, check=True).stdout.split("\n")
        bad = [(cases[k], out[k], expect[k]) for k in range(len(cases)) if out[k] != expect[k]]
        assert not bad, (cmd, len(bad), bad[:3])
    answered = sum(e.split()[1] != "none" for e in expect)
    assert 0.2 * len(cases) < answered < 0.8 * len(cases)  # both answers are well represented


def test_quadratic_shortcuts_same_bits(tmp_path):
    """The degree-2 fast path's shortcuts (C inline and out of line, Rust) and
    Modula-2's fast path (its admission from the bits, the written-out
    quadratic) return the bits of the Python reference, which takes the whole
    path."""
    from max2code_rt.roots import smallest_root
    cases = _quadratic_shortcut_cases(6000)
    expect = []
    for k, (c, lo, hi) in enumerate(cases):
        t = smallest_root(c, lo, hi)
        expect.append(f"{k} none" if t is None else f"{k} {R.hex_of(t)}")
    _every_runtime_answers(tmp_path, cases, expect)


def _poly_from_roots(roots, quad, scale):
    """Ascending coefficients of scale * prod(t - r) * (t^2 + quad[0] t + quad[1] if quad)."""
    c = [scale]
    for r in roots:
        c = [(c[i - 1] if i else 0.0) - r * (c[i] if i < len(c) else 0.0) for i in range(len(c) + 1)]
    if quad:
        p, q = quad
        c = [(c[i - 2] if i >= 2 else 0.0) + p * (c[i - 1] if 1 <= i <= len(c) else 0.0)
             + q * (c[i] if i < len(c) else 0.0) for i in range(len(c) + 2)]
    return c


def _no_root_test_cases(count: int, seed: int = 15) -> list[tuple[list[float], float, float]]:
    """Cubics and quartics aimed at the edge of degrees 3 and 4's no-root test
    (docs/roots.md step 1, "lo >= 0" (c)): a root just below 0 or just above hi,
    double roots inside, roots at -0.0, 0 and hi, complex pairs near the window,
    magnitudes 2^-500..2^500, hi 2^-40..2^40 (and below 2^-250, where hi^n
    underflows), lo = 0, -0.0 and inside, overflowing c_i hi^i, zero coefficients."""
    rng = random.Random(seed)
    cases = []
    for k in range(count):
        n = 3 + k % 2
        hi = rng.uniform(1.0, 2.0) * 2.0 ** rng.randint(-40, 40)
        kind = rng.randrange(9)
        eps = 2.0 ** -rng.randint(1, 52)
        near = [-hi * eps, hi * (1.0 + eps), -hi * rng.uniform(0.0, 3.0), hi * rng.uniform(1.0, 5.0)]
        roots = [rng.choice(near) for _ in range(n)]
        quad = None
        if kind == 0:            # a double root inside the window, the rest outside
            r = hi * rng.uniform(0.01, 0.99)
            roots[:2] = [r, r]
        elif kind == 1:          # a root at 0, -0.0 or hi
            roots[0] = rng.choice([0.0, -0.0, hi])
        elif kind == 2:          # a complex pair near the window (no real root there)
            roots = roots[:n - 2]
            x = hi * rng.uniform(-0.5, 1.5)
            quad = (-2.0 * x, x * x + (hi * rng.choice([eps, 0.1, 1.0])) ** 2)
        elif kind == 3:          # one root just inside
            roots[0] = hi * rng.choice([eps, 1.0 - eps, 0.5])
        c = _poly_from_roots(roots, quad, rng.choice([1.0, -1.0]) * 2.0 ** rng.randint(-500, 500))
        if kind == 4:            # zero coefficients
            for i in rng.sample(range(1, n + 1), rng.randint(1, n - 1)):
                c[i] = 0.0
        elif kind == 5:          # c_i hi^i overflows (or the sum of |t_i| does)
            hi = 2.0 ** rng.randint(20, 40)
            c[rng.randint(1, n)] = rng.choice([1.0, -1.0]) * 2.0 ** rng.randint(900, 1023)
        elif kind == 6:          # hi so small that hi^2..hi^4 underflow while some c_i is huge
            hi = rng.uniform(1.0, 2.0) * 2.0 ** rng.randint(-700, -240)
            c = [rng.choice([1.0, -1.0]) * 2.0 ** rng.randint(-800, -600)] + [0.0] * n
            c[rng.randint(1, n)] = -math.copysign(2.0 ** rng.randint(500, 1020), c[0])
        lo = rng.choice([0.0, 0.0, -0.0, hi * rng.uniform(0.0, 0.9), -hi * 0.5])
        cases.append((c, lo, hi))
    return cases


def test_no_root_test_same_bits(tmp_path):
    """Degrees 3 and 4's no-root test at the entry (lo >= 0, hi >= 2^-250; C,
    Rust, Modula-2, Python) changes no answer: every runtime prints the bits of
    the Python reference's path without the test (the per-degree entry and
    smallest_root's final checks), and the test answers a good share."""
    from max2code_rt import roots as py
    cases = _no_root_test_cases(6000)
    expect, fired = [], 0
    for k, (c, lo, hi) in enumerate(cases):
        t = py._ENTRY[len(c) - 1](list(c), lo, hi)
        t = None if t is None or not (lo < t <= hi) else t + 0.0
        expect.append(f"{k} none" if t is None else f"{k} {R.hex_of(t)}")
        got = py.smallest_root(c, lo, hi)
        assert expect[-1] == (f"{k} none" if got is None else f"{k} {R.hex_of(got)}"), (c, lo, hi)
        no_root = py._no_root3 if len(c) == 4 else py._no_root4
        fired += lo >= 0.0 and hi >= py._HI_MIN and no_root(*c, hi)
    _every_runtime_answers(tmp_path, cases, expect)
    assert fired > 0.15 * len(cases), fired               # the test answers a good share
