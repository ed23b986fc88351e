"""Waking by the support graph (docs/simulator.md, "Waking"): a jolt on a
sleeper wakes it and, going up, every sleeper resting on a woken body, and
nothing else.  An input on the top box of a sleeping stack wakes only it;
one on the bottom box wakes the whole stack; a ball asleep beside (not on)
a jolted ball stays asleep.  On random piles jolted late by an input, every
wake is closed upwards (a sleeper whose support woke woke with it) and
wakes only sleepers; the four runtimes give the same bytes, with no
overlap and no energy gained.  Each case runs in every runtime."""
from __future__ import annotations

import json
import random

import pytest
from hypothesis import given, settings, strategies as st

from max2code.sim.scene import parse_scene
from sim_scenes import pile_scene, run_everywhere  # noqa: E402
from test_several_contacts import box  # noqa: E402

pytestmark = pytest.mark.slow      # runs the native runtimes


def stack(who, velocity, n=3):
    """n boxes (0.2 m) stacked on a floor, each 1e-6 m above the one under
    it: they fall asleep within a millisecond; at t = 1 an input adds
    velocity to box `who`."""
    bodies = [box("floor", 1.0, -0.05, 1.5, 0.05)]
    bodies += [box(f"box{k}", 1.0, 0.1 + 0.2 * k + 1e-6 * (k + 1), 0.1, 0.1, mass=1.0) for k in range(n)]
    raw = {"name": f"stack {who}", "end_time": 1.2, "frame_rate": 30, "gravity": [0.0, -9.81], "bodies": bodies,
           "inputs": [{"time": 1.0, "body": who, "add_velocity": list(velocity)}]}
    return parse_scene(json.dumps(raw), "stack.json")


def woken_at(tr, t):
    """The bodies of the first wake line at t (its state lines)."""
    for e in tr.events:
        if e["kind"] == "wake" and e["t"] == t:
            return [s["body"] for s in e["states"]]
    return None


def asleep_before(tr, t):
    """The bodies asleep just before t (from the sleep and wake lines)."""
    asleep = set()
    for e in tr.events:
        if e["t"] >= t:
            break
        if e["kind"] == "sleep":
            asleep.add(e["bodies"][0])
        elif e["kind"] == "wake":
            asleep -= {s["body"] for s in e["states"]}
    return asleep


@pytest.mark.parametrize("velocity", [(0.5, 0.0), (0.0, 0.3)])
def test_a_jolt_on_the_top_box_wakes_only_it(velocity):
    tr = run_everywhere(stack("box2", velocity))
    assert asleep_before(tr, 1.0) == {"box0", "box1", "box2"}
    assert woken_at(tr, 1.0) == ["box2"]


@pytest.mark.parametrize("velocity", [(0.5, 0.0), (0.0, 0.3)])
def test_a_jolt_on_the_bottom_box_wakes_the_whole_stack(velocity):
    tr = run_everywhere(stack("box0", velocity))
    assert asleep_before(tr, 1.0) == {"box0", "box1", "box2"}
    assert woken_at(tr, 1.0) == ["box0", "box1", "box2"]


def test_a_jolt_on_the_middle_box_wakes_it_and_what_is_above():
    tr = run_everywhere(stack("box1", (0.0, 0.3)))
    assert woken_at(tr, 1.0) == ["box1", "box2"]


def balls_side_by_side(velocity):
    """Two balls (r = 0.1) asleep side by side, 1e-6 m apart, on a box
    asleep on a floor (one pile); at t = 1 an input adds velocity to the
    left ball."""
    def ball(name, x):
        return {"name": name, "shape": "circle", "radius": 0.1, "mass": 1.0, "restitution": 0.1,
                "friction": 0.5, "position": [x, 0.2 + 2e-6]}
    bodies = [box("floor", 1.0, -0.05, 1.5, 0.05), box("base", 1.1, 0.05 + 1e-6, 0.3, 0.05, mass=5.0),
              ball("left", 1.0), ball("right", 1.2 + 1e-6)]
    raw = {"name": "side by side", "end_time": 1.2, "frame_rate": 30, "gravity": [0.0, -9.81],
           "bodies": bodies, "inputs": [{"time": 1.0, "body": "left", "add_velocity": list(velocity)}]}
    return parse_scene(json.dumps(raw), "side.json")


@pytest.mark.parametrize("velocity", [(-0.5, 0.0), (0.0, 0.4)])
def test_a_ball_beside_a_jolted_ball_stays_asleep(velocity):
    """Neither the ball beside nor the base under the jolted ball wakes with it."""
    tr = run_everywhere(balls_side_by_side(velocity))
    assert asleep_before(tr, 1.0) == {"base", "left", "right"}
    assert woken_at(tr, 1.0) == ["left"]
    assert not [e for e in tr.events if e["kind"] == "wake" and "right" in [s["body"] for s in e["states"]]]


def wakes_are_closed_upwards(tr):
    """At every wake line, each body woken was asleep, and each sleeper
    whose support (the G of its last sleep line) woke woke with it."""
    asleep = {}                     # body -> the G of its sleep line
    for e in tr.events:
        if e["kind"] == "sleep":
            asleep[e["bodies"][0]] = e["bodies"][1]
        elif e["kind"] == "wake":
            woken = {s["body"] for s in e["states"]}
            assert e["bodies"][0] in woken
            assert woken <= set(asleep), (e, asleep)
            for b, g in asleep.items():
                if g in woken:
                    assert b in woken, (e, b, g)
            for b in woken:
                del asleep[b]


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 10 ** 6))
def test_piles_jolted_late_wake_upwards_in_all_four_runtimes(seed):
    raw = pile_scene(seed, end_time=1.6)
    rng = random.Random(seed)
    movers = [b["name"] for b in raw["bodies"] if not b.get("fixed")]
    raw["inputs"] = [{"time": 1.2, "body": rng.choice(movers),
                      "add_velocity": [rng.uniform(-1.0, 1.0), rng.uniform(0.0, 1.0)]}]
    scene = parse_scene(json.dumps(raw), f"pile-{seed}.json")
    tr = run_everywhere(scene)
    wakes_are_closed_upwards(tr)
