"""The TOI library's overlap test at t = 0 is spared when the bounding
circles are apart (docs/toi.md, "Cost"; bounds_apart in C, Rust, Python,
BoundsApart in Modula-2): on random pairs of polygons and circles whose
centres are just farther apart than their bounds and the tolerance, the
separation the overlap test would take is above the tolerance, and only
pairs within the tolerance and a small margin of touching bounds are not
spared."""
from __future__ import annotations

import math
import random

from max2code.toolchain import toi
from max2code_rt import toi as rt
from toi_draws import random_polygon  # noqa: E402

TOL = 1e-9      # m


def _shape(rng: random.Random) -> rt.Shape:
    return random_polygon(rng) if rng.random() < 0.8 else rt.circle(rng.uniform(0.1, 2.0))


def test_pairs_whose_bounds_are_apart_are_apart():
    pair = toi.python_toi(tol=TOL).pair
    rng = random.Random(20261207)
    spared = kept = 0
    for _ in range(2000):
        sa, sb = _shape(rng), _shape(rng)
        off = rng.choice([0.0, rng.uniform(-1e4, 1e4)])
        th = rng.uniform(0.0, 2.0 * math.pi)
        dist = (sa.bound + sb.bound) + TOL * rng.choice([rng.uniform(-4.0, 4.0), rng.uniform(1.0, 1e6)])
        ma = rt.Motion(x=off, y=off, angle=rng.uniform(-4, 4), orbit=0.0)
        mb = rt.Motion(x=off + dist * math.cos(th), y=off + dist * math.sin(th), angle=rng.uniform(-4, 4))
        A, B = rt._body(sa, ma, 0), rt._body(sb, mb, 1)
        pair.s.tol, pair.s.bodies = TOL, [A, B]
        if rt._bounds_apart(A, B, TOL):
            spared += 1
            sep = pair.library_separation(A, B)
            assert sep > TOL, (sep, dist - (sa.bound + sb.bound))
        else:
            kept += 1
            # kept only within the tolerance and a margin of a few 2^-30 of the sizes
            r = A.bound + B.bound
            assert math.hypot(B.px - A.px, B.py - A.py) - r < TOL + 2.0 ** -29 * (dist + r + 4.0 * abs(off))
    assert spared > 500 and kept > 200, (spared, kept)
