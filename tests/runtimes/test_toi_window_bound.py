"""The window bound of the TOI pair code (docs/toi.md, "Cost") spares only
vertex-edge pairs that have no contact in the window: on random pairs of
turning convex polygons close to touching, every pair it spares gets no
contact from the full computation (point_edge polynomial, roots, inside
check) either.  The four runtimes apply the same bound; the Python
runtime's is the one checked here, through its own window_bound and
spares."""
from __future__ import annotations

import math
import random

from max2code.toolchain import toi
from max2code_rt import toi as rt
from toi_draws import random_polygon  # noqa: E402

TOL = 1e-9      # m


def _motion(rng: random.Random, x: float, y: float) -> rt.Motion:
    accel = rng.random() < 0.3
    return rt.Motion(x=x, y=y, vx=rng.uniform(-3, 3), vy=rng.uniform(-3, 3),
                     ax=rng.uniform(-10, 10) if accel else 0.0, ay=rng.uniform(-10, 10) if accel else 0.0,
                     angle=rng.choice([rng.uniform(-4, 4), rng.uniform(-1e3, 1e3)]),
                     omega=rng.choice([0.0, rng.uniform(-8, 8), rng.uniform(-40, 40)]))


def _check_window(pair, A, B, now, w, tally):
    """Every pair of the window [now, now + w] that the bound spares has no
    contact; tally counts windows, spared and solved pairs, contacts."""
    for X, Y in ((A, B), (B, A)):
        k = pair.window_bound(X, Y, now, w)
        if k is None:
            continue
        tally["windows"] += 1
        for i, v in enumerate(X.verts):
            for j, spare in enumerate(pair.spares(k, v)):
                t = pair.predict_pe(X, Y, v, j, now, w, i)
                if spare:
                    tally["spared"] += 1
                    assert t is None, (f"spared vertex {i} against edge {j} has a contact at s = {t!r} "
                                       f"(now {now!r}, window {w!r})")
                else:
                    tally["solved"] += 1
                    tally["contacts"] += t is not None


def test_spared_pairs_have_no_contact():
    lib = toi.python_toi(tol=TOL)
    pair = lib.pair
    rng = random.Random(20261207)
    tally = {"windows": 0, "spared": 0, "solved": 0, "contacts": 0}
    for _ in range(300):
        sa, sb = random_polygon(rng), random_polygon(rng)
        dist = (sa.bound + sb.bound) * rng.uniform(0.8, 1.5)
        th = rng.uniform(0.0, 2.0 * math.pi)
        off = rng.choice([0.0, rng.uniform(-1e5, 1e5)])
        ma = _motion(rng, off, off)
        mb = _motion(rng, off + dist * math.cos(th), off + dist * math.sin(th))
        # B heads for A so that most scenes touch
        mb.vx, mb.vy = mb.vx - 2.0 * math.cos(th), mb.vy - 2.0 * math.sin(th)
        A, B = rt._body(sa, ma, 0), rt._body(sb, mb, 1)
        s = pair.s
        s.tol, s.bodies, s.end = TOL, [A, B], 4.0
        if pair.separation(A, B, 0.0) < -TOL:
            continue
        ta, tb = pair.turn_rate(A), pair.turn_rate(B)
        big = max(A.bound, B.bound)
        s.alpha = 0.5
        if ta > 0.0 and tb > 0.0:
            s.alpha = rt._angle_for(3.0 * big, lib.order, TOL)
            x = s.alpha / (ta + tb)
        elif ta > 0.0:
            A.window = rt._angle_for(A.bound, lib.order, TOL)
            x = A.window / ta
        elif tb > 0.0:
            B.window = rt._angle_for(B.bound, lib.order, TOL)
            x = B.window / tb
        else:
            x = s.end
        # the window where the pair's first contact is, as the search solves it
        found, at, _ = pair.pair_search(A, B, 0.0, s.end, rt.MAX_STEPS, rt.MAX_STEPS)
        if found == 1:
            _check_window(pair, A, B, at, min(s.end - at, x), tally)
        # and a window anywhere
        now = rng.uniform(0.0, 1.0)
        _check_window(pair, A, B, now, x, tally)
    # the check covers both kinds of pair, and windows where contacts happen
    assert (tally["windows"] > 500 and tally["spared"] > 5000 and tally["solved"] > 500
            and tally["contacts"] > 100), tally
