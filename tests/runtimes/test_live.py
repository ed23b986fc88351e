"""Python on the C engine (max2code/sim/live.py, cworld.py): the compiled C
world through ctypes gives the same contacts and states as the pure-Python
reference World, call for call, and the same trace bytes as the batch
simulator when advanced a frame at a time."""
from __future__ import annotations

import io
import math
import os
from pathlib import Path
import subprocess

import pytest

from max2code.sim.live import as_scene, open_world
from max2code.sim.scene import compile_scene
from max2code.sim.simulate import build_simulator
from max2code_rt.sim import SimError

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
# scenes the Python reference plays in a few seconds (gravity-box takes a minute)
SCENES = ["platformer.json", "billiard-break.json", "newtons-cradle.json", "resting-ball.json"]


def _play(world, scene, fps=60.0):
    """Advance frame by frame; every contact and every body's state at every frame."""
    got = []
    n = math.floor(scene.end_time * fps)
    for k in range(1, n + 1):
        t = k / fps
        for c in world.advance(t):
            got.append(("contact", c.t, c.a, c.b, c.feature, c.i, c.j, c.px, c.py, c.nx, c.ny, c.impulse))
        one_by_one = tuple(world.state(b, t) for b in range(len(scene.bodies)))
        assert tuple(world.states(t)) == one_by_one
        got.append(("states", t, one_by_one))
    return got


@pytest.mark.parametrize("name", SCENES)
def test_c_world_equals_python_world(name):
    scene = as_scene(os.path.join(ROOT, "examples", name))
    c = _play(open_world(scene, "c"), scene)
    py = _play(open_world(scene, "python"), scene)
    assert any(x[0] == "contact" for x in py), "no contacts: the comparison would be vacuous"
    assert len(c) == len(py)
    for a, b in zip(c, py):
        assert a == b


@pytest.mark.parametrize("name", ["platformer.json", "pinball.json"])
def test_c_world_in_frames_writes_the_batch_trace(name):
    """Advanced at 60 frames per second, finished, the C world's trace (passed
    to a Python object through its temporary file) is the batch simulator's."""
    scene = as_scene(os.path.join(ROOT, "examples", name))
    buf = io.StringIO()
    w = open_world(scene, "c", out=buf)
    _play(w, scene, fps=60.0)
    w.finish()
    w.close()
    build = build_simulator("c", scene.effects, scene.taylor_order)
    ref = subprocess.run(build.run_cmd, input=compile_scene(scene), capture_output=True, text=True,
                         cwd=build.workdir, check=True).stdout
    assert ref.count("\nE ") > 10
    assert buf.getvalue() == ref


@pytest.mark.parametrize("engine", ["c", "python"])
def test_errors_are_the_references(engine):
    scene = as_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    w = open_world(scene, engine)
    w.advance(0.5)
    assert w.time == 0.5
    nxt = w.next_event_time()
    assert 0.5 <= nxt < math.inf
    with pytest.raises(SimError, match="outside"):
        w.state(0, nxt + 1.0)
    with pytest.raises(SimError, match="no body"):
        w.state(len(scene.bodies), 0.5)
    with pytest.raises(SimError, match="outside"):
        w.states(nxt + 1.0)
    assert len(w.states(0.5)) == len(scene.bodies)
    with pytest.raises(SimError):
        w.advance(0.25)


def test_open_world_refuses_an_unknown_engine():
    with pytest.raises(ValueError, match="engine"):
        open_world(os.path.join(ROOT, "examples", "newtons-cradle.json"), "fortran")


def _session(world, scene):
    """A scripted play of live inputs on the platformer's hero: walk, jump, a
    push, an impulse, a teleport onto a ledge and one into the ground
    (refused); every contact, answer and drawn state."""
    hero = len(scene.bodies) - 1
    plan = {30: ("set_velocity", 1.5, 0.0), 72: ("set_velocity", 2.2, 5.6), 100: ("add_velocity", -0.5, 0.0),
            140: ("apply_impulse", 0.0, 3.0), 170: ("teleport", 4.6, 2.6), 200: ("teleport", 4.0, -0.1),
            230: ("set_velocity", -1.0, 4.0)}
    got = []
    for k in range(1, 300):
        t = k / 60.0
        got += [("contact", c.t, c.a, c.b, c.feature, c.i, c.j, c.px, c.py, c.nx, c.ny, c.impulse, c.support)
                for c in world.advance(t)]
        if k in plan:
            op, x, y = plan[k]
            got.append((op, getattr(world, op)(hero, x, y)))
        got.append(("states", t, tuple(world.state(b, t) for b in range(len(scene.bodies)))))
    return got


def test_live_inputs_same_in_both_engines():
    scene = as_scene(os.path.join(ROOT, "examples", "platformer.json"))
    bufs = {e: io.StringIO() for e in ("c", "python")}
    runs, logs = {}, {}
    for engine in ("c", "python"):
        w = open_world(scene, engine, out=bufs[engine])
        runs[engine] = _session(w, scene)
        w.finish()
        # the input log a recording writes
        logs[engine] = w.input_log()
        if engine == "c":
            w.close()
    answers = [x for x in runs["python"] if x[0] == "teleport"]
    assert answers == [("teleport", True), ("teleport", False)]
    assert runs["c"] == runs["python"]
    assert bufs["c"].getvalue() == bufs["python"].getvalue()
    assert bufs["c"].getvalue().count("E input") == 6 + len(scene.inputs)
    assert logs["c"] == logs["python"] and len(logs["c"]) == 6 + len(scene.inputs)   # the refused teleport: not logged


@pytest.mark.parametrize("engine", ["c", "python"])
def test_a_removed_body_is_gone(engine):
    """remove_body through the binding: the ball leaves the cradle's chain, so
    no contact names it afterwards and the log holds the removal (MODE 4)."""
    scene = as_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    w = open_world(scene, engine)
    k = next(i for i, b in enumerate(scene.bodies) if b.name == "ball2")
    w.advance(0.25)
    w.remove_body(k)
    after = w.advance(2.5)
    assert after and all(k not in (c.a, c.b) for c in after)
    log = w.input_log()
    assert log[-1] == (0.25, k, 4, 0.0, 0.0)
