"""Turning bodies cost few predictions and stay exact:
a spinning polygon against a body that does not turn is bounded by its
bounding circle against that body itself, so windows open only near it."""
from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from max2code.conformance.exact_ref import reference
from max2code.sim.invariants import check, energy_growth
from max2code.sim.replay import read_trace
from max2code.sim.scene import load_scene, parse_scene
from max2code.sim.simulate import run_scene
from sim_scenes import spinning_scene  # noqa: E402
from test_contact import runtimes  # noqa: E402

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def graze_scene(ceiling_vy: float, omega: float, angle: float) -> dict:
    """A square (half side 0.1, bounding radius 0.1414) thrown up under a
    weak gravity so that its bounding circle crosses a long ceiling's face
    (y = 1) while it spins: a corner reaches the face on the way."""
    half = 0.1
    return {"name": "graze", "end_time": 1.0, "tolerance": 1e-12, "gravity": [0.0, -2.0],
            "bodies": [{"name": "ceiling", "shape": "polygon", "fixed": True, "position": [0.0, 1.05],
                        "velocity": [0.0, ceiling_vy],
                        "vertices": [[-3.0, -0.05], [3.0, -0.05], [3.0, 0.05], [-3.0, 0.05]]},
                       {"name": "square", "shape": "polygon", "mass": 1.0, "position": [0.0, 0.8],
                        "velocity": [0.3, 0.8], "angle": angle, "angular_velocity": omega,
                        "vertices": [[-half, -half], [half, -half], [half, half], [-half, half]]}]}


def exact_first_contact(raw: dict) -> float:
    """The earliest time a corner of the square meets the ceiling's face in
    the exact motion (real sin), from the exact-motion reference
    (max2code.conformance.exact_ref, mpmath): per corner, the point-line gap
    face - (y + vy t + ay t^2/2 + rho sin(w t + angle + beta))."""
    ceiling, sq = raw["bodies"]
    face = ceiling["position"][1] - 0.05
    g = raw["gravity"][1]
    best = None
    for x, y in sq["vertices"]:
        p = {"a": face, "b": ceiling["velocity"][1], "c": 0.0, "d": 0.0, "e": 0.0, "f": 0.0,
             "g": sq["position"][1], "h": sq["velocity"][1], "i": g, "j": math.hypot(x, y),
             "k": sq["angular_velocity"], "l": sq["angle"] + math.atan2(y, x)}
        ref = reference("point-line", p, raw["end_time"])
        assert ref.expect != "overlapped"
        if ref.expect is not None and (best is None or ref.expect < best):
            best = ref.expect
    return best


@pytest.mark.parametrize("ceiling_vy", [0.0, -0.05], ids=["still-wall", "moving-wall"])
@pytest.mark.parametrize("omega,angle", [(1.5, 0.3), (-2.5, 0.2), (4.0, 1.1)])
def test_a_spinning_polygon_grazing_a_long_wall_collides_at_the_exact_time(ceiling_vy, omega, angle):
    raw = graze_scene(ceiling_vy, omega, angle)
    want = exact_first_contact(raw)
    assert want is not None and want > 0.05
    scene = parse_scene(json.dumps(raw), "graze.json")
    tr = run_scene(scene, "python")
    hits = [e for e in tr.events if e["kind"] in ("collision", "support")]
    assert hits and hits[0]["bodies"] == ["square", "ceiling"]
    # the Taylor windows keep the gap within the tolerance (1e-12 m); the
    # corner meets the face at >= 0.05 m/s here, so 1e-10 s is generous
    assert abs(hits[0]["t"] - want) <= 1e-10, (hits[0]["t"], want)


def test_spinning_polygons_need_few_horizons_per_collision():
    """examples/spinning-polygons.json: at most 5 horizon events per
    collision (6,694 for 35 collisions before the bound against the walls
    themselves: the walls' bounding circles always overlap)."""
    tr = run_scene(load_scene(os.path.join(ROOT, "examples", "spinning-polygons.json")), "python")
    n = tr.stats["events"]          # the trace's N lines
    assert n["collisions"] >= 30
    assert n["horizons"] <= 5 * n["collisions"], n


# derandomized: about 1 seed in 100 of this family met the corner-to-corner
# pinch of the test that follows (stuck) before the "Corners" and "Held
# contacts" rules; a free draw stays out of CI so that a case still unknown
# cannot fail it now and then
@settings(max_examples=8, deadline=None, derandomize=True)
@given(seed=st.integers(0, 10 ** 6))
def test_spinning_polygons_in_boxes_never_overlap(seed):
    raw = spinning_scene(seed)
    scene = parse_scene(json.dumps(raw), f"spinning-{seed}.json")
    tr = run_scene(scene, "python")
    rp = read_trace("\n".join(tr.lines()), scene, f"spinning-{seed}.json")
    rep = check(scene, rp, kinds=("collision", "support", "stop", "leave", "sleep", "wake", "frame"))
    assert rep.max_overlap <= scene.tolerance, (seed, rep)


def _finishes_cleanly(seed, lang):
    """spinning_scene(seed), at most 1000 events at one instant, run in lang:
    no overlap beyond the tolerance at any event or frame, energy never grows."""
    raw = spinning_scene(seed)
    raw["max_events_at_one_time"] = 1000
    name = f"spinning-{seed}.json"
    scene = parse_scene(json.dumps(raw), name)
    tr = run_scene(scene, lang)
    rp = read_trace("\n".join(tr.lines()), scene, name)
    rep = check(scene, rp, kinds=("collision", "support", "stop", "leave", "sleep", "wake", "frame"))
    assert rep.max_overlap <= scene.tolerance, rep
    er = energy_growth(scene, rp)
    assert er.instants > 0 and er.max_growth <= 1e-12, er


@pytest.mark.parametrize("lang", runtimes("stuck", "held"))
def test_corner_meets_corner_in_a_spinning_scene(lang):
    """Found in 1 of 100 seeds of spinning_scene (stuck at one instant in
    every runtime): a spinning pentagon comes to rest on the floor with a
    corner on a resting triangle's corner at floor level.  A corner was
    accepted against a face whose line does not separate them ("Corners"),
    and the impulses between the two supported bodies ended their supports,
    which the floor took back at once ("Held contacts"): more than 100000
    events at one instant.  It finishes, with no overlap beyond the
    tolerance and no gain of energy."""
    _finishes_cleanly(984787, lang)


@pytest.mark.parametrize("lang", runtimes("hopfloor"))
def test_a_polygon_resting_on_a_sliding_polygon_never_gains_energy(lang):
    """Found by a seed hunt: a spinning hexagon comes to rest
    on a square that is supported and slides on the floor; the pair hops and
    the square meets the floor again at once.  The hops at the floor speed
    added 1.4e-9 relative; now paid from the pair's common motion
    (docs/simulator.md 'Hop', see test_contact.py,
    test_a_ball_resting_on_a_sliding_box_never_gains_energy)."""
    raw = spinning_scene(26)
    scene = parse_scene(json.dumps(raw), "spinning-26.json")
    tr = run_scene(scene, lang)
    rp = read_trace("\n".join(tr.lines()), scene, "spinning-26.json")
    er = energy_growth(scene, rp)
    assert er.instants > 0 and er.max_growth <= 1e-12, er


@pytest.mark.parametrize("lang", runtimes("wedged"))
def test_random_spinning_scene_64739_finishes(lang):
    """Found by a seed hunt (200 random spinning scenes, 1
    stuck at one instant in every runtime): polygon p6 wedged between the
    right wall and polygon p1, which sleeps on the floor; each hit woke p1,
    which was supported and fell asleep again at once, a cycle at one
    instant.  The contacts are solved together (docs/simulator.md, "Contact
    model: simultaneous contacts"): it finishes, with no overlap beyond the
    tolerance and no gain of energy."""
    _finishes_cleanly(64739, lang)
