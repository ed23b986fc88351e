"""The two circles' whole-horizon bound of the exact-motion driver
(docs/exact-motion.md, "Two circles: the whole-horizon bound"): where the
bound polynomial H exceeds its margin the exact gap (mpmath) is positive, so
the bound never declares no contact where there is one; the generator finds
the circles' layout only where Maxima proves the gap; and the driver's
answers with the bound are those without it wherever the windows it skips
hold no contact (bit for bit with orbits; without orbits, where the driver
solves the gap's own polynomial, to the last bits)."""
from __future__ import annotations

import dataclasses
import json
import math
import os
import random
from pathlib import Path

import mpmath
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from max2code.conformance.exact_cases import _aim
from max2code.conformance.exact_ref import DPS, Gap, reference
from max2code.generate.pipeline import GenerateRequest, generate_file

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
CC = "abcdefmnopqghijklrsuvwxz"


@pytest.fixture(scope="module")
def circles_py():
    g = generate_file(GenerateRequest(path=str(ROOT / "equations" / "circle-circle.mxm"), lang="python",
                                      out_name="generated", exact=True))
    ns: dict = {}
    exec(compile(g.text, "generated.py", "exec"), ns)
    return g, ns


def test_layout_is_found_and_proved(circles_py):
    g, ns = circles_py
    # per body: x, y position; x, y velocity; x, y acceleration; orbit radius; x term's rate and
    # phase; y term's; radius (equations/circle-circle.mxm's letters)
    assert [CC[i] for i in g.exact.circles] == list("ambncodefpqxgrhsiujklvwz")
    assert tuple(ns["CIRCLE_CIRCLE_MOTION"].circles) == g.exact.circles
    pl = generate_file(GenerateRequest(path=str(ROOT / "equations" / "point-line.mxm"), lang="python",
                                       out_name="generated", exact=True))
    assert pl.exact.circles is None


@pytest.mark.slow
def test_float_code_has_no_bound():
    g = generate_file(GenerateRequest(path=str(ROOT / "equations" / "circle-circle.mxm"), lang="c",
                                      out_name="generated", exact=True, real="float"))
    assert "circle_circle_circles" not in g.text
    d = generate_file(GenerateRequest(path=str(ROOT / "equations" / "circle-circle.mxm"), lang="c",
                                      out_name="generated", exact=True))
    assert "static const int circle_circle_circles[24]" in d.text


finite = st.floats(-4.0, 4.0, allow_nan=False)
rates = st.floats(-6.0, 6.0, allow_nan=False)


@st.composite
def circle_params(draw):
    p = {}
    for pos, vel, acc, rad, w1, ph1, posy, vely, accy, w2, ph2 in (tuple("abcdefmnopq"), tuple("ghijklrsuvw")):
        circular = draw(st.booleans())
        w = draw(rates)
        ph = draw(st.floats(-3.2, 3.2))
        p.update({pos: draw(finite), vel: draw(finite), acc: draw(st.floats(-1, 1)),
                  rad: draw(st.sampled_from([0.0, draw(st.floats(0.0, 1.5))])),
                  w1: w, ph1: ph + math.pi / 2 if circular else draw(st.floats(-3.2, 3.2)),
                  posy: draw(finite), vely: draw(finite), accy: draw(st.floats(-1, 1)),
                  w2: w if circular else draw(rates), ph2: ph})
    p["x"], p["z"] = draw(st.floats(0.0, 1.5)), draw(st.floats(0.0, 1.5))
    return p


@settings(max_examples=300, deadline=None)
@given(circle_params(), st.floats(0.1, 10.0), st.floats(0.0, 1.0))
def test_the_gap_is_positive_where_the_bound_is(p, T, frac):
    """H(t) > margin implies the exact gap (40 digits) is positive at t."""
    from max2code_rt.exact import _circles_bound, _value

    ix = [CC.index(c) for c in "ambncodefpqxgrhsiujklvwz"]
    vec = [p[c] for c in CC]
    h, _, margin, _ = _circles_bound(ix, vec, T)
    t = frac * T
    if _value(h, 4, t) > margin:
        gp = Gap("circle-circle", p, T)
        with mpmath.workdps(DPS):
            assert gp.G(mpmath.mpf(t)) > 0


def _same_answer(new, old, p: dict) -> bool:
    """The driver's answer with the circles' layout is the windowed one: the
    same bits when a body orbits; without orbits (the gap's own polynomial,
    solved once) the same answer to 2^-40 relative."""
    if p["d"] != 0.0 or p["j"] != 0.0 or not (isinstance(new, float) and isinstance(old, float)):
        return new == old
    return abs(new - old) <= 2.0 ** -40 * max(abs(old), 1e-300)


def _draw(rng: random.Random) -> tuple[dict, float]:
    """Two circles on circular orbits (or none), aimed at each other or not."""
    p = {}
    for b in ("abcdefmnopq", "ghijklrsuvw"):
        a, bv, c, d, e, f, m, n, o, pw, q = b
        w = rng.uniform(-3, 3)
        ph = rng.uniform(-3.1, 3.1)
        orbit = rng.random() < 0.8
        p.update({a: rng.uniform(-5, 5), bv: rng.uniform(-3, 3), c: rng.uniform(-1, 1) * (rng.random() < 0.5),
                  d: rng.uniform(0.1, 1.0) if orbit else 0.0, e: w, f: ph + math.pi / 2, m: rng.uniform(-5, 5),
                  n: rng.uniform(-3, 3), o: 0.0, pw: w, q: ph})
    p["x"], p["z"] = rng.uniform(0.1, 1.0), rng.uniform(0.1, 1.0)
    T = rng.choice([1.0, 3.0, 8.0])
    if rng.random() < 0.5:
        p = _aim(rng, p, "circle-circle", T, 1.3)
    return p, T


def test_bound_never_hides_a_contact_and_keeps_the_answers(circles_py):
    """On drawn circle pairs: whenever the driver with the bound answers none,
    the reference allows none, and every answer is the windows-only driver's
    (_same_answer)."""
    from max2code_rt.exact import exact_toc

    _, ns = circles_py
    motion = ns["CIRCLE_CIRCLE_MOTION"]
    plain = dataclasses.replace(motion, circles=None)
    rng = random.Random(3131)
    decided = 0
    for _ in range(60):
        p, T = _draw(rng)
        vec = [p[c] for c in CC]
        new = exact_toc(motion, vec, T)
        old = exact_toc(plain, vec, T)
        ref = reference("circle-circle", p, T)
        if ref.expect == "overlapped":
            assert new == old == "overlapped"
            continue
        for ans in (new, old):
            if ans is None:
                assert ref.none_ok
            else:
                assert any(lo <= ans <= hi for lo, hi in ref.accept) or abs(ans - ref.expect) <= 1e-12 * ref.expect
        assert _same_answer(new, old, p)
        decided += new is None
    assert decided >= 10


def test_conformance_cases_keep_their_bits(circles_py):
    """Every circle-circle case of tests/conformance/toc_exact.jsonl, refined
    and not: the same answer with and without the bound (_same_answer)."""
    from max2code_rt.exact import exact_toc

    _, ns = circles_py
    motion = ns["CIRCLE_CIRCLE_MOTION"]
    plain = dataclasses.replace(motion, circles=None)
    n = 0
    with open(ROOT / "tests" / "conformance" / "toc_exact.jsonl") as f:
        for line in f:
            c = json.loads(line)
            if c["equation"] != "circle-circle":
                continue
            vec = [c["params"][k] for k in CC]
            for refine in (True, False):
                o = dict(c.get("options") or {}, refine=refine)
                new = exact_toc(motion, vec, c["horizon"], **o)
                old = exact_toc(plain, vec, c["horizon"], **o)
                assert _same_answer(new, old, c["params"]), (c["id"], new, old)
            n += 1
    assert n > 150


def _face_each_other(p, D, dist, t):
    """Turn both circular orbits (radii at least 0.05) so that at time t
    each offset points at the other circle along D, the centres' difference
    without orbits (length dist): the orbits' whole reach closes the gap.
    The radii, or None when the circles are too close for it."""
    d1, d2 = max(p["d"], 0.05), max(p["j"], 0.05)
    if dist < d1 + d2 + 0.1:
        return None
    ux, uy = D[0] / dist, D[1] / dist
    for rad, w, f, wy, q, sign, dk in (("d", "e", "f", "p", "q", -1.0, d1), ("j", "k", "l", "v", "w", 1.0, d2)):
        p[rad] = dk
        p[wy] = p[w]
        p[q] = math.atan2(sign * uy, sign * ux) - (p[w] * t if t else 0.0)
        p[f] = p[q] + math.pi / 2
    return d1, d2


@settings(max_examples=200, deadline=None)
@given(circle_params(), st.floats(0.1, 10.0), st.floats(0.0, 1.0), st.floats(-1e-3, 1e-3))
def test_the_bound_is_tight_where_the_orbits_face_each_other(p, T, frac, slack):
    """Circular orbits turned so that at time t both offsets point at the
    other circle, radii so that the circles overlap (slack > 0) or miss
    (slack < 0) by |slack| there: H(t) > margin only where they miss, and
    that is the only way H can exceed its margin at t, so a bound weaker
    than the orbits' reach fails here."""
    from max2code_rt.exact import _circles_bound, _value

    t = frac * T
    D = [(p[a] + p[b] * t + p[c] * t * t / 2) - (p[g] + p[h] * t + p[i] * t * t / 2)
         for a, b, c, g, h, i in (("a", "b", "c", "g", "h", "i"), ("m", "n", "o", "r", "s", "u"))]
    dist = math.hypot(*D)
    radii = _face_each_other(p, D, dist, t)
    if radii is None:
        return
    d1, d2 = radii
    total = dist - d1 - d2 + slack
    p["x"], p["z"] = 0.4 * total, 0.6 * total
    ix = [CC.index(c) for c in "ambncodefpqxgrhsiujklvwz"]
    h, _, margin, _ = _circles_bound(ix, [p[c] for c in CC], T)
    gp = Gap("circle-circle", p, T)
    with mpmath.workdps(DPS):
        g = gp.G(mpmath.mpf(t))
    if _value(h, 4, t) > margin:
        assert g > 0
    elif slack < -1e-9:
        assert g > 0     # a miss that the bound leaves to the windows


@settings(max_examples=300, deadline=None)
@given(circle_params())
def test_the_circles_rate_is_the_generated_rate(circles_py, p):
    """The driver's window rate for two circles (the orbiting bodies'
    |angular velocities|, no sine) is the generated NAME_rate to the bit."""
    from max2code_rt.exact import _circles_rate

    g, ns = circles_py
    vec = [p[c] for c in CC]
    assert _circles_rate(g.exact.circles, vec) == ns["CIRCLE_CIRCLE_MOTION"].rate(vec)


@settings(max_examples=300, deadline=None)
@given(circle_params(), st.floats(-1e-3, 1e-3), st.booleans())
def test_the_gap_at_zero_is_above_its_lower_bound(p, slack, facing):
    """The lower bound on the gap at t = 0 with which the rules at t = 0
    skip the exact gap is below the gap (40 digits); with both orbit
    offsets turned at t = 0 towards the other circle (facing) it is within
    |slack| of it, so a bound that ignored the orbits' reach fails here."""
    from max2code_rt.exact import _circles_bound, _clear_at_zero

    ix = [CC.index(c) for c in "ambncodefpqxgrhsiujklvwz"]
    D = [p["a"] - p["g"], p["m"] - p["r"]]
    dist = math.hypot(*D)
    if facing:
        radii = _face_each_other(p, D, dist, 0.0)
        if radii is None:
            return
        d1, d2 = radii
        total = dist - d1 - d2 + slack
        if total <= 0.0:
            return
        p["x"], p["z"] = 0.4 * total, 0.6 * total
    _, d, _, rho = _circles_bound(ix, [p[c] for c in CC], 1.0)
    lo = _clear_at_zero(d, rho)
    with mpmath.workdps(DPS):
        g = Gap("circle-circle", p, 1.0).G(mpmath.mpf(0))
        assert lo <= g
        if facing and lo > 0.0:
            assert g - lo < 4 * abs(slack) * total + 1e-9


def _still_draw(rng: random.Random) -> tuple[dict, float]:
    """Two circles without orbits (the angular velocities and phases drawn
    all the same, the radii zero): apart, aimed at each other, inside each
    other, or touching at t = 0 along x (the gap there is zero exactly)."""
    p, T = _draw(rng)
    p["d"] = p["j"] = 0.0
    kind = rng.randrange(4)
    if kind == 2:       # inside each other
        p["g"], p["r"] = p["a"] + 0.1 * p["x"], p["m"]
    elif kind == 3:     # touching at t = 0, moving together or apart
        p["g"], p["r"] = p["a"] + (p["x"] + p["z"]), p["m"]
        p["h"] = p["b"] + rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0)
    return p, T


@pytest.mark.slow
def test_a_non_finite_parameter_answers_none_without_orbits(circles_py, tmp_path):
    """Without orbits the C and Rust drivers test the parameters' finiteness
    only before an answer other than none: on drawn pairs that touch, meet,
    miss or overlap, any one parameter (used by the gap or not) made an
    infinity or a NaN gives none in C, Rust and Python; the finite pairs give
    the same bits in the three."""
    from max2code.toolchain.exact import build_exact_harness

    _, ns = circles_py
    py_toc = ns["circle_circle_toc_exact"]
    rng = random.Random(2718)
    finite, broken = [], []
    for _ in range(40):
        p, T = _still_draw(rng)
        finite.append((p, T))
        for _ in range(3):
            q = dict(p)
            q[rng.choice(CC)] = rng.choice([math.inf, -math.inf, math.nan])
            broken.append((q, T))
    rows = [[p[c] for c in CC] + [T, 1.0, 1.0, 0.0, 0.0] for p, T in finite + broken]
    answers = {}
    for lang in ("c", "rust"):
        g = generate_file(GenerateRequest(path=str(ROOT / "equations" / "circle-circle.mxm"), lang=lang,
                                          out_name="generated", exact=True))
        h = build_exact_harness(lang, g.text, g.exact, str(tmp_path / lang))
        answers[lang], _ = h.run(rows)
    py = []
    for p, T in finite + broken:
        a = py_toc(*[p[c] for c in CC], T)
        py.append((0, 0.0) if a is None else (2, 0.0) if a == "overlapped" else (1, a))
    n = len(finite)
    assert answers["c"][:n] == answers["rust"][:n] == py[:n]
    assert {st for st, _ in py[:n]} == {0, 1, 2}     # the draws reach none, contact and overlapped
    for lang, got in (("c", answers["c"]), ("rust", answers["rust"]), ("python", py)):
        assert all(st == 0 for st, _ in got[n:]), lang
