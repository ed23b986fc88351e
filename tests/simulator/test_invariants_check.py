"""The overlap check of max2code.sim.invariants is exact although it skips
work: the depth of two polygons with a floor (`penetration_placed(...,
above)`) is the true depth whenever that exceeds the floor and never below
the true depth otherwise; and `check` reports the same deepest overlap, at
the same place, as measuring every pair of bodies at every instant."""
from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, strategies as st

from max2code.sim.invariants import check
from max2code.sim.replay import read_trace
from max2code.sim.scene import Body, parse_scene, penetration, penetration_placed, world_vertices
from max2code.sim.simulate import run_scene
from sim_scenes import pile_scene, resting_scene

coord = st.floats(-2.0, 2.0, allow_nan=False)


def _polygon(cx, cy, angle, n, size):
    """A regular n-gon of circumradius size (counter-clockwise) at (cx, cy), turned by angle."""
    verts = [(size * math.cos(2 * math.pi * k / n), size * math.sin(2 * math.pi * k / n)) for k in range(n)]
    return Body("p", True, False, 1.0, 1.0, 1.0, (cx, cy), (0.0, 0.0), (0.0, 0.0), angle, 0.0, vertices=verts)


bodies = st.builds(_polygon, coord, coord, st.floats(-4.0, 4.0), st.integers(3, 8), st.floats(0.05, 1.5))


@given(bodies, bodies, st.floats(-3.0, 1.0))
def test_a_floor_gives_the_true_depth_above_it_and_a_bound_below(a, b, above):
    true = penetration(a, b)
    got = penetration_placed(a, world_vertices(a), b, world_vertices(b), above)
    if true > above:
        assert got == true
    else:
        assert true <= got <= above


def _every_pair(scene, rp, kinds):
    """The plain check: every pair that is not two fixed bodies, at every
    instant; the deepest overlap and every (instant, pair) where it is reached."""
    depths = []
    for t in sorted({e.t for e in rp.events if e.kind in kinds}):
        placed = []
        for k, b in enumerate(scene.bodies):
            s = rp.state_at(k, t)
            placed.append(Body(b.name, b.polygon, b.fixed, b.mass, b.inertia, b.restitution, (s.px, s.py),
                               (s.vx, s.vy), b.acceleration, s.angle, s.omega, b.radius, b.orbit_radius,
                               b.orbit_angle, b.vertices, b.friction))
        for j in range(len(placed)):
            for k in range(j + 1, len(placed)):
                if placed[j].fixed and placed[k].fixed:
                    continue
                depths.append((penetration(placed[j], placed[k]), t, placed[j].name, placed[k].name))
    deepest = max(d for d, *_ in depths)
    return deepest, [f"{a} and {b} at t={t!r}" for d, t, a, b in depths if d == deepest]


@pytest.mark.slow
@pytest.mark.parametrize("raw", [pile_scene(546537, end_time=0.6), pile_scene(7, end_time=0.6),
                                 resting_scene(15095, boxes=True)], ids=["boxes", "pile-7", "resting"])
def test_check_finds_the_deepest_overlap_of_every_pair(raw):
    scene = parse_scene(json.dumps(raw), raw["name"])
    tr = run_scene(scene, "c")
    rp = read_trace("\n".join(tr.lines()), scene, raw["name"])
    kinds = ("collision", "support", "stop", "leave", "sleep", "wake", "input", "frame")
    rep = check(scene, rp, kinds=kinds)
    deepest, places = _every_pair(scene, rp, kinds)
    assert rep.max_overlap == deepest
    swapped = {" and ".join(reversed(w.split(" at ")[0].split(" and "))) + " at " + w.split(" at ")[1] for w in places}
    assert rep.overlap_where in set(places) | swapped
