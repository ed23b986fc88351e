"""All four runtimes' simulators give the same sequence of events (kinds,
bodies, features, times within 1e-9 relative) on every example scene and
on 20 random scenes and random scenes of resting and sliding circles, through `max2code crosscheck`'s own comparison; in
fact they write the same bytes, which is checked too."""
from __future__ import annotations

import glob
import json
import os
from pathlib import Path
import tempfile

import pytest
from hypothesis import given, settings, strategies as st

from max2code.sim.scene import load_scene
from max2code.sim.commands import crosscheck
from max2code.sim.simulate import LANGS
from sim_scenes import resting_scene, spinning_scene, write_random_scenes  # noqa: E402

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "*.json")))


def _agree(path):
    scene = load_scene(path)
    traces, problems = crosscheck(scene, LANGS)
    assert not problems, problems
    ref = traces[LANGS[0]]
    assert ref.events, "no events at all"
    for lang, tr in traces.items():
        assert tr.raw == ref.raw, f"{lang} agrees within 1e-9 but does not write the same bytes as {LANGS[0]}"


@pytest.mark.parametrize("path", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_examples_agree_in_all_four_runtimes(path):
    _agree(path)


@pytest.fixture(scope="module")
def random_scenes(tmp_path_factory):
    return write_random_scenes(str(tmp_path_factory.mktemp("scenes")), range(20))


@pytest.mark.parametrize("k", range(20))
def test_random_scenes_agree_in_all_four_runtimes(random_scenes, k):
    _agree(random_scenes[k])


def test_crosscheck_reports_the_first_difference():
    """The comparison is not vacuous: a trace with one time moved by 1e-8
    relative is reported at that event."""
    from max2code.sim.commands import compare
    from max2code.sim.simulate import run_scene
    import copy
    scene = load_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    a = run_scene(scene, "python")
    b = copy.deepcopy(a)
    b.lang = "altered"
    k = next(i for i, e in enumerate(b.events) if e["kind"] == "collision")
    b.events[k]["t"] *= 1 + 1e-8
    d = compare(a, b)
    assert d is not None and d.index == k and "times differ" in d.what
    c = copy.deepcopy(a)
    c.events[k]["bodies"] = list(reversed(c.events[k]["bodies"]))
    assert compare(a, c).index == k
    assert compare(a, copy.deepcopy(a)) is None


@settings(max_examples=4, deadline=None, derandomize=True)
@given(st.integers(min_value=0, max_value=10**6))
def test_random_resting_scenes_agree_in_all_four_runtimes(seed):
    """Circles dropped, placed at rest and sliding on floors and slopes
    (support, stop and leave events): the four runtimes write the same bytes."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, f"resting-{seed}.json")
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(resting_scene(seed, boxes=False), fh)
        _agree(path)


def _agree_raw(raw, name):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, name)
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(raw, fh)
        _agree(path)


def _box(name, x, y, half, **kw):
    b = {"name": name, "shape": "polygon", "mass": 1.0, "position": [x, y],
         "vertices": [[-half, -half], [half, -half], [half, half], [-half, half]]}
    b.update(kw)
    return b


def test_a_stack_carried_by_a_driven_plank_agrees_in_all_four_runtimes():
    """Carried bodies (docs/simulator.md, "Carried bodies") under every change
    of their base's motion: a fixed plank under a box, a smaller box and a
    ball, all at rest; the plank is driven (set_velocity) and stopped, the
    base box is pushed, the middle box removed.  The four runtimes write the
    same bytes, and the run goes through supports, leaves, sleeps and wakes."""
    raw = {"end_time": 2.0, "gravity": [0.0, -9.81], "frame_rate": 20, "bodies": [
        {"name": "plank", "shape": "polygon", "fixed": True, "position": [0.0, -0.05], "friction": 1.0,
         "vertices": [[-2.0, -0.05], [2.0, -0.05], [2.0, 0.05], [-2.0, 0.05]]},
        _box("base", 0.0, 0.1, 0.1, friction=1.0),
        _box("mid", 0.02, 0.25, 0.05, friction=1.0),
        {"name": "top", "shape": "circle", "radius": 0.05, "mass": 1.0, "position": [0.03, 0.35], "friction": 1.0}],
        "inputs": [{"time": 0.2, "body": "plank", "set_velocity": [0.4, 0.0]},
                   {"time": 0.7, "body": "plank", "set_velocity": [0.0, 0.0]},
                   {"time": 1.0, "body": "base", "set_velocity": [0.3, 0.0]},
                   {"time": 1.3, "body": "mid", "remove": True}]}
    _agree_raw(raw, "driven-stack.json")


@pytest.mark.parametrize("seed,boxes", [(1909, False), (244, True), (47, True), (33, True)])
def test_scenes_whose_hops_pay_the_floor_agree_in_all_four_runtimes(seed, boxes):
    """The seed hunt's scenes where a hop at the floor speed is paid from the
    pair's common motion, or a sleeper's touch is not gentle because its hop
    could not be (docs/simulator.md, "Hop"): the four runtimes write the same bytes."""
    _agree_raw(resting_scene(seed, boxes=boxes), f"resting-{seed}{'-boxes' if boxes else ''}.json")


@pytest.mark.parametrize("family,seed", [("resting", 993908), ("resting", 15095), ("resting", 788526),
                                         ("spinning", 64739)])
def test_wedged_scenes_solved_together_agree_in_all_four_runtimes(family, seed):
    """The seed hunts' wedged scenes, whose contacts are solved together
    (docs/simulator.md, "Contact model: simultaneous contacts": cluster,
    sequential impulses, separation, sleeping where the contacts hold): the
    four runtimes write the same bytes through the whole rule."""
    raw = resting_scene(seed, boxes=True) if family == "resting" else spinning_scene(seed)
    raw["max_events_at_one_time"] = 1000
    _agree_raw(raw, f"{family}-{seed}.json")
