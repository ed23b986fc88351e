"""Cases of the TOI library (op "toi": tests/conformance/toi/toi.jsonl,
docs/toi.md, docs/conformance.md), with their references on the exact
motion (toi_ref.py, mpmath).  Fixed seed; families: no spin, spin vs fixed,
both spinning (two boxes), grazing (within a few tolerances of touching,
either side), far from the origin, circle against polygon, polygon against
polygon, overlapped at t = 0, none within the horizon, orbiting circles.

    python -m max2code.conformance.toi_cases [-o tests/conformance/toi/toi.jsonl] [--seed N] [--jobs N]
"""
from __future__ import annotations

import argparse
import json
import math
import random
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from max2code.conformance.toi_ref import reference

TOL = 1e-9
OUT = Path(__file__).resolve().parents[2] / "tests" / "conformance" / "toi" / "toi.jsonl"


def box(hw: float, hh: float) -> list[list[float]]:
    return [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]


def ngon(rng: random.Random, n: int, size: float) -> list[list[float]]:
    """A strictly convex polygon of n vertices on a circle (gaps below pi),
    about a centre of rotation near its middle."""
    while True:
        angles = sorted(rng.uniform(0.0, 2.0 * math.pi) for _ in range(n))
        gaps = [(angles[(k + 1) % n] - angles[k]) % (2.0 * math.pi) for k in range(n)]
        if max(gaps) < 0.9 * math.pi and min(gaps) > 0.2:
            break
    return [[size * math.cos(a), size * math.sin(a)] for a in angles]


def motion(x=0.0, y=0.0, vx=0.0, vy=0.0, ax=0.0, ay=0.0, angle=0.0, omega=0.0, orbit=0.0, orbit_phase=0.0) -> dict:
    return {"x": x, "y": y, "vx": vx, "vy": vy, "ax": ax, "ay": ay, "angle": angle, "omega": omega,
            "orbit": orbit, "orbit_phase": orbit_phase}


def poly(vertices, m) -> dict:
    return {"shape": "polygon", "vertices": vertices, "motion": m}


def disc(radius, m) -> dict:
    return {"shape": "circle", "radius": radius, "motion": m}


def _aimed(rng: random.Random, reach: float, speed: tuple[float, float], accel: bool = False):
    """A start 2-5 m from the origin moving towards it, missing the centre by
    up to `reach`: (x, y, vx, vy, ax, ay)."""
    d = rng.uniform(2.0, 5.0)
    a = rng.uniform(0.0, 2.0 * math.pi)
    x, y = d * math.cos(a), d * math.sin(a)
    s = rng.uniform(*speed)
    off = rng.uniform(-reach, reach)
    tx, ty = -math.sin(a), math.cos(a)
    aimx, aimy = off * tx - x, off * ty - y
    n = math.hypot(aimx, aimy)
    vx, vy = s * aimx / n, s * aimy / n
    ax = ay = 0.0
    if accel:
        ax, ay = rng.uniform(-1.0, 1.0), rng.uniform(-2.0, 0.0)
    return x, y, vx, vy, ax, ay


def _shape(rng: random.Random, kind: str):
    if kind == "box":
        return box(rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.8))
    return ngon(rng, rng.choice((3, 5, 6)), rng.uniform(0.3, 0.9))


def family_cases(rng: random.Random) -> list[dict]:
    cases = []

    def add(family, a, b, horizon, tol=TOL):
        cases.append({"id": f"toi-{family}-{len([c for c in cases if c['family'] == family]):03d}", "op": "toi",
                      "family": family, "horizon": horizon, "tol": tol, "a": a, "b": b})

    for _ in range(12):         # no spin: boxes and polygons, some accelerating
        x, y, vx, vy, ax, ay = _aimed(rng, 1.2, (0.5, 4.0), accel=rng.random() < 0.4)
        add("no-spin", poly(_shape(rng, rng.choice(("box", "ngon"))), motion(x, y, vx, vy, ax, ay,
                                                                              angle=rng.uniform(-3, 3))),
            poly(_shape(rng, "box"), motion(angle=rng.uniform(-3, 3))), 4.0)
    for _ in range(12):         # a spinning polygon against one that does not turn
        x, y, vx, vy, ax, ay = _aimed(rng, 1.2, (0.5, 4.0))
        add("spin-vs-fixed", poly(_shape(rng, rng.choice(("box", "ngon"))),
                                  motion(x, y, vx, vy, angle=rng.uniform(-3, 3), omega=rng.uniform(-8, 8))),
            poly(_shape(rng, "box"), motion(angle=rng.uniform(-3, 3))), 4.0)
    for _ in range(30):         # two spinning boxes (the benchmark's family)
        x, y, vx, vy, ax, ay = _aimed(rng, 1.2, (0.5, 4.0))
        add("both-spinning", poly(_shape(rng, "box"), motion(x, y, vx, vy, angle=rng.uniform(-3, 3),
                                                              omega=rng.uniform(-6, 6))),
            poly(_shape(rng, "box"), motion(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2),
                                            angle=rng.uniform(-3, 3), omega=rng.uniform(-6, 6))), 4.0)
    # grazing: within a few tolerances of touching, on either side
    for d in (3.0, 1.5, -1.5, -3.0, 10.0, -10.0):
        gap = d * TOL
        # a box sliding over a floor box, its bottom face `gap` above the floor's top
        add("grazing", poly(box(0.5, 0.25), motion(-3.0, 0.25 + 0.5 + gap, vx=2.0)),
            poly(box(1.0, 0.5), motion()), 4.0)
        # a spinning square passing over a floor: its lowest corner reaches `gap` above the top
        s = 0.3
        add("grazing", poly(box(s, s), motion(-2.0, 0.5 + s * math.sqrt(2.0) + gap, vx=1.0, angle=0.0,
                                              omega=math.pi / 4.0 / 2.0)),
            poly(box(3.0, 0.5), motion()), 4.0)
        # a circle rolling over a box's top
        add("grazing", disc(0.3, motion(-3.0, 0.5 + 0.3 + gap, vx=1.5)), poly(box(1.0, 0.5), motion(angle=0.0)),
            4.0)
    for _ in range(12):         # far from the origin: the same motions moved by 1e4 to 1e6 m
        ox, oy = rng.choice((-1, 1)) * 10 ** rng.uniform(4, 6), rng.choice((-1, 1)) * 10 ** rng.uniform(4, 6)
        x, y, vx, vy, ax, ay = _aimed(rng, 1.0, (0.5, 4.0))
        add("far", poly(_shape(rng, "box"), motion(ox + x, oy + y, vx, vy, angle=rng.uniform(-3, 3),
                                                    omega=rng.uniform(-5, 5))),
            poly(_shape(rng, "box"), motion(ox, oy, angle=rng.uniform(-3, 3), omega=rng.uniform(-5, 5))), 4.0)
    for _ in range(14):         # a circle (sometimes orbiting) against a polygon (sometimes spinning)
        x, y, vx, vy, ax, ay = _aimed(rng, 1.0, (0.5, 4.0), accel=rng.random() < 0.3)
        orbit = rng.choice((0.0, 0.0, rng.uniform(0.1, 0.5)))
        om = rng.uniform(-4, 4) if orbit > 0.0 else 0.0
        add("circle-polygon", disc(rng.uniform(0.1, 0.6), motion(x, y, vx, vy, ax, ay, angle=rng.uniform(-3, 3),
                                                                  omega=om, orbit=orbit,
                                                                  orbit_phase=rng.uniform(-3, 3))),
            poly(_shape(rng, rng.choice(("box", "ngon"))),
                 motion(angle=rng.uniform(-3, 3), omega=rng.choice((0.0, rng.uniform(-5, 5))))), 4.0)
    for _ in range(12):         # random convex polygons, both turning
        x, y, vx, vy, ax, ay = _aimed(rng, 1.0, (0.5, 4.0))
        add("polygon-polygon", poly(_shape(rng, "ngon"), motion(x, y, vx, vy, angle=rng.uniform(-3, 3),
                                                                 omega=rng.uniform(-5, 5))),
            poly(_shape(rng, "ngon"), motion(angle=rng.uniform(-3, 3), omega=rng.uniform(-5, 5))), 4.0)
    for _ in range(8):          # overlapping at t = 0
        depth = rng.uniform(0.01, 0.2)
        shp = rng.choice(("box", "circle"))
        b = poly(box(0.5, 0.5), motion(angle=0.0, omega=rng.uniform(-3, 3)))
        if shp == "box":
            a = poly(box(0.4, 0.4), motion(0.9 - depth, rng.uniform(-0.3, 0.3), vx=rng.uniform(-2, 2),
                                           omega=rng.uniform(-3, 3)))
        else:
            a = disc(0.4, motion(0.9 - depth, rng.uniform(-0.3, 0.3), vx=rng.uniform(-2, 2)))
        add("overlapped", a, b, 2.0)
    for _ in range(8):          # none within the horizon: moving apart, or too far for the horizon
        x, y, vx, vy, ax, ay = _aimed(rng, 0.5, (0.5, 2.0))
        if rng.random() < 0.5:
            vx, vy = -vx, -vy
            h = 4.0
        else:
            h = 0.3
        add("none", poly(_shape(rng, "box"), motion(x, y, vx, vy, omega=rng.uniform(-4, 4))),
            poly(_shape(rng, "box"), motion(omega=rng.uniform(-4, 4))), h)
    for _ in range(6):          # two circles, orbiting
        x, y, vx, vy, ax, ay = _aimed(rng, 0.6, (0.5, 3.0))
        add("circle-circle", disc(rng.uniform(0.1, 0.4), motion(x, y, vx, vy, omega=rng.uniform(-4, 4),
                                                                 orbit=rng.uniform(0.1, 0.5),
                                                                 orbit_phase=rng.uniform(-3, 3))),
            disc(rng.uniform(0.1, 0.4), motion(omega=rng.uniform(-4, 4), orbit=rng.choice((0.0, 0.3)))), 4.0)
    return cases


def with_reference(case: dict) -> dict:
    ref = reference(case)
    out = dict(case)
    out.update(ref)
    tol = case["tol"]
    if ref["d0"] < -2.0 * tol:
        out["expect"] = "overlapped"
    elif ref["t_deep"] is not None:
        out["expect"] = "hit"
    elif ref["t_in"] is not None:
        out["expect"] = "hit-or-none"     # within the tolerance of touching: either answer stands
    else:
        out["expect"] = "none"
    return out


def generate(seed: int = 2031, jobs: int = 2) -> list[dict]:
    cases = family_cases(random.Random(seed))
    with ProcessPoolExecutor(max_workers=jobs) as ex:
        return list(ex.map(with_reference, cases))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", default=str(OUT))
    ap.add_argument("--seed", type=int, default=2031)
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    cases = generate(args.seed, args.jobs)
    with open(args.out, "w", encoding="utf-8") as fh:
        for c in cases:
            fh.write(json.dumps(c) + "\n")
    counts = {}
    for c in cases:
        counts[c["expect"]] = counts.get(c["expect"], 0) + 1
    print(f"{len(cases)} cases to {args.out}: {counts}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
