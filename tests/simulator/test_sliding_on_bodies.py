"""Friction between movable bodies (docs/contact-model.md, "Sliding on a
sleeping base"; docs/simulator.md, "Contact model: sliding on a sleeping
base"): a box sliding on a box that rests on a fixed floor stops at the
Coulomb distance, the base stays exactly where it is, and the box falls
asleep on it; a rider leaves when its base's island wakes; a base whose
resting contact cannot hold the rider's friction is not ridden; a stack of
ten boxes stays exactly still.  Each proof runs in every runtime, and every
scene here is written with the same bytes by all four."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

from max2code.sim.commands import crosscheck
from max2code.sim.invariants import check, energy_growth
from max2code.sim.replay import read_trace
from max2code.sim.scene import parse_scene
from max2code.sim.simulate import LANGS, run_scene

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path.insert(0, os.path.join(ROOT, "tests"))

G = 9.81


def floor(half=3.0, friction=1.0):
    return {"name": "floor", "shape": "polygon", "fixed": True, "position": [0.0, -0.05], "friction": friction,
            "vertices": [[-half, -0.05], [half, -0.05], [half, 0.05], [-half, 0.05]]}


def box(name, x, y, hw, hh, **kw):
    b = {"name": name, "shape": "polygon", "mass": 1.0, "position": [x, y],
         "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    b.update(kw)
    return b


def ball(name, x, y, r, **kw):
    b = {"name": name, "shape": "circle", "radius": r, "mass": 1.0, "position": [x, y]}
    b.update(kw)
    return b


def scene_of(bodies, end, frame_rate=20, name="sliding.json"):
    raw = {"end_time": end, "frame_rate": frame_rate, "gravity": [0.0, -G], "bodies": bodies,
           "max_events_at_one_time": 1000}
    return parse_scene(json.dumps(raw), name)


def run(scene, lang):
    tr = run_scene(scene, lang)
    rp = read_trace("\n".join(tr.lines()), scene, scene.path)
    return tr, rp


def events(tr):
    return [e for e in tr.events if e["kind"] != "frame"]


def final(tr, name):
    return next(b for b in tr.final["bodies"] if b["body"] == name)


def sound(scene, rp):
    rep = check(scene, rp, kinds=("collision", "support", "stop", "leave", "sleep", "wake", "input", "frame"))
    assert rep.max_overlap <= scene.tolerance, rep
    er = energy_growth(scene, rp)
    assert er.instants > 0 and er.max_growth <= 1e-12, er


def box_on_box(v, mu, mass, half):
    """A plank (2 half wide, 0.2 high, 1 kg, friction 1) at rest on the floor
    (friction 1), a 0.2 m box (mass kg, friction mu) on it sliding at v."""
    return [floor(), box("lower", 0.0, 0.1, half, 0.1, friction=1.0),
            box("upper", 0.0, 0.3, 0.1, 0.1, mass=mass, friction=mu, velocity=[v, 0.0])]


CASES = [(1.0, 0.5, 1.0, 0.4), (-2.0, 0.3, 3.0, 1.0), (0.7, 0.9, 0.5, 0.4)]


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("v, mu, mass, half", CASES)
def test_a_box_sliding_on_a_box_stops_at_the_coulomb_distance(v, mu, mass, half, lang):
    """The plank falls asleep on the floor; the box is supported on it as on
    a fixed body (the floor's static friction holds the plank: mu m g <=
    1 (m + 1) g) and decelerates at mu g (the pair's friction mu x 1): it
    stops after v / (mu g) at v^2 / (2 mu g) from where it started, and
    falls asleep on the plank.  The plank never moves."""
    scene = scene_of(box_on_box(v, mu, mass, half), end=1.0)
    tr, rp = run(scene, lang)
    # the boxes touch at t = 0 before either is supported: grazes of rounding size
    assert all(e["t"] == 0.0 and abs(e["impulse"]) <= 1e-12 for e in events(tr) if e["kind"] == "collision")
    ev = [e for e in events(tr) if e["kind"] != "collision"]
    assert [e["kind"] for e in ev] == ["support", "sleep", "support", "stop", "sleep"]
    assert [e["bodies"] for e in ev] == [["lower", "floor"], ["lower", "floor"], ["upper", "lower"],
                                         ["upper", "lower"], ["upper", "lower"]]
    ts = abs(v) / (mu * G)
    dist = v * abs(v) / (2 * mu * G)
    assert abs(ev[3]["t"] - ts) <= 1e-9
    up, low = final(tr, "upper"), final(tr, "lower")
    assert abs(up["position"][0] - dist) <= 1e-9
    assert up["position"][1] == 0.3 and up["velocity"] == [0.0, 0.0] and up["angle"] == 0.0
    assert low["position"] == [0.0, 0.1] and low["velocity"] == [0.0, 0.0] and low["angle"] == 0.0
    sign = 1.0 if v > 0 else -1.0
    for t in rp.frame_times:
        s = min(t, ts)
        x = v * s - sign * mu * G * s * s / 2
        assert abs(rp.state_at("upper", t).px - x) <= 1e-9
        assert rp.state_at("lower", t).px == 0.0
    sound(scene, rp)


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_a_base_whose_floor_cannot_hold_the_friction_is_not_ridden(lang):
    """On a frictionless floor the plank's resting contact holds no
    tangential force: the box sliding on it is never supported on it (the
    coupled motion of both is not built), and the run stays sound."""
    bodies = box_on_box(1.0, 0.5, 1.0, 0.4)
    bodies[0]["friction"] = 0.0
    scene = scene_of(bodies, end=0.3)
    tr, rp = run(scene, lang)
    assert not any(e["kind"] == "support" and e["bodies"] == ["upper", "lower"] for e in events(tr))
    sound(scene, rp)


def base_hit():
    """The box slides on the plank; a ball rolling on the floor hits the
    plank's side at t = 0.1 s while the box still slides."""
    return [floor(), box("lower", 0.0, 0.1, 0.4, 0.1, friction=1.0),
            box("upper", 0.0, 0.3, 0.1, 0.1, friction=0.5, velocity=[1.0, 0.0]),
            ball("ball", 0.6, 0.1, 0.1, velocity=[-1.0, 0.0])]


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_a_rider_leaves_when_its_base_wakes(lang):
    scene = scene_of(base_hit(), end=0.6)
    tr, rp = run(scene, lang)
    ev = events(tr)
    wake = next(k for k, e in enumerate(ev) if e["kind"] == "wake")
    assert ev[wake]["bodies"][0] == "lower" and abs(ev[wake]["t"] - 0.1) <= 1e-9
    leave = ev[wake + 1]
    assert leave["kind"] == "leave" and leave["bodies"] == ["upper", "lower"] and leave["t"] == ev[wake]["t"]
    st = leave["states"][0]
    assert abs(st["velocity"][0] - (1.0 - 0.5 * G * 0.1)) <= 1e-9 and st["acceleration"] == [0.0, -G]
    sound(scene, rp)


def stack(n):
    return [floor()] + [box(f"b{k}", 0.0, 0.1 + 0.2 * k, 0.1, 0.1, friction=0.5) for k in range(n)]


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_a_stack_of_ten_boxes_stays_exactly_still(lang):
    scene = scene_of(stack(10), end=3.0, frame_rate=10)
    tr, rp = run(scene, lang)
    assert all(e["kind"] in ("support", "sleep", "collision") for e in events(tr))
    assert all(e["t"] == 0.0 for e in events(tr))
    for k in range(10):
        f = final(tr, f"b{k}")
        assert f["position"] == [0.0, 0.1 + 0.2 * k] and f["velocity"] == [0.0, 0.0] and f["angle"] == 0.0
        for t in rp.frame_times:
            st = rp.state_at(f"b{k}", t)
            assert (st.px, st.py, st.angle) == (0.0, 0.1 + 0.2 * k, 0.0)
    sound(scene, rp)


@pytest.mark.slow
@pytest.mark.parametrize("bodies, end", [(box_on_box(*CASES[1]), 1.0), (base_hit(), 0.6), (stack(10), 1.0)],
                         ids=["box-on-box", "base-hit", "stack"])
def test_all_four_runtimes_write_the_same_bytes(bodies, end):
    scene = scene_of(bodies, end)
    traces, problems = crosscheck(scene, LANGS)
    assert not problems, problems
    ref = traces[LANGS[0]]
    for lang, tr in traces.items():
        assert tr.raw == ref.raw, lang
