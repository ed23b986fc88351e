"""Generate the "roots" conformance cases (deterministic, fixed seed):

    python -m max2code.conformance.gencases [--out tests/conformance]

writes roots_hard.jsonl (hand-picked hard and degenerate inputs),
roots_random.jsonl (random polynomials of degree 1..16) and
roots_scaled.jsonl (any magnitude: roots from 1e-300 to 1e300, coefficients
across the whole double range; `--only scaled` writes just this one).  Reference answers
come from max2code.conformance.reference (exact rationals + mpmath), computed
from the exact double coefficients stored in the case.  The generated files are
committed, so a conformance run never needs mpmath.
"""
from __future__ import annotations

import argparse
import json
import math
import random
from fractions import Fraction
from multiprocessing import Pool
from pathlib import Path

from max2code.conformance.ops import num
from max2code.conformance.reference import reference
from max2code.paths import CASES

SEED = 20221117


def from_roots(roots, lead=1.0):
    """Ascending coefficients (rounded doubles) of lead * prod (t - r)."""
    c = [lead]
    for r in roots:
        nxt = [0.0] * (len(c) + 1)
        for i, v in enumerate(c):
            nxt[i + 1] += v
            nxt[i] -= r * v
        c = nxt
    return c


def times(c, d):
    out = [0.0] * (len(c) + len(d) - 1)
    for i, a in enumerate(c):
        for j, b in enumerate(d):
            out[i + j] += a * b
    return out


def enc(x: float):
    return x if math.isfinite(x) else ("nan" if math.isnan(x) else ("inf" if x > 0 else "-inf"))


def case(cid, coeffs, lo, hi, note=""):
    return {"id": cid, "op": "roots", "coeffs": [float(v) for v in coeffs], "lo": float(lo), "hi": float(hi),
            "note": note}


def hard_cases() -> list[dict]:
    out = []
    add = lambda *a: out.append(case(*a))  # noqa: E731
    # exact multiple roots (dyadic, so the doubles hold them exactly)
    add("double-d2", from_roots([0.5, 0.5]), 0.0, 1.0, "exact double root, touching")
    add("double-d3", from_roots([0.5, 0.5, -3.0]), 0.0, 2.0, "exact double root")
    add("double-d4-later", from_roots([0.25, 0.25, 0.75, 3.0]), 0.0, 1.0, "touching at 0.25 before a crossing")
    add("double-d5-touch-first", from_roots([0.375, 0.375, 0.625, 0.625, 2.0]), 0.0, 1.0, "two touchings")
    add("double-neg-lead", from_roots([0.5, 0.5, 0.75], -2.0), 0.0, 1.0, "negative leading coefficient")
    add("triple-d3", from_roots([0.5, 0.5, 0.5]), 0.0, 1.0, "exact triple root")
    add("triple-d4", from_roots([0.5, 0.5, 0.5, 5.0]), 0.0, 2.0, "exact triple root")
    add("triple-d6", from_roots([0.25, 0.25, 0.25, -1.0, 2.0, 3.0]), 0.0, 1.0, "exact triple root")
    add("quadruple-d5", from_roots([0.25] * 4 + [0.75]), 0.0, 1.0, "exact quadruple root (touching)")
    add("quadruple-d8", from_roots([0.625] * 4 + [-0.5, 2.0, 3.0, -4.0]), 0.0, 1.0, "exact quadruple root")
    add("double-at-hi", from_roots([1.0, 1.0, -2.0]), 0.0, 1.0, "double root exactly at hi")
    add("double-at-lo", from_roots([0.0, 0.0, 0.5]), 0.0, 1.0, "double root at lo (excluded), next root")
    # nearly multiple (rounded coefficients: mpmath decides on the exact doubles)
    for k, r in enumerate([0.3, 0.7, 0.1, 1.0 / 3.0]):
        add(f"near-double-{k}", from_roots([r, r, 2.5]), 0.0, 1.0, f"(t-{r})^2 (t-2.5), rounded")
        add(f"near-triple-{k}", from_roots([r, r, r, -1.5]), 0.0, 1.0, f"(t-{r})^3 (t+1.5), rounded")
    # clusters 1e-8 apart
    for deg in (3, 4, 6, 8):
        rs = [0.5, 0.5 + 1e-8] + [1.5 + 0.25 * k for k in range(deg - 2)]
        add(f"cluster-1e-8-d{deg}", from_roots(rs), 0.0, 1.0, "two roots 1e-8 apart")
    add("cluster3-1e-8-d5", from_roots([0.4, 0.4 + 1e-8, 0.4 + 2e-8, -1.0, 3.0]), 0.0, 1.0, "three roots 1e-8 apart")
    add("cluster-1e-8-above-lo", from_roots([0.25 + 1e-8, 0.25 + 2e-8, 3.0]), 0.25, 1.0, "cluster just above lo")
    # complex pairs near the real axis (no root)
    a = 2.0 ** -10
    pair = [a * a + 1e-18, -2.0 * a, 1.0]
    add("complex-1e-9-d2", pair, 0.0, 1.0, "(t-2^-10)^2 + (1e-9)^2: no real root")
    add("complex-1e-9-d4", times(pair, [-6.0, -1.0, 1.0]), 0.0, 1.0, "pair 1e-9 from the axis times (t-3)(t+2)")
    add("complex-1e-9-d6", times(times(pair, [-6.0, -1.0, 1.0]), [4.0, 0.0, 1.0]), 0.0, 1.0, "pair near axis, degree 6")
    add("complex-1e-9-then-root", times(pair, [-0.75, 1.0]), 0.0, 1.0, "pair near axis then a root at 0.75")
    pair2 = [0.25 + 1e-14, -1.0, 1.0]
    add("complex-1e-7-d2", pair2, 0.0, 1.0, "(t-1/2)^2 + 1e-14: pair 1e-7 from the axis")
    add("complex-1e-7-d5", times(pair2, from_roots([2.0, -3.0, 4.0])), 0.0, 1.0, "pair 1e-7 from the axis, degree 5")
    # roots near lo and hi
    add("root-at-lo", from_roots([0.25, 0.7, 2.0]), 0.25, 1.0, "root exactly at lo does not count")
    add("root-above-lo", from_roots([0.25 + 1e-12, 0.7, 2.0]), 0.25, 1.0, "root 1e-12 above lo")
    add("root-below-lo", from_roots([0.25 - 1e-12, 0.7, 2.0]), 0.25, 1.0, "root 1e-12 below lo")
    add("root-at-hi", from_roots([0.75, 1.5, -2.0]), 0.0, 0.75, "root exactly at hi counts")
    add("root-below-hi", from_roots([0.75 - 1e-12, 1.5, -2.0]), 0.0, 0.75, "root 1e-12 below hi")
    add("root-above-hi", from_roots([0.75 + 1e-12, 1.5, -2.0]), 0.0, 0.75, "root 1e-12 above hi")
    add("root-at-hi-d1", [-0.75, 1.0], 0.0, 0.75, "linear root at hi")
    add("root-at-lo-d1", [-0.25, 1.0], 0.25, 0.75, "linear root at lo")
    add("root-at-zero", from_roots([0.0, 1.0, 1.0]), -0.5, 0.5, "root exactly at 0 inside (lo, hi]")
    add("root-at-zero-lo", from_roots([0.0, 0.5, 2.0]), 0.0, 1.0, "root at lo = 0 excluded")
    # tiny leading coefficient
    add("tiny-lead-d3", [-0.5, 1.0, 0.25, 1e-15], 0.0, 1.0, "leading coefficient 1e-15 of the others")
    add("tiny-lead-d3-far", [-0.5, 1.0, 0.25, 1e-15], -1e16, 1.0, "the large root of a 1e-15 leading coefficient")
    add("tiny-lead-d5", [0.3, -1.2, 0.5, 0.7, -0.2, 1e-15], 0.0, 1.0, "degree 5, leading 1e-15")
    add("tiny-lead-d8", from_roots([0.2, 0.4, 0.6, 0.8, 1.5, -1.0, 2.0], 1.0) + [1e-15], 0.0, 1.0,
        "degree 8, leading 1e-15")
    add("tiny-lead-d2", [-0.5, 1.0, 1e-15], 0.0, 1.0, "quadratic, leading 1e-15")
    add("tiny-lead-d2-far", [-0.5, 1.0, 1e-15], -2e15, 0.0, "quadratic, the far root")
    # roots spread 1e-6 .. 1e6
    spread = [1e-6, 1e-3, 1.0, 1e3, 1e6]
    add("spread-d5", from_roots(spread), 0.0, 1e7, "roots 1e-6 .. 1e6")
    add("spread-d5-skip", from_roots(spread), 1e-5, 1e7, "roots 1e-6 .. 1e6, first excluded")
    add("spread-d5-big", from_roots(spread), 10.0, 1e7, "roots 1e-6 .. 1e6, from 10")
    add("spread-d5-last", from_roots(spread), 1e4, 1e7, "roots 1e-6 .. 1e6, the last")
    add("spread-d7", from_roots([1e-6, -1e-4, 1e-2, 1.0, -1e2, 1e4, 1e6]), 0.0, 1e7, "roots +-1e-6 .. 1e6")
    add("spread-d10", from_roots([10.0 ** k for k in range(-6, 4)]), 1e-5, 1e7, "roots 1e-6 .. 1e3, degree 10")
    # scaling by 1e-200 and 1e200
    bases = {
        "d3": (from_roots([0.2, 0.45, 3.0]), 0.0, 1.0),
        "d6": (from_roots([0.35, 0.6, -1.0, 2.0, 0.9, 4.0], -3.0), 0.0, 1.0),
        "double": (from_roots([0.5, 0.5, 0.75]), 0.0, 1.0),
        "complex": (times(pair, [-6.0, -1.0, 1.0]), 0.0, 1.0),
        "d2": ([0.06, -0.5, 1.0], 0.0, 1.0),
        "d1": ([-0.3, 1.0], 0.0, 1.0),
    }
    for name, (c, lo, hi) in bases.items():
        for s, tag in ((1e-200, "1e-200"), (1e200, "1e200"), (2.0 ** -1000, "2^-1000")):
            add(f"scaled-{tag}-{name}", [v * s for v in c], lo, hi, f"{name} times {tag}")
    # high degree
    add("wilkinson-d16", from_roots([0.05 * (k + 1) for k in range(16)]), 0.0, 1.0, "roots 0.05 .. 0.8")
    add("wilkinson-d16-mid", from_roots([0.05 * (k + 1) for k in range(16)]), 0.42, 1.0, "roots 0.05 .. 0.8 from 0.42")
    add("chebyshev-like-d16", [(-1.0) ** k / (k + 1) for k in range(17)], -1.0, 1.0, "alternating coefficients")
    add("power-d16", [-(2.0 ** -16)] + [0.0] * 15 + [1.0], 0.0, 1.0, "t^16 - 2^-16: root 1/2")
    add("power-d9-neg", [2.0 ** -9] + [0.0] * 8 + [1.0], -1.0, 0.0, "t^9 + 2^-9: root -1/2")
    add("no-root-d8", [1.0 + k * 0.125 for k in range(9)], 0.0, 1.0, "positive coefficients, no root on (0,1]")
    add("no-root-d12-wiggle", times(from_roots([1.2, 1.3, 1.4, 1.5, 1.6]), [2.0, 0.0, 1.0] * 1)
        + [0.0] * 5, -1.0, 1.0, "wiggles outside the interval, trailing zero coefficients")
    # degenerate inputs
    nan, inf = math.nan, math.inf
    add("degenerate-all-zero", [0.0, 0.0, 0.0, 0.0], 0.0, 1.0, "identically zero: none")
    add("degenerate-empty", [], 0.0, 1.0, "no coefficients: none")
    add("degenerate-constant", [2.5], 0.0, 1.0, "nonzero constant: none")
    add("degenerate-constant-padded", [2.5, 0.0, -0.0, 0.0], 0.0, 1.0, "constant with zero top coefficients")
    add("degenerate-zero-top-d1", [-0.5, 1.0, 0.0, 0.0, 0.0], 0.0, 1.0, "zero top coefficients dropped")
    add("degenerate-zero-top-d3", from_roots([0.2, 0.4, 0.9]) + [0.0] * 13, 0.0, 1.0, "degree 16 with 13 zero tops")
    add("degenerate-negzero-top", [-0.5, 1.0, -0.0], 0.0, 1.0, "-0.0 top coefficient dropped")
    add("degenerate-nan-coeff", [-0.5, nan, 1.0], 0.0, 1.0, "NaN coefficient")
    add("degenerate-inf-coeff", [-0.5, 1.0, inf], 0.0, 1.0, "infinite coefficient")
    add("degenerate-neginf-coeff", [-inf, 1.0, 1.0], 0.0, 1.0, "-inf coefficient")
    add("degenerate-nan-lo", [-0.5, 1.0], nan, 1.0, "NaN lo")
    add("degenerate-nan-hi", [-0.5, 1.0], 0.0, nan, "NaN hi")
    add("degenerate-inf-hi", [-0.5, 1.0], 0.0, inf, "infinite hi")
    add("degenerate-neginf-lo", [-0.5, 1.0], -inf, 1.0, "-inf lo")
    add("degenerate-lo-eq-hi", [-0.5, 1.0], 0.5, 0.5, "lo == hi")
    add("degenerate-lo-gt-hi", from_roots([0.5, 0.6, 0.7]), 1.0, 0.0, "lo > hi")
    add("degenerate-huge-range", from_roots([0.5, 0.6, 0.7]), -1e308, 1e308, "huge but finite interval")
    add("degenerate-subnormal-coeffs", [-5e-324, 1e-323, 0.0, 5e-324], 0.0, 1.0, "subnormal coefficients")
    add("degenerate-overflowing", [1e308, -1e308, 1e308, -1e308], 0.0, 2.0, "coefficients near overflow")
    add("degenerate-lead-underflow", [1e300, -1e300, 1e-300], 0.0, 2.0, "leading coefficient 1e-600 relative")
    for c in out:
        c["coeffs"] = [enc(v) for v in c["coeffs"]]
        c["lo"], c["hi"] = enc(c["lo"]), enc(c["hi"])
    return out


def random_cases(per_degree: int = 150) -> list[dict]:
    rng = random.Random(SEED)
    out = []
    for deg in range(1, 17):
        for k in range(per_degree):
            kind = k % 3
            if kind == 0:
                # random coefficients, random sign pattern, interval (0, 1]
                c = [rng.gauss(0.0, 1.0) for _ in range(deg + 1)]
                lo, hi, note = 0.0, 1.0, "gaussian coefficients"
            elif kind == 1:
                # known roots: some inside (0, 1], some outside, complex pairs
                rs, c = [], [rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 10.0)]
                left = deg
                while left > 0:
                    if left >= 2 and rng.random() < 0.3:
                        re, im = rng.uniform(-1.0, 2.0), rng.uniform(0.01, 1.0)
                        c = times(c, [re * re + im * im, -2.0 * re, 1.0])
                        left -= 2
                    else:
                        r = rng.uniform(-1.0, 2.0)
                        rs.append(r)
                        c = times(c, [-r, 1.0])
                        left -= 1
                lo, hi, note = 0.0, 1.0, "random real roots and complex pairs"
            else:
                # random interval and scale
                c = [rng.uniform(-1.0, 1.0) * 10.0 ** rng.randint(-3, 3) for _ in range(deg + 1)]
                lo = rng.uniform(-2.0, 1.0)
                hi = lo + 10.0 ** rng.uniform(-2.0, 1.0)
                note = "uniform coefficients of mixed magnitude, random interval"
            out.append(case(f"random-d{deg}-{k:03d}", c, lo, hi, note))
    return out


def exact_poly(roots, lead, pairs=()):
    """Exact rational coefficients of lead * prod (t - r) * prod ((t - re)^2 + im^2)."""
    c = [Fraction(lead)]
    factors = [[-Fraction(r), Fraction(1)] for r in roots]
    for re, im in pairs:
        re, im = Fraction(re), Fraction(im)
        factors.append([re * re + im * im, -2 * re, Fraction(1)])
    for f in factors:
        out = [Fraction(0)] * (len(c) + len(f) - 1)
        for i, a in enumerate(c):
            for j, b in enumerate(f):
                out[i + j] += a * b
        c = out
    return c


def _log10(x: Fraction) -> float:
    return math.log10(abs(x.numerator)) - math.log10(x.denominator)


def _doubles(c, rng, window=307.0):
    """The coefficients rounded to doubles after a power of ten that puts the
    largest and the smallest nonzero magnitude at a random place inside
    10^(+-window); None when they span more than the window allows."""
    logs = [_log10(v) for v in c if v != 0]
    lo_, hi_ = min(logs), max(logs)
    if hi_ - lo_ > 2 * window:
        return None
    k = round(rng.uniform(-window - lo_, window - hi_))
    f = Fraction(10) ** k if k >= 0 else Fraction(1, 10 ** -k)
    return [float(v * f) for v in c]


def scaled_cases(per_degree: int = 12) -> list[dict]:
    """Any magnitude: hand-picked classics, then per degree 1..16
    polynomials with roots of one magnitude from 1e-300 to 1e300 or of
    magnitudes spread as far as the coefficients allow, moderate roots with t
    scaled by a power of ten (coefficients across the double range), and for
    degrees up to 4 independent coefficients from 1e-307 to 1e307.  Each case
    carries `scale10`, the power of ten near its roots, for the reference
    (dropped from the file)."""
    rng = random.Random(SEED + 11)
    out = []

    def add(cid, coeffs, lo, hi, note, scale10):
        c = case(cid, coeffs, lo, hi, note)
        c["scale10"] = scale10
        out.append(c)

    big = 1.7976931348623157e308
    quartic = [float(v) for v in exact_poly([1e80, 1e77, 1e76, 1e75], 1e-307)]
    add("mag-quartic-1e80", quartic, 0.0, 1e300, "coefficients 1e-307 .. 1e1, roots 1e75 .. 1e80", 77)
    add("mag-quartic-1e80-last", quartic, 2e77, 1e300, "the root near 1e80", 77)
    add("mag-quartic-1e80-none", quartic, -1e300, 1e70, "no root below 1e75", 77)
    add("mag-quartic-1e-80", [float(v) for v in exact_poly([1e-80, 1e-77, 1e-76, 1e-75], 1e300)],
        0.0, 1.0, "roots 1e-80 .. 1e-75", -77)
    q = [float(v) for v in exact_poly([1e-300, 1e300], 1.0)]
    add("mag-quadratic-1e-300-1e300", q, 0.0, big, "roots 1e-300 and 1e300", 0)
    add("mag-quadratic-1e300", q, 1.0, big, "roots 1e-300 and 1e300, the large one", 0)
    add("mag-pm-1e-300", [-1e-300, 0.0, 1e300], 0.0, 1.0, "1e300 t^2 - 1e-300: roots +-1e-300", -300)
    add("mag-pm-1e-300-neg", [-1e-300, 0.0, 1e300], -1.0, 1.0, "1e300 t^2 - 1e-300: the negative root", -300)
    add("mag-complex-1e-300", [2e-300, 0.0, 1e300], -1.0, 1.0, "1e300 t^2 + 2e-300: a pair at 1.4e-300 i", -300)
    add("mag-linear-tiny", [-1e-300, 1e8], 0.0, 1.0, "root 1e-308", -308)
    add("mag-linear-huge", [-1e300, 1e-7], 0.0, big, "root 1e307", 307)
    d3 = [float(v) for v in exact_poly([1e-300, 1.0, 1e300], 1.0)]
    add("mag-d3-1e-300-1-1e300", d3, 0.0, big, "roots 1e-300, 1, 1e300", 0)
    add("mag-d3-1e-300-1-1e300-mid", d3, 1e-200, big, "roots 1e-300, 1, 1e300: from 1e-200", 0)
    add("mag-d3-1e-300-1-1e300-neg", [float(v) for v in exact_poly([-1e-300, -1.0, -1e300], 1.0)], -big, 0.0,
        "roots -1e300, -1, -1e-300", 0)
    add("mag-d5-zero-root", [0.0] + [float(v) for v in exact_poly([1e-50, 2e-50, 1e50, 3e50], 1e-10)],
        -1.0, 1e300, "t (t - 1e-50)(t - 2e-50)(t - 1e50)(t - 3e50): 0 first", 0)
    add("mag-d16-1e18", [float(v) for v in exact_poly([1e18 * (k + 1) for k in range(16)], 1.0)], 0.0, 1e300,
        "roots 1e18 .. 1.6e19, degree 16 (beyond 2^(900/16))", 19)
    add("mag-quartic-pm-1e55", [2.6612249000050942e+110, 0.0, -3.3265311250063676, 0.0, 6.653062250012736e-111],
        0.0, big, "roots +-1e55, +-2e55 (hypothesis): one scale, 4AC of p'' underflows unscaled", 55)
    for deg in range(1, 17):
        for k in range(per_degree):
            kind = k % 4
            if kind == 2 and deg > 4:
                kind = 0
            if kind in (0, 1):
                # real roots and complex pairs of one magnitude (kind 0) or spread (kind 1)
                while True:
                    centre = rng.uniform(-300.0, 300.0)
                    spread = 0.0 if kind == 0 else rng.uniform(0.0, min(20.0, 600.0 / deg))
                    mag = lambda: 10.0 ** max(-300.0, min(300.0, centre + rng.uniform(-0.5, 0.5) * spread))  # noqa
                    rs, pairs, left = [], [], deg
                    while left > 0:
                        if left >= 2 and rng.random() < 0.25:
                            m = mag()
                            pairs.append((m * rng.uniform(-1.0, 1.0), m * rng.uniform(0.01, 1.0)))
                            left -= 2
                        else:
                            rs.append(rng.choice([-1.0, 1.0]) * mag() * rng.uniform(1.0, 2.0))
                            left -= 1
                    c = _doubles(exact_poly(rs, rng.choice([-1.0, 1.0]), pairs), rng)
                    if c is not None and c[-1] != 0.0:
                        break
                note = f"roots near 1e{centre:.0f}" + (f", spread 1e{spread:.0f}" if spread else "")
                if rs and rng.random() < 0.6:
                    r = rng.choice(rs)
                    lo, hi = sorted((r * 0.5, r * 2.0))
                    note += ", interval around a root"
                elif rng.random() < 0.5:
                    lo, hi = 0.0, big
                else:
                    lo, hi = -big, big
                s10 = round(centre)
            elif kind == 2:
                # independent coefficients across the whole double range
                c = [rng.choice([-1.0, 1.0]) * rng.uniform(1.0, 10.0) * 10.0 ** rng.uniform(-307.0, 307.0)
                     for _ in range(deg + 1)]
                lo, hi, note, s10 = 0.0, big, "coefficients 1e-307 .. 1e307", 0
            else:
                # a polynomial of moderate roots scaled in t: p(t / 10^k), coefficients over the range
                s10 = round(rng.uniform(-1.0, 1.0) * min(300.0, 600.0 / deg))
                rs = [rng.uniform(-1.0, 2.0) for _ in range(deg)]
                base = exact_poly(rs, 1.0)
                f10 = Fraction(10) ** s10 if s10 >= 0 else Fraction(1, 10 ** -s10)
                c = _doubles([v / f10 ** i for i, v in enumerate(base)], rng)
                if c is None or c[-1] == 0.0:
                    raise AssertionError("the scaled coefficients must fit")
                lo, hi = 0.0, float(f10)
                note = f"roots in (-1, 2] times 1e{s10}, interval (0, 1e{s10}]"
            add(f"mag-d{deg}-{k:03d}", c, lo, hi, note, s10)
    return out


def _with_reference(c: dict) -> dict:
    coeffs = [num(v) for v in c["coeffs"]]
    if c["id"].startswith("mag-"):
        e = c.pop("scale10")
        scale = Fraction(10) ** e if e >= 0 else Fraction(1, 10 ** -e)
        try:
            ref = reference(coeffs, num(c["lo"]), num(c["hi"]), floor=5e-324, limit=1.7976931348623157e308,
                            scale=scale)
        except RuntimeError:
            return {"id": c["id"], "dropped": True}   # no certain reference: the case is left out
    else:
        ref = reference(coeffs, num(c["lo"]), num(c["hi"]))
    c = dict(c)
    c["expect"] = ref["expect"]
    c["roots"] = ref["roots"]
    return c


def write(path: Path, cases: list[dict], jobs: int) -> None:
    with Pool(jobs) as pool:
        done = pool.map(_with_reference, cases, chunksize=8)
    dropped = [c["id"] for c in done if c.get("dropped")]
    if dropped:
        print(f"left out (no certain reference): {', '.join(dropped)}")
    done = [c for c in done if not c.get("dropped")]
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        for c in done:
            fh.write(json.dumps(c, allow_nan=False) + "\n")
    print(f"wrote {len(done)} cases to {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=CASES)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--per-degree", type=int, default=150)
    ap.add_argument("--only", choices=("hard", "random", "scaled"), help="write only this file")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.only in (None, "hard"):
        write(args.out / "roots_hard.jsonl", hard_cases(), args.jobs)
    if args.only in (None, "random"):
        write(args.out / "roots_random.jsonl", random_cases(args.per_degree), args.jobs)
    if args.only in (None, "scaled"):
        write(args.out / "roots_scaled.jsonl", scaled_cases(), args.jobs)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
