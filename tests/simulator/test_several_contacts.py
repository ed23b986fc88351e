"""Sleeping on several contacts (docs/simulator.md, "Several contacts"): a
body held by several contacts together falls asleep when they admit a
static equilibrium with a margin, and only then.  A box leaning on a wall
at a drawn angle with drawn friction sleeps leaning exactly when an
independent check (the equilibrium's one free unknown eliminated by hand,
the best margin found over it) says it can stand there, and slides down
when it says it cannot (a frictionless lean never stands); random piles
run the same bytes in all four runtimes, with no overlap and no energy
gained.  Each case runs in every runtime."""
from __future__ import annotations

import json
import math

import pytest
from hypothesis import assume, given, settings, strategies as st

from max2code.sim.scene import parse_scene
from sim_scenes import pile_scene, run_everywhere  # noqa: E402

pytestmark = pytest.mark.slow      # runs the native runtimes

HW, HH = 0.05, 0.2                 # the leaning box's half width and half height, m
G = 9.81


def box(name, x, y, hw, hh, mass=None, friction=0.5, angle=0.0):
    b = {"name": name, "shape": "polygon", "position": [x, y], "angle": angle,
         "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]], "friction": friction}
    if mass is None:
        b["fixed"] = True
    else:
        b["mass"] = mass
        b["restitution"] = 0.1
    return b


def rot(a, x, y):
    c, s = math.cos(a), math.sin(a)
    return c * x - s * y, s * x + c * y


def lean_pose(tilt):
    """The box turned clockwise by tilt (rad) with its top right corner on
    the wall x = 1 and its lowest corner (bottom right) on the floor y = 0,
    each 1e-6 m away: its centre, its angle, and the two contact points."""
    a = -tilt
    corners = [rot(a, -HW, -HH), rot(a, HW, -HH), rot(a, HW, HH), rot(a, -HW, HH)]
    cx = 1.0 - max(p[0] for p in corners) - 1e-6
    cy = -min(p[1] for p in corners) + 1e-6
    floor = (cx + corners[1][0], cy + corners[1][1])
    wall = (cx + corners[2][0], cy + corners[2][1])
    return (cx, cy), a, floor, wall


def lean_scene(tilt, mu_box, mu_wall):
    (cx, cy), a, _, _ = lean_pose(tilt)
    raw = {"name": f"lean {tilt} {mu_box} {mu_wall}", "end_time": 0.6, "frame_rate": 30, "gravity": [0.0, -G],
           "bodies": [box("floor", 1.0, -0.05, 1.5, 0.05, friction=1.0),
                      box("wall", 1.05, 0.5, 0.05, 0.5, friction=mu_wall),
                      box("leaner", cx, cy, HW, HH, mass=1.0, friction=mu_box, angle=a)]}
    return parse_scene(json.dumps(raw), "lean.json")


def lean_margin(tilt, mu_floor, mu_wall):
    """The best margin, relative to the weight W, of the leaning box's
    equilibrium: floor force (F1, N1) at the floor corner, wall force
    (-N2, F2) at the wall corner, F1 = N2 and N1 = W - F2 (forces), the
    torque about the centre zero, which gives F2 as a linear function of
    s = N2; the margin is max over s >= 0 of the least of N2, N1,
    mu_floor N1 -+ F1, mu_wall N2 -+ F2.  Each is linear in s, so the
    maximum of their minimum is at s = 0 or where two of them are equal."""
    (cx, cy), _, floor, wall = lean_pose(tilt)
    ax, ay = floor[0] - cx, floor[1] - cy
    bx, by = wall[0] - cx, wall[1] - cy
    W = 1.0
    # torque: ax N1 - ay F1 + bx F2 - by (-N2) = 0 with N1 = W - F2, F1 = s, N2 = s
    k0, k1 = -ax * W / (bx - ax), -(by - ay) / (bx - ax)       # F2 = k0 + k1 s

    f2 = (k0, k1)
    n1 = (W - k0, -k1)
    ls = [(0.0, 1.0), n1]          # each (c0, c1): c0 + c1 s >= 0
    eqs = []                       # each (c0, c1): c0 + c1 s = 0 (a frictionless contact takes no friction)
    if mu_floor > 0.0:
        ls += [(mu_floor * n1[0], mu_floor * n1[1] - 1.0), (mu_floor * n1[0], mu_floor * n1[1] + 1.0)]
    else:
        eqs.append((0.0, 1.0))     # F1 = s = 0
    if mu_wall > 0.0:
        ls += [(-f2[0], mu_wall - f2[1]), (f2[0], mu_wall + f2[1])]
    else:
        eqs.append(f2)             # F2 = 0
    if eqs:
        c0, c1 = eqs[0]
        s = -c0 / c1 if c1 != 0.0 else 0.0
        worst = min(c0 + c1 * s for (c0, c1) in ls)
        for (c0, c1) in eqs[1:]:
            worst = min(worst, -abs(c0 + c1 * s))
        return worst / W
    cands = [0.0, 1e3]
    for i in range(len(ls)):
        for j in range(i + 1, len(ls)):
            (a0, a1), (b0, b1) = ls[i], ls[j]
            if a1 != b1:
                s = (b0 - a0) / (a1 - b1)
                if s >= 0.0:
                    cands.append(s)
    return max(min(c0 + c1 * s for (c0, c1) in ls) for s in cands) / W


def sleeps_leaning(tr, a0):
    """The box fell asleep near its leaning pose (its angle within 0.01 rad
    of where it started)."""
    for e in tr.events:
        if e["kind"] == "sleep" and e["bodies"][0] == "leaner":
            if abs(e["states"][0]["angle"] - a0) < 0.01:
                return True
    return False


def test_the_independent_check_knows_a_ladder():
    """lean_margin is not vacuous: a frictionless lean cannot stand, a lean
    on high friction can."""
    assert lean_margin(0.35, 0.0, 0.0) < 0.0
    assert lean_margin(0.35, 1.0, 1.0) > 0.05
    assert lean_margin(0.35, 0.0, 0.5) < 0.0
    assert lean_margin(0.35, 0.5, 0.0) > 0.0          # a ladder on a frictionless wall, friction on the floor


@settings(max_examples=12, deadline=None)
@given(tilt=st.floats(0.2, 0.9), mu_box=st.one_of(st.just(0.0), st.floats(0.05, 1.0)),
       mu_wall=st.one_of(st.just(0.0), st.floats(0.05, 1.0)))
def test_a_leaning_box_sleeps_exactly_when_it_can_stand(tilt, mu_box, mu_wall):
    margin = lean_margin(tilt, mu_box * 1.0, mu_box * mu_wall)
    assume(abs(margin) > 0.02)         # away from the limit: the pose moves a hop's height while it hops
    scene = lean_scene(tilt, mu_box, mu_wall)
    tr = run_everywhere(scene)
    a0 = -tilt
    assert sleeps_leaning(tr, a0) == (margin > 0.0), (margin, [e for e in tr.events if e["kind"] == "sleep"])


@pytest.mark.parametrize("tilt", [0.3, 0.6])
def test_a_frictionless_leaning_box_slides_down(tilt):
    tr = run_everywhere(lean_scene(tilt, 0.0, 0.5))
    assert not [e for e in tr.events if e["kind"] == "sleep" and e["bodies"][0] == "leaner"]
    leaner = next(b for b in tr.final["bodies"] if b["body"] == "leaner")
    assert leaner["velocity"] != [0.0, 0.0]         # still moving at the end


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 10 ** 6))
def test_piles_agree_in_all_four_runtimes(seed):
    raw = pile_scene(seed, end_time=0.8)
    scene = parse_scene(json.dumps(raw), f"pile-{seed}.json")
    run_everywhere(scene)


@settings(max_examples=6, deadline=None)
@given(plank_x=st.one_of(st.floats(0.9, 1.1), st.floats(1.32, 1.45)))
def test_a_plank_sleeps_on_two_boxes_only_with_its_centre_between_them(plank_x):
    """The plank of test_two_supports.bridge (0.6 m, boxes' tops spanning
    0.7..0.9 and 1.1..1.3 m): centred between the boxes it falls asleep on
    them; with its centre past the right box's far corner it never sleeps
    on a box (it tips off)."""
    from test_two_supports import bridge
    tr = run_everywhere(bridge(plank_x))
    on_boxes = [e for e in tr.events if e["kind"] == "sleep" and e["bodies"][0] == "plank"
                and e["bodies"][1] in ("left", "right")]
    if plank_x <= 1.1:
        assert on_boxes and on_boxes[0]["t"] < 0.2
    else:
        assert not on_boxes
