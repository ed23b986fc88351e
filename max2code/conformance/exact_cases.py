"""Conformance cases of the exact-motion contact time (op "toc" with
"motion": "exact"): `python -m max2code.conformance.exact_cases` writes
tests/conformance/toc_exact.jsonl (fixed seed; references from exact_ref).

Case: {"id", "op": "toc", "equation", "motion": "exact", "params": {letter: value},
       "horizon": T, "expect": t | null, "accept": [[lo, hi], ...], "none_ok": bool,
       "regular": bool, "kind": ..., "note": ..., "options": {...} (optional)}

Kinds: random motions; fast orbits (up to 50 rad/s over long horizons);
bodies far from the origin; tiny radii; grazing contacts (the bodies overlap
by 1e-9 at their closest) and misses by 1e-9; touching at t = 0,
approaching and separating; no orbit at all (one window); and a few cases
with other window angles.
"""
from __future__ import annotations

import json
import math
import random
import sys

import mpmath

from max2code.conformance.exact_ref import DPS, Gap, reference
from max2code.progress import bar

from max2code.paths import CASES
CASE_FILE = CASES / "toc_exact.jsonl"
CC = "abcdefmnopqghijklrsuvwxz"
PL = "abcdefghijkl"


def _circle_random(rng: random.Random, w: float = 3.0) -> dict:
    a, m = rng.uniform(-5, 5), rng.uniform(-5, 5)
    return {"a": a, "b": rng.uniform(-3, 3), "c": rng.uniform(-1, 1), "d": rng.uniform(0, 1),
            "e": rng.uniform(-w, w), "f": rng.uniform(-3.1, 3.1), "m": m, "n": rng.uniform(-3, 3),
            "o": rng.uniform(-1, 1), "p": rng.uniform(-w, w), "q": rng.uniform(-3.1, 3.1),
            "g": a + rng.uniform(-5, 5), "h": rng.uniform(-3, 3), "i": rng.uniform(-1, 1), "j": rng.uniform(0, 1),
            "k": rng.uniform(-w, w), "l": rng.uniform(-3.1, 3.1), "r": m + rng.uniform(-5, 5),
            "s": rng.uniform(-3, 3), "u": rng.uniform(-1, 1), "v": rng.uniform(-w, w), "w": rng.uniform(-3.1, 3.1),
            "x": rng.uniform(0.1, 1.5), "z": rng.uniform(0.1, 1.5)}


def _line_random(rng: random.Random, w: float = 3.0) -> dict:
    p = {}
    for pos, vel, acc, rad, om, ph in (("a", "b", "c", "d", "e", "f"), ("g", "h", "i", "j", "k", "l")):
        p.update({pos: rng.uniform(-3, 3), vel: rng.uniform(-3, 3), acc: rng.uniform(-2, 2),
                  rad: rng.uniform(0, 1), om: rng.uniform(-w, w), ph: rng.uniform(-3.1, 3.1)})
    return p


def _first_extremum(gp: Gap, T: float, value, slope):
    """The first t in (0, T) where `slope` changes sign (a local extremum
    of `value`), found on a grid fine enough for the fastest orbit."""
    with mpmath.workdps(DPS):
        wmax = max(abs(float(m.w)) for m in (gp.x1, gp.x2) + ((gp.y1, gp.y2) if gp.equation == "circle-circle" else ()))
        n = int(400 + 40 * wmax * T)
        prev_t, prev = 0.0, slope(mpmath.mpf(0))
        for i in range(1, n + 1):
            t = T * i / n
            s = slope(mpmath.mpf(t))
            if (s < 0) != (prev < 0):
                lo, hi = mpmath.mpf(prev_t), mpmath.mpf(t)
                for _ in range(120):
                    mid = (lo + hi) / 2
                    if (slope(mid) < 0) == (prev < 0):
                        lo = mid
                    else:
                        hi = mid
                return (lo + hi) / 2
            prev_t, prev = t, s
        return None


def _graze_circles(rng, miss: bool):
    """Radii such that the circles overlap (or miss) by 1e-9 at their first closest approach."""
    for _ in range(200):
        p = _circle_random(rng)
        T = rng.choice([2.0, 5.0])
        gp = Gap("circle-circle", dict(p, x=0.0, z=0.0), T)
        t = _first_extremum(gp, T, gp.G, gp.G1)
        if t is None or gp.G2(t) <= 0:
            continue
        with mpmath.workdps(DPS):
            dist = mpmath.sqrt(gp.G(t))
        if dist < 0.2:
            continue
        total = float(dist + (-1e-9 if miss else 1e-9))
        p["x"] = rng.uniform(0.3, 0.7) * total
        p["z"] = total - p["x"]
        return p, T
    raise RuntimeError("no grazing configuration found")


def _graze_line(rng, miss: bool):
    for _ in range(200):
        p = _line_random(rng)
        T = rng.choice([2.0, 5.0])
        gp = Gap("point-line", p, T)
        t = _first_extremum(gp, T, gp.G, gp.G1)
        if t is None:
            continue
        with mpmath.workdps(DPS):
            ge, curv = gp.G(t), gp.G2(t)
        if curv == 0:
            continue
        # a minimum (curv > 0) should just dip below zero (graze) or stay above (miss)
        target = (1e-9 if miss else -1e-9) * (1 if curv > 0 else -1)
        p["a"] = float(mpmath.mpf(p["a"]) - ge + target)
        return p, T
    raise RuntimeError("no grazing configuration found")


def _touch0(rng, equation: str, approach: bool):
    for _ in range(1000):
        if equation == "circle-circle":
            p = _circle_random(rng)
            gp = Gap(equation, dict(p, x=0.0, z=0.0), 1.0)
            with mpmath.workdps(DPS):
                total = float(mpmath.sqrt(gp.G(0)))
            p["x"] = rng.uniform(0.3, 0.7) * total
            p["z"] = total - p["x"]
        else:
            p = _line_random(rng)
            p["a"] = p["g"] + p["j"] * math.sin(p["l"]) - p["d"] * math.sin(p["f"])
        gp = Gap(equation, p, 1.0)
        with mpmath.workdps(DPS):
            slope = gp.G1(0)
            if abs(gp.G(0)) > gp.band(0) / 4 or abs(slope) < 0.1:
                continue
        if (slope < 0) == approach:
            return p, rng.choice([1.0, 3.0])
    raise RuntimeError("no touching configuration found")


def _aim(rng, p: dict, equation: str, T: float, reach: float) -> dict:
    """Move body 2 so that the bodies meet near a random time in (0, T):
    circle 2's centre lands within `reach` times the radius sum of circle 1's
    (beyond 1: a miss), the point within `reach` of the line's end."""
    tc = rng.uniform(0.1, 0.9) * T
    if equation == "circle-circle":
        gp = Gap(equation, dict(p, x=0.0, z=0.0), T)
        with mpmath.workdps(DPS):
            dx = gp.x1.at(tc) - gp.x2.at(tc)
            dy = gp.y1.at(tc) - gp.y2.at(tc)
        off = (p["x"] + p["z"]) * rng.uniform(0, reach)
        ang = rng.uniform(0, 2 * math.pi)
        p["g"] = float(mpmath.mpf(p["g"]) + dx + off * math.cos(ang))
        p["r"] = float(mpmath.mpf(p["r"]) + dy + off * math.sin(ang))
    else:
        gp = Gap(equation, p, T)
        with mpmath.workdps(DPS):
            p["g"] = float(mpmath.mpf(p["g"]) + gp.G(tc) + rng.uniform(-reach, reach))
    return p


def _tiny(rng, equation: str):
    """Tiny radii on a path that meets (or nearly)."""
    p = _circle_random(rng)
    r = 10.0 ** rng.uniform(-6, -3)
    p["x"], p["z"] = r * rng.uniform(0.2, 1), r * rng.uniform(0.2, 1)
    return _aim(rng, p, equation, 2.0, 1.2), 2.0


def draws(equation: str, rng: random.Random):
    """(kind, params, horizon, options) for one equation."""
    cc = equation == "circle-circle"
    rnd = _circle_random if cc else _line_random
    out = []
    def aimed(p, T):
        return _aim(rng, p, equation, T, 1.5) if rng.random() < 0.7 else p

    for _ in range(60 if cc else 50):
        T = rng.choice([0.5, 2.0, 5.0, 10.0])
        out.append(("random", aimed(rnd(rng), T), T, None))
    for _ in range(20):
        T = rng.choice([5.0, 20.0])
        out.append(("fast", aimed(rnd(rng, 50.0), T), T, None))
    for _ in range(15):
        T = rng.choice([2.0, 5.0])
        p = aimed(rnd(rng), T)
        off = rng.choice([1e6, -3e5, 2.5e5])
        for k in (("a", "g", "m", "r") if cc else ("a", "g")):
            p[k] += off
        out.append(("far", p, T, None))
    if cc:
        for _ in range(15):
            p, T = _tiny(rng, equation)
            out.append(("tiny", p, T, None))
    for miss in (False, True):
        for _ in range(15):
            p, T = (_graze_circles if cc else _graze_line)(rng, miss)
            out.append(("miss" if miss else "graze", p, T, None))
    for approach in (True, False):
        for _ in range(5):
            p, T = _touch0(rng, equation, approach)
            out.append(("touch0-approach" if approach else "touch0-separate", p, T, None))
    for _ in range(10):
        p = rnd(rng)
        p["d"] = 0.0
        p["j"] = 0.0
        out.append(("no-orbit", p, rng.choice([2.0, 10.0]), None))
    for angle in (0.05, 2.0):
        for _ in range(5):
            out.append(("window", aimed(rnd(rng), 5.0), 5.0, {"window_angle": angle}))
    return out


def _point_below(p: dict) -> dict:
    """The point-line gap is the line's y minus the point's: positive while
    the point is below, negative past the line (inside).  A draw that starts
    inside is mirrored (every position, speed, acceleration and orbit radius
    negated: the gap changes sign, its roots stay), so that these cases keep
    testing contact times; overlap at t = 0 has cases of its own."""
    gp = Gap("point-line", p, 1.0)
    with mpmath.workdps(DPS):
        if not gp.G(0) < 0:
            return p
    return {k: (-v if k in "abcdghij" else v) for k, v in p.items()}


def _overlap0(rng, equation: str, separating: bool):
    """Bodies inside each other at t = 0 (the gap well below zero), moving
    apart (the gap grows: its root is the end of the overlap, never a
    contact) or further in."""
    for _ in range(1000):
        if equation == "circle-circle":
            p = _circle_random(rng)
            gp = Gap(equation, dict(p, x=0.0, z=0.0), 1.0)
            with mpmath.workdps(DPS):
                dist = float(mpmath.sqrt(gp.G(0)))
            total = dist * rng.uniform(1.05, 1.5)
            p["x"] = rng.uniform(0.3, 0.7) * total
            p["z"] = total - p["x"]
        else:
            p = _line_random(rng)
            p["a"] = p["g"] + p["j"] * math.sin(p["l"]) - p["d"] * math.sin(p["f"]) - rng.uniform(0.05, 0.5)
        gp = Gap(equation, p, 1.0)
        with mpmath.workdps(DPS):
            if not gp.G(0) < -100 * gp.band(0):
                continue
            slope = gp.G1(0)
        if abs(slope) > 0.1 and (slope > 0) == separating:
            return p, rng.choice([1.0, 3.0, 10.0])
    raise RuntimeError("no overlapping configuration found")


def overlap_draws(equation: str, rng: random.Random):
    out = []
    for separating in (True, False):
        for _ in range(5):
            p, T = _overlap0(rng, equation, separating)
            out.append(("overlap0-separating" if separating else "overlap0-approaching", p, T, None))
    return out


def generate(seed: int = 2027, progress: bool = True) -> list[dict]:
    rng = random.Random(seed)
    cases = []
    plan = [(eq, d) for eq in ("circle-circle", "point-line") for d in draws(eq, rng)]
    # overlap at t = 0 (its own answer), drawn apart so that the cases above keep their draws
    orng = random.Random(seed + 1)
    plan += [(eq, d) for eq in ("circle-circle", "point-line") for d in overlap_draws(eq, orng)]
    counts: dict[str, int] = {}
    for n, (eq, (kind, params, T, options)) in enumerate(plan):
        if progress:
            bar(n, len(plan), f"{eq} {kind}", prefix="exact cases")
        if eq == "point-line" and not kind.startswith("overlap0"):
            params = _point_below(params)
        ref = reference(eq, params, T)
        key = f"{eq}-{kind}"
        counts[key] = counts.get(key, 0) + 1
        case = {"id": f"exact-{key}-{counts[key]:03d}", "op": "toc", "equation": eq, "motion": "exact",
                "params": {k: params[k] for k in (CC if eq == "circle-circle" else PL)}, "horizon": T,
                "expect": ref.expect, "accept": ref.accept, "none_ok": ref.none_ok, "regular": ref.regular,
                "kind": kind, "note": ref.note}
        if options:
            case["options"] = options
        if ref.overlapped_ok:
            case["overlapped_ok"] = True
        cases.append(case)
    if progress:
        bar(len(plan), len(plan), "done", prefix="exact cases")
    return cases


def main(argv: list[str] | None = None) -> int:
    cases = generate()
    with open(CASE_FILE, "w", encoding="utf-8") as fh:
        for c in cases:
            fh.write(json.dumps(c, sort_keys=True) + "\n")
    found = sum(c["expect"] is not None and c["expect"] != "overlapped" for c in cases)
    print(f"wrote {CASE_FILE}: {len(cases)} cases, {found} with a contact, "
          f"{sum(c['regular'] for c in cases)} regular", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
