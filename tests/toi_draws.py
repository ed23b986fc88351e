"""Random shapes for the TOI library's property tests (tests/runtimes/test_toi_*.py)."""
from __future__ import annotations

import math
import random

from max2code_rt import toi as rt


def random_polygon(rng: random.Random) -> rt.Shape:
    """A box or a random convex polygon about its centre of rotation (m)."""
    if rng.random() < 0.5:
        hx, hy = rng.uniform(0.2, 2.0), rng.uniform(0.2, 2.0)
        return rt.polygon([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])
    n = rng.randint(3, 9)
    angles = sorted(rng.uniform(0.0, 2.0 * math.pi) for _ in range(n))
    r = rng.uniform(0.3, 2.0)
    try:
        return rt.polygon([(r * math.cos(a), r * math.sin(a)) for a in angles])
    except ValueError:      # points too close to make a strictly convex polygon
        return rt.polygon([(-r, -r), (r, -r), (r, r), (-r, r)])
