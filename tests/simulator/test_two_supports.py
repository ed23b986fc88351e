"""Sleeping on two supports (docs/simulator.md, "Several contacts"): a plank
laid across two boxes asleep on the floor touches each with a corner and
has its centre over neither face, so neither support alone lets it sleep.
Both together hold it: the two contacts can push against gravity within
their friction cones and its centre lies between them.  It falls asleep
after a few hops instead of hopping for ever, joins one island with both
boxes (a push on either wakes it too), and a plank whose centre lies
beyond both contacts still tips off.  Every case runs in the four
runtimes, which write the same bytes."""
from __future__ import annotations

import json

import pytest

from max2code.sim.scene import parse_scene
from sim_scenes import run_everywhere  # noqa: E402


def box(name, x, y, hw, hh, mass=None, friction=0.5):
    b = {"name": name, "shape": "polygon", "position": [x, y], "angle": 0.0,
         "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]], "friction": friction}
    if mass is None:
        b["fixed"] = True
    else:
        b["mass"] = mass
        b["restitution"] = 0.1
    return b


def bridge(plank_x: float, push: bool = False, friction: float = 0.5):
    """Two 0.2 m boxes on the floor (centres 0.8 and 1.2 m, a 0.2 m gap) and
    a 0.6 x 0.1 m plank dropped from 1 cm above them, centred at plank_x."""
    raw = {"name": f"bridge at {plank_x}", "end_time": 2.0, "frame_rate": 60, "gravity": [0.0, -9.81],
           "bodies": [box("floor", 1.0, -0.05, 1.5, 0.05, friction=1.0),
                      box("left", 0.8, 0.1, 0.1, 0.1, mass=2.0, friction=friction),
                      box("right", 1.2, 0.1, 0.1, 0.1, mass=2.0, friction=friction),
                      box("plank", plank_x, 0.26, 0.3, 0.05, mass=1.0, friction=friction)]}
    if push:
        raw["inputs"] = [{"time": 1.0, "body": "left", "set_velocity": [-0.5, 0.0]}]
    return parse_scene(json.dumps(raw), f"bridge-{plank_x}-{push}-{friction}.json")


def final(tr, name):
    return next(b for b in tr.final["bodies"] if b["body"] == name)


@pytest.mark.slow
@pytest.mark.parametrize("plank_x", [1.0, 1.02, 0.97])
def test_a_plank_across_two_sleeping_boxes_falls_asleep_on_both(plank_x):
    tr = run_everywhere(bridge(plank_x))
    sleeps = [e for e in tr.events if e["kind"] == "sleep" and e["bodies"][0] == "plank"]
    assert len(sleeps) == 1 and sleeps[0]["bodies"][1] in ("left", "right"), sleeps
    assert sleeps[0]["t"] < 0.1                     # a few hops after landing at 0.045 s
    assert tr.stats["events"]["collisions"] < 50
    p = final(tr, "plank")
    assert p["velocity"] == [0.0, 0.0] and p["angular_velocity"] == 0.0
    assert p["position"][1] == pytest.approx(0.25, abs=2.5e-4)      # within a hop's height of the boxes' tops
    assert p["position"][0] == pytest.approx(plank_x, abs=1e-3)


@pytest.mark.slow
def test_the_plank_joins_both_boxes_islands_so_a_push_on_either_wakes_it():
    tr = run_everywhere(bridge(1.0, push=True))
    wakes = [e for e in tr.events if e["kind"] == "wake" and e["t"] == 1.0]
    assert wakes, "the push at t = 1 s woke nothing"
    woken = {s["body"] for e in wakes for s in e["states"]}
    assert {"left", "right", "plank"} <= woken, woken


@pytest.mark.slow
def test_a_plank_whose_centre_lies_beyond_both_contacts_tips_off():
    tr = run_everywhere(bridge(1.35))
    p = final(tr, "plank")
    assert p["position"][1] < 0.1, p                # on the floor, past the right box
    assert not [e for e in tr.events if e["kind"] == "sleep" and e["bodies"][0] == "plank"
                and e["bodies"][1] in ("left", "right")]
