"""A gentle touch on a sleeping base leaves what slides on it sliding
(docs/simulator.md, "Contact model: sliding on a sleeping base"): a box
sliding with friction on a box asleep on the floor, and a light pebble
that hits the base's side so gently that the base stays asleep.  The base
has not moved, so the slider keeps its support and stops at Coulomb's
distance, `v^2 / (2 mu g)`, never sinking into the base.  Each case runs
in every runtime, which write the same bytes."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from max2code.sim.commands import crosscheck
from max2code.sim.invariants import check
from max2code.sim.replay import read_trace
from max2code.sim.scene import parse_scene
from max2code.sim.simulate import LANGS

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
BOX_ON_BOX = ROOT / "examples" / "piles" / "box-on-box.json"
G = 9.81                    # m/s^2
MU = 0.5 * 0.5              # the two boxes' friction, multiplied
X0, V0 = 0.65, 1.0          # m, m/s: the slider's start


def scene_with_pebble(y: float, vx: float, mass: float):
    """box-on-box, one second long, with a pebble (1 cm, `mass` kg) coming at
    the base's right side (x = 1.5 m) from 2 cm away at height y (m)."""
    raw = json.loads(BOX_ON_BOX.read_text())
    raw["end_time"] = 1.0
    raw["bodies"].append({"name": "pebble", "shape": "circle", "radius": 0.01, "mass": mass, "restitution": 0.5,
                          "friction": 0.5, "position": [1.52, y], "velocity": [vx, 0.0]})
    return parse_scene(json.dumps(raw), f"pebble-{y}-{vx}-{mass}.json")


def final(tr, name):
    return next(b for b in tr.final["bodies"] if b["body"] == name)


@pytest.mark.slow
@pytest.mark.parametrize("y, vx", [(0.1, -0.5), (0.15, -1.0), (0.05, -2.0)])
def test_a_gentle_touch_on_the_base_does_not_drop_the_slider_into_it(y, vx):
    scene = scene_with_pebble(y, vx, 0.001)
    tr, problems = crosscheck(scene, LANGS)
    assert problems == []
    ref = tr[LANGS[0]]
    for lang in LANGS[1:]:
        assert tr[lang].raw == ref.raw, lang
    events = ref.events
    touch = [e for e in events if e["kind"] == "collision" and set(e["bodies"]) == {"pebble", "bottom"}]
    assert touch, "the pebble never touched the base"
    assert not [e for e in events if e["kind"] == "wake"], "the touch was meant to be gentle: the base stays asleep"
    assert not [e for e in events if e["kind"] == "leave" and e["bodies"][0] == "top"]
    top = final(ref, "top")
    assert top["position"][0] == pytest.approx(X0 + V0 * V0 / (2 * MU * G), abs=1e-9)
    assert top["position"][1] == pytest.approx(0.3, abs=1e-12)
    rep = check(scene, read_trace("\n".join(ref.lines()), scene, scene.name))
    assert rep.max_overlap <= scene.tolerance, rep.overlap_where


@pytest.mark.slow
def test_a_real_hit_on_the_base_still_wakes_it_and_the_slider_lands_on_it():
    """The same pebble, heavy: the base wakes and moves, the slider leaves its
    support and meets the base again at once, never sinking into it."""
    scene = scene_with_pebble(0.1, -0.5, 1.0)
    tr, problems = crosscheck(scene, ["c", "python"])
    assert problems == []
    assert tr["c"].raw == tr["python"].raw
    events = tr["c"].events
    assert [e for e in events if e["kind"] == "wake" and e["bodies"] == ["bottom"]]
    rep = check(scene, read_trace("\n".join(tr["c"].lines()), scene, scene.name))
    assert rep.max_overlap <= scene.tolerance, rep.overlap_where
