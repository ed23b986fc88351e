"""The TOI library (docs/toi.md): its conformance cases pass in C,
Modula-2, Python and Rust against the mpmath references, with the same bits (time,
features, point, normal), as do random pairs of turning polygons; the judge
rejects wrong answers; shapes are checked."""
from __future__ import annotations

import json
import math
import random
from pathlib import Path

import pytest

from max2code.conformance import toi_op
from max2code.conformance.ops import hex_of
from toi_draws import random_polygon  # noqa: E402

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
CASES = ROOT / "tests" / "conformance" / "toi" / "toi.jsonl"


def _cases() -> list[dict]:
    return [json.loads(line) for line in CASES.read_text(encoding="utf-8").splitlines() if line.strip()]


LANGS = ("c", "m2", "python", "rust")


@pytest.fixture(scope="module")
def answers():
    cases = dict(enumerate(_cases()))
    op = toi_op.ToiOp()
    return cases, {lang: op.batch(lang, cases) for lang in LANGS}


def test_every_family_is_there():
    families = {c["family"] for c in _cases()}
    assert families >= {"no-spin", "spin-vs-fixed", "both-spinning", "grazing", "far", "circle-polygon",
                        "polygon-polygon", "overlapped", "none", "circle-circle"}
    expects = {c["expect"] for c in _cases()}
    assert {"hit", "none", "overlapped"} <= expects


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_cases_pass(answers, lang):
    cases, got = answers
    bad = []
    for seq, case in cases.items():
        v = toi_op.judge(case, got[lang][seq])
        if not v.ok:
            bad.append(f"{case['id']}: {v.why} ({got[lang][seq]})")
    assert not bad, "\n".join(bad[:20])


@pytest.mark.slow
def test_the_runtimes_give_the_same_bits(answers):
    cases, got = answers
    differ = [cases[s]["id"] for s in cases if len({got[lang][s] for lang in LANGS}) > 1]
    assert not differ, differ[:10]
    hits = sum(1 for s in cases if got["c"][s].startswith("hit"))
    assert hits >= len(cases) // 2


def _turning_pairs(rng: random.Random, count: int) -> dict[int, dict]:
    """Pairs of turning polygons heading for each other (boxes and random
    convex polygons; some accelerate, some far from the origin, some spin
    fast): the library's clear stretches of two turning polygons and its
    step straight to a window, on more motions than the conformance cases."""
    out = {}
    for seq in range(count):
        sa, sb = random_polygon(rng), random_polygon(rng)
        off = rng.choice([0.0, rng.uniform(-1e4, 1e4), rng.uniform(-1e6, 1e6)])
        th = rng.uniform(0.0, 2.0 * math.pi)
        dist = (sa.bound + sb.bound) * rng.uniform(1.0, 2.5)
        accel = rng.random() < 0.4

        def motion(x, y, hx, hy):
            return {"x": x, "y": y, "vx": rng.uniform(-3, 3) + hx, "vy": rng.uniform(-3, 3) + hy,
                    "ax": rng.uniform(-5, 5) if accel else 0.0, "ay": rng.uniform(-5, 5) if accel else 0.0,
                    "angle": rng.uniform(-4, 4), "omega": rng.choice([rng.uniform(-8, 8), rng.uniform(-40, 40)]),
                    "orbit": 0.0, "orbit_phase": 0.0}

        out[seq] = {"id": f"turning-{seq:03d}", "horizon": 4.0, "tol": 1e-9,
                    "a": {"shape": "polygon", "vertices": [[v.lx, v.ly] for v in sa.verts],
                          "motion": motion(off, off, 0.0, 0.0)},
                    "b": {"shape": "polygon", "vertices": [[v.lx, v.ly] for v in sb.verts],
                          "motion": motion(off + dist * math.cos(th), off + dist * math.sin(th),
                                           -2.0 * math.cos(th), -2.0 * math.sin(th))}}
    return out


@pytest.mark.slow
def test_turning_polygons_give_the_same_bits_in_every_runtime():
    cases = _turning_pairs(random.Random(20261208), 200)
    op = toi_op.ToiOp()
    got = {lang: op.batch(lang, cases) for lang in LANGS}
    differ = [cases[s]["id"] for s in cases if len({got[lang][s] for lang in LANGS}) > 1]
    assert not differ, differ[:10]
    hits = sum(1 for s in cases if got["c"][s].startswith("hit"))
    errors = [cases[s]["id"] for s in cases if got["c"][s].startswith("error")]
    assert hits >= len(cases) // 5 and not errors, (hits, errors[:10])


def _case(**over):
    c = {"tol": 1e-9, "d0": 1.0, "t_in": 0.5, "t_star": 0.5000000005, "t_deep": 0.500000001}
    c.update(over)
    return c


def _hit(t: float) -> str:
    return " ".join(["hit", hex_of(t), "1", "0", "0", "0"] + [hex_of(0.0)] * 4)


def test_the_judge_fails_wrong_answers():
    c = _case()
    assert toi_op.judge(c, _hit(0.5000000005)).ok
    assert not toi_op.judge(c, _hit(0.49)).ok                 # before the bodies come near
    assert not toi_op.judge(c, _hit(0.6)).ok                  # late: they are inside each other
    assert not toi_op.judge(c, "none").ok                     # missed
    assert not toi_op.judge(c, "overlapped").ok               # apart at 0
    assert not toi_op.judge(c, "error refused").ok
    graze = _case(t_deep=None, t_star=None)
    assert toi_op.judge(graze, "none").ok and toi_op.judge(graze, _hit(0.5)).ok
    far = _case(t_in=None, t_deep=None, t_star=None)
    assert not toi_op.judge(far, _hit(0.5)).ok                # invented
    deep = _case(d0=-1e-3)
    assert toi_op.judge(deep, "overlapped").ok and not toi_op.judge(deep, "none").ok


def test_shapes_are_checked():
    from max2code_rt import toi as rt
    with pytest.raises(ValueError):
        rt.polygon([(0, 0), (1, 0), (1, 1), (0, 1)][::-1])      # clockwise
    with pytest.raises(ValueError):
        rt.polygon([(0, 0), (1, 0), (0.5, 0.0), (0, 1)])        # not strictly convex
    with pytest.raises(ValueError):
        rt.circle(0.0)
    sq = rt.polygon([(-1, -1), (1, -1), (1, 1), (-1, 1)])
    assert sq.bound == math.sqrt(2.0)
    # outward normals: down, right, up, left
    assert [(round(math.cos(v.psi), 12), round(math.sin(v.psi), 12)) for v in sq.verts] == [
        (0.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)]
