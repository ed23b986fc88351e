"""The contact model of the reference simulator (issue 10,
docs/simulator.md "Contact model"): resting contact, support, sliding,
friction.  Python runtime; the other runtimes are held to the same bytes
by tests/test_crosscheck.py."""
from __future__ import annotations

import json
import math

import pytest

from max2code.sim.invariants import check
from max2code.sim.replay import read_trace
from max2code.sim.scene import parse_scene
from max2code.sim.simulate import run_scene

G = 9.81


def floor(name="floor", x=0.0, top=0.0, half=1.0, thick=0.1, **kw):
    b = {"name": name, "shape": "polygon", "fixed": True, "position": [x, top - thick / 2],
         "vertices": [[-half, -thick / 2], [half, -thick / 2], [half, thick / 2], [-half, thick / 2]]}
    b.update(kw)
    return b


def ball(name="ball", x=0.0, y=0.1, r=0.1, **kw):
    b = {"name": name, "shape": "circle", "radius": r, "mass": 1.0, "position": [x, y]}
    b.update(kw)
    return b


def run(bodies, end=1.0, frame_rate=100, **kw):
    raw = {"end_time": end, "frame_rate": frame_rate, "gravity": [0.0, -G], "bodies": bodies}
    raw.update(kw)
    scene = parse_scene(json.dumps(raw), "contact.json")
    tr = run_scene(scene, "python")
    rp = read_trace("\n".join(tr.lines()), scene, "contact.json")
    return scene, tr, rp


def final(tr, name):
    return next(b for b in tr.final["bodies"] if b["body"] == name)


def no_overlap(scene, rp):
    rep = check(scene, rp, kinds=("collision", "input", "frame"))
    assert rep.max_overlap <= scene.tolerance, rep
    return rep


def test_ball_touching_a_floor_at_rest_is_a_contact_at_t0():
    """Zero approach speed, pressed by gravity: a contact now, not a fall through."""
    scene, tr, rp = run([floor(), ball()])
    first = next(e for e in tr.events if e["kind"] != "frame")
    assert first["t"] == 0.0 and first["bodies"] == ["ball", "floor"]
    no_overlap(scene, rp)
    assert final(tr, "ball")["position"][1] >= 0.1 - scene.tolerance


def test_ball_resting_on_a_ball_on_a_floor_does_not_pass_through():
    scene, tr, rp = run([floor(), ball("low"), ball("high", y=0.3)], end=0.5)
    no_overlap(scene, rp)
    assert final(tr, "high")["position"][1] >= 0.3 - 2 * scene.tolerance


def test_ball_at_rest_on_a_slope_does_not_pass_through():
    th = 0.3
    slope = floor(half=2.0, angle=th)
    # the ball touches the slope's top face: centre r along the face's normal
    cx, cy = slope["position"]
    top = (cx - 0.05 * math.sin(th), cy + 0.05 * math.cos(th))
    b = ball(x=round(top[0] - 0.1 * math.sin(th), 15), y=round(top[1] + 0.1 * math.cos(th), 15))
    scene, tr, rp = run([slope, b], end=0.5)
    no_overlap(scene, rp)
