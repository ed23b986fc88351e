"""The Modula-2 example of docs/engine-api.md ("Modula-2: SimWorld"): the
program on that page, built against the world compiled for the scene's
effects, drives examples/newtons-cradle.json frame by frame with two live
inputs, and prints what the Python world (the reference) gives when driven
the same way: the first contact, the refused teleport, the number of
contacts and the striker's final position to the last bit."""
from __future__ import annotations

import os
import re
import subprocess

from max2code.sim.live import python_world
from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator
from max2code.targets.m2 import Modula2

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRIKER = 4


def _program() -> str:
    doc = open(os.path.join(ROOT, "docs", "engine-api.md"), encoding="utf-8").read()
    section = doc[doc.index("## Modula-2"):]
    return re.search(r"```modula2\n(.*?)```", section, re.S).group(1)


def _reference(scene):
    """The example's loop on the Python world."""
    w = python_world(scene)
    frame = 1.0 / 60.0
    got, refused = [], None
    k = 1
    while k * frame < scene.end_time:
        got += w.advance(k * frame)
        w.state(STRIKER, w.time)
        if k == 60:
            refused = not w.teleport(STRIKER, 0.7, 0.02)
            w.apply_impulse(STRIKER, 0.0, 0.05)
        k += 1
    got += w.finish()
    return got, refused, w.state(STRIKER, scene.end_time)


def test_the_modula2_example_runs_as_the_reference(tmp_path):
    scene = load_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    build = build_simulator("m2", scene.effects, scene.taylor_order)
    (tmp_path / "WorldDemo.mod").write_text(_program(), encoding="utf-8")
    (tmp_path / "cradle.scene").write_text(compile_scene(scene), encoding="ascii")
    exe = str(tmp_path / "demo")
    cmd = Modula2().sim_program_build(build.workdir, str(tmp_path / "WorldDemo.mod"), exe)
    made = subprocess.run(cmd, cwd=str(tmp_path), capture_output=True, text=True, timeout=600)
    assert made.returncode == 0, made.stderr[-3000:]
    run = subprocess.run([exe], cwd=str(tmp_path), capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    contacts, refused, (x, y, *_rest) = _reference(scene)
    first = contacts[0]
    assert lines[0] == f"first contact: bodies {first.a} and {first.b}, impulse {first.impulse:.5f}"
    assert refused and lines[1] == "teleport refused"
    assert lines[2] == f"contacts: {len(contacts)}"
    words = lines[3].split()
    assert words[:4] == ["striker", "at", "the", "end:"]
    assert (float(words[4]), float(words[5])) == (x, y)       # 17 significant digits: the same double
