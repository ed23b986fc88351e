"""The equations in tests/data/equations/, each written a second time here in
plain Python (refpoly: exact polynomials in Fractions, no Maxima, nothing of
the generator), and every generated variant compared with that independent
expansion, its conditions substituted, at random rational points."""
import os
import random
from fractions import Fraction

import pytest

from conftest import ROOT
from max2code.generate.pipeline import GenerateRequest, generate_file
from refpoly import V, compare, cos_of, run_python, sin_of, substitute_zeros, trig_env

pytestmark = pytest.mark.slow      # runs Maxima on every variant of each fixture

DATA = os.path.join(ROOT, "tests", "data", "equations")
T = V("t")


def moving(p, v=None, a=None):
    x = V(p)
    if v:
        x = x + V(v) * T
    if a:
        x = x + Fraction(1, 2) * V(a) * T ** 2
    return x


def spheres_3d(order):
    d = [moving(f"a{c}", f"av{c}", f"aa{c}") - moving(f"b{c}", f"bv{c}", f"ba{c}") for c in "xyz"]
    return d[0] ** 2 + d[1] ** 2 + d[2] ** 2 - (V("ra") + V("rb")) ** 2


def arena(order):
    dx = moving("px", "vx", "gx") - (V("cx") + V("ro") * cos_of("wo", "fo", order))
    dy = moving("py", "vy", "gy") - (V("cy") + V("ro") * sin_of("wo", "fo", order))
    return (V("big") - V("r")) ** 2 - (dx ** 2 + dy ** 2)


def segment_end(order):
    dx = moving("qx", "ux", "gx") - (V("sx") + V("hl") * cos_of("om", "ph", order))
    dy = moving("qy", "uy", "gy") - (V("sy") + V("hl") * sin_of("om", "ph", order))
    return dx ** 2 + dy ** 2 - V("rc") ** 2


def orbiting_circles(order):
    dx = moving("x1", "u1") - (moving("x2", "u2", "a2") + V("d2") * cos_of("w2", "f2", order))
    dy = moving("yp1", "v1") - (moving("y2", "v2", "b2") + V("d2") * sin_of("w2", "f2", order))
    return dx ** 2 + dy ** 2 - (V("r1") + V("r2")) ** 2


def quintic_floor(order):
    height = moving("h0", "v0", "a0") + Fraction(1, 6) * V("k0") * T ** 3 + Fraction(1, 24) * V("s0") * T ** 4 \
        + Fraction(1, 120) * V("c0") * T ** 5
    floor = V("hf") + V("vf") * T + V("bf") * sin_of("wf", "pf", order)
    return height - V("rp") - floor


REFERENCES = {"spheres-3d": spheres_3d, "arena": arena, "segment-end": segment_end,
              "orbiting-circles": orbiting_circles, "quintic-floor": quintic_floor}
# (file, Taylor order): each default, order 8 for all, and the spinning segment at 6, 7, 8
CASES = [("spheres-3d", None), ("arena", 5), ("arena", 8), ("segment-end", 6), ("segment-end", 7),
         ("segment-end", 8), ("orbiting-circles", 3), ("orbiting-circles", 8), ("quintic-floor", 7),
         ("quintic-floor", 8)]


def generate(name, order, **kw):
    options = {"order": str(order)} if order is not None else {}
    return generate_file(GenerateRequest(path=os.path.join(DATA, f"{name}.mxm"), lang="python",
                                         options=options, out_name="generated.py", **kw))


def random_point(params, rng):
    """Random doubles with few bits (exact Fractions), none zero, magnitudes 1/16 .. 2."""
    return {p: Fraction(rng.choice([-1, 1]) * rng.randint(2, 64), 32) for p in params}


@pytest.mark.parametrize("name,order", CASES, ids=[f"{n}-{o}" for n, o in CASES])
def test_every_variant_matches_an_independent_expansion(name, order):
    out = generate(name, order)
    ns = run_python(out.text)
    reference = REFERENCES[name](order).by_power()
    params = out.function.params
    rng = random.Random(f"{name}:{order}")
    checked = 0
    for v in out.variants:
        expected = substitute_zeros(reference, v.zeros)
        fn = ns[v.name]
        for _ in range(4):
            point = random_point(params, rng)
            point.update({z: Fraction(0) for z in v.zeros})
            got = fn(*(float(point[p]) for p in params))
            bad = compare(got, expected, trig_env(point))
            assert not bad, (v.name, v.zeros, bad[:3])
            checked += 1
    assert len(out.variants) >= 3 and checked == 4 * len(out.variants)


def test_the_spinning_segment_variants_agree_with_the_full_equation_at_orders_6_to_8():
    """With zero acceleration, segment_end_no_accel1's t^6 coefficient is a
    product of two negated factors in its Horner form; it must equal
    segment_end's (and its own --naive form's).  Every variant, at every
    order, must give the full equation's coefficients where its conditions
    hold."""
    for order in (6, 7, 8):
        out = generate("segment-end", order)
        naive = run_python(generate("segment-end", order, shared=False).text)
        ns = run_python(out.text)
        params = out.function.params
        rng = random.Random(order)
        names = {v.name for v in out.variants}
        assert {"segment_end_no_accel1", "segment_end_no_accel1_point1"} <= names
        for v in out.variants:
            for _ in range(20):
                point = {p: rng.uniform(-1, 1) for p in params}
                point.update({z: 0.0 for z in v.zeros})
                args = [point[p] for p in params]
                full, mine, plain = ns["segment_end"](*args), ns[v.name](*args), naive[v.name](*args)
                assert len(mine) == len(plain) <= len(full)
                for k, f in enumerate(full):
                    m, n = (mine[k], plain[k]) if k < len(mine) else (0.0, 0.0)
                    tol = 1e-9 * (1 + abs(f))
                    assert abs(m - f) <= tol and abs(n - f) <= tol, (order, v.name, k, f, m, n)
