"""The Modula-2 example of docs/engine-api.md ("Modula-2: SimLive"): the
program on that page, built against the world compiled for the scene's
effects, drives examples/newtons-cradle.json frame by frame with two live
inputs, and prints what the Python world (the reference) gives when driven
the same way: the first contact, the refused teleport, the number of
contacts and the striker's final position to the last bit."""
from __future__ import annotations

import os
from pathlib import Path
import re
import subprocess

import pytest

from max2code.sim.live import python_world
from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator
from max2code.toolchain.m2 import Modula2Toolchain

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
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


def _build_and_run(tmp_path, scene, module: str, source: str, scene_file: str, exe_name: str):
    """The Modula-2 program `module` (its text source) built against the
    simulator of the scene's effects, with the compiled scene in
    scene_file, and run in tmp_path: the finished process."""
    (tmp_path / f"{module}.mod").write_text(source, encoding="utf-8")
    (tmp_path / scene_file).write_text(compile_scene(scene), encoding="ascii")
    build = build_simulator("m2", scene.effects, scene.taylor_order)
    exe = str(tmp_path / exe_name)
    made = subprocess.run(Modula2Toolchain().sim_program_build(build.workdir, str(tmp_path / f"{module}.mod"), exe),
                          cwd=str(tmp_path), capture_output=True, text=True, timeout=600)
    assert made.returncode == 0, made.stderr[-3000:]
    return subprocess.run([exe], cwd=str(tmp_path), capture_output=True, text=True, timeout=60)


def test_the_modula2_example_runs_as_the_reference(tmp_path):
    scene = load_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    run = _build_and_run(tmp_path, scene, "WorldDemo", _program(), "cradle.scene", "demo")
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


ADD_PROGRAM = """MODULE AddDemo ;
FROM SYSTEM IMPORT ADR ;
FROM SimC IMPORT write, snprintf ;
FROM SimLive IMPORT Contact, FromFile, Advance, AddBody, Finish, Error ;

VAR
   text: ARRAY [0..4095] OF CHAR ;
   msg: ARRAY [0..511] OF CHAR ;
   k: INTEGER ;

PROCEDURE Check (c: Contact) ;
BEGIN
   IF c.t > 1.5 THEN HALT END
END Check ;

PROCEDURE Say (ok: BOOLEAN) ;
VAR
   line: ARRAY [0..1023] OF CHAR ;
   n: INTEGER ;
BEGIN
   line[0] := 0C ;
   IF ok THEN
      n := snprintf (ADR (line), 1023, "index %d", k)
   ELSE
      Error (msg) ;
      n := snprintf (ADR (line), 1023, "error %s", ADR (msg))
   END ;
   line[n] := 12C ;
   IF write (2, ADR (line), VAL (LONGCARD, n + 1)) # VAL (LONGINT, n + 1) THEN HALT END
END Say ;

BEGIN
   IF NOT FromFile ("scene.txt", TRUE) THEN HALT END ;
   IF NOT Advance (0.5, Check) THEN HALT END ;
%s
   IF NOT Advance (1.5, Check) THEN HALT END ;
   IF NOT Finish (Check) THEN HALT END
END AddDemo.
"""


def test_add_body_in_modula2_writes_the_reference_bytes(tmp_path):
    """SimLive.AddBody: refused where it overlaps (-1), a movable body too
    large for the cells is an error (the reference's message), a good one
    joins with the next index and lands on the floor: the trace is the
    Python world's byte for byte."""
    import io
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.live import flat_body
    from max2code.sim.scene import parse_scene
    raw = inputs_scene(1.5)
    raw["inputs"] = []
    scene = parse_scene(json.dumps(raw))
    drop = {"name": "drop", "shape": "circle", "radius": 0.08, "mass": 0.5, "position": [0.3, 1.5],
            "velocity": [0.0, -1.0]}
    crate = {"name": "box", "shape": "polygon", "mass": 1.0, "position": [1.5, 1.7], "angular_velocity": 2.0,
             "vertices": [[-0.1, -0.05], [0.1, -0.05], [0.1, 0.05], [-0.1, 0.05]]}
    bodies = [drop | {"position": [1.0, 0.0]}, drop, drop | {"radius": 5.0, "position": [30.0, 30.0]}, crate]
    texts = [" ".join(flat_body(scene, b).split()) for b in bodies]
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.5)
    expect = []
    for text in texts:
        try:
            expect.append(f"index {w.add_body(text)}")
        except Exception as exc:           # the reference's SimError
            expect.append(f"error {exc}")
    w.advance(1.5)
    w.finish()
    assert expect[0] == "index -1" and expect[2].startswith("error add_body: a movable body")
    calls = "\n".join(f'   text := "{t}" ;\n   Say (AddBody (text, k)) ;' for t in texts)
    run = _build_and_run(tmp_path, scene, "AddDemo", ADD_PROGRAM.replace("%s\n", calls + "\n", 1), "scene.txt",
                         "add")
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr
    assert run.stderr.splitlines() == expect
    assert run.stdout == out.getvalue()


SESSION_PROGRAM = """MODULE Session ;
FROM SYSTEM IMPORT ADR ;
FROM SimC IMPORT write, snprintf ;
FROM SimLive IMPORT Contact, FromFile, Advance, SetVelocity, AddVelocity, ApplyImpulse, Teleport, RemoveBody,
                    Finish, InputLogLength, InputLog, Added ;

VAR
   k, body, mode, n: INTEGER ;
   t, x, y: REAL ;
   moved: BOOLEAN ;
   line: ARRAY [0..255] OF CHAR ;

PROCEDURE Check (c: Contact) ;
BEGIN
   IF c.t > 2.0 THEN HALT END
END Check ;

PROCEDURE Ok (ok: BOOLEAN) ;
BEGIN
   IF NOT ok THEN HALT END
END Ok ;

BEGIN
   Ok (FromFile ("scene.txt", TRUE)) ;
   Ok (Advance (0.3, Check)) ;
   Ok (ApplyImpulse (%(ball)d, 0.5, 2.0)) ;
   Ok (SetVelocity (%(crate)d, 0.0, 1.0)) ;
   Ok (Advance (%(hit)s, Check)) ;
   Ok (AddVelocity (%(pebble)d, 0.1, 0.1)) ;
   Ok (Advance (0.5, Check)) ;
   Ok (Teleport (%(ball)d, 1.0, 1.2, moved)) ; Ok (moved) ;
   Ok (Teleport (%(crate)d, 1.0, -0.05, moved)) ; Ok (NOT moved) ;
   Ok (Advance (1.1, Check)) ;
   Ok (SetVelocity (%(pebble)d, 0.0, 0.0)) ;
   Ok (Advance (1.4, Check)) ;
   Ok (RemoveBody (%(ledge)d)) ;
   Ok (Advance (1.9, Check)) ;
   Ok (RemoveBody (%(pebble)d)) ;
   Ok (Finish (Check)) ;
   Ok (Added () = 0) ;
   FOR k := 0 TO InputLogLength () - 1 DO
      Ok (InputLog (k, t, body, mode, x, y)) ;
      line[0] := 0C ;
      n := snprintf (ADR (line), 255, "%%.17g %%d %%d %%.17g %%.17g", t, body, mode, x, y) ;
      line[n] := 12C ;
      Ok (write (2, ADR (line), VAL (LONGCARD, n + 1)) = VAL (LONGINT, n + 1))
   END
END Session.
"""


def test_a_modula2_session_is_recorded_and_replays_in_the_batch_simulators(tmp_path):
    """The live session of tests/runtimes/test_world.py's recording test driven from
    Modula-2 (inputs at an event's exact time and at the scene's own input
    times, a refused teleport, removals): its input log (InputLog) made into
    a recording (max2code.sim.recording) replays the session's trace byte
    for byte in the Modula-2 and the Python batch simulators."""
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.recording import recording
    from max2code.sim.scene import parse_scene
    from max2code.sim.simulate import run_scene
    raw = inputs_scene(2.0, remove=True)
    raw["inputs"] = [{"time": 0.5, "body": "crate", "set_velocity": [-1.0, 2.0]},
                     {"time": 1.1, "body": "pebble", "teleport": [1.0, 0.7]}]
    path = str(tmp_path / "scene.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(raw, fh)
    scene = load_scene(path)
    names = {b.name: k for k, b in enumerate(scene.bodies)}
    hit = python_world(scene).advance(0.45)[3].t               # an event's exact time
    run = _build_and_run(tmp_path, scene, "Session", SESSION_PROGRAM % dict(names, hit=repr(hit).replace("e", "E")),
                         "scene.txt", "session")
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr
    log = [(float(t), int(b), int(m), float(x), float(y)) for t, b, m, x, y in map(str.split, run.stderr.splitlines())]
    assert len(log) == 2 + 7
    rec = parse_scene(json.dumps(recording(path, log)), "recording.json")
    for lang in ("m2", "python"):
        assert run_scene(rec, lang).raw == run.stdout, lang


CHECK_PROGRAM = """MODULE LiveChecks ;
FROM SYSTEM IMPORT ADR ;
FROM SimC IMPORT write, snprintf ;
FROM SimLive IMPORT Contact, FromFile, Advance, AddBody, SetVelocity, ApplyImpulse, Teleport, Finish, Error ;

VAR
   text: ARRAY [0..4095] OF CHAR ;
   msg: ARRAY [0..511] OF CHAR ;
   k: INTEGER ;
   moved: BOOLEAN ;

PROCEDURE Check (c: Contact) ;
BEGIN
   IF c.t > 1.5 THEN HALT END
END Check ;

PROCEDURE Say (ok: BOOLEAN) ;
VAR
   line: ARRAY [0..1023] OF CHAR ;
   n: INTEGER ;
BEGIN
   line[0] := 0C ;
   IF ok THEN
      n := snprintf (ADR (line), 1023, "ok")
   ELSE
      Error (msg) ;
      n := snprintf (ADR (line), 1023, "error %s", ADR (msg))
   END ;
   line[n] := 12C ;
   IF write (2, ADR (line), VAL (LONGCARD, n + 1)) # VAL (LONGINT, n + 1) THEN HALT END
END Say ;

BEGIN
   IF NOT FromFile ("scene.txt", TRUE) THEN HALT END ;
   IF NOT Advance (0.5, Check) THEN HALT END ;
(*BEFORE*)
   IF NOT Advance (1.5, Check) THEN HALT END ;
   IF NOT Finish (Check) THEN HALT END ;
(*AFTER*)
END LiveChecks.
"""


def test_modula2_add_body_is_checked_and_the_live_api_refuses_without_changing_the_world(tmp_path):
    """SimLive.AddBody checks its text as a scene's body is checked
    (docs/simulator.md, "Flat scene checks", WHAT = add_body); inputs whose
    velocity would not be finite, far teleports and unknown bodies are
    refused, and so is every input or AddBody after Finish.  Refused calls
    leave the world as it was: the trace is the Python world's without them."""
    import io
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.live import flat_body
    from max2code.sim.scene import parse_scene
    raw = inputs_scene(1.5)
    raw["inputs"] = []
    scene = parse_scene(json.dumps(raw))
    ball = next(i for i, b in enumerate(raw["bodies"]) if b["name"] == "ball")
    pebble = next(i for i, b in enumerate(raw["bodies"]) if b["name"] == "pebble")   # 0.2 kg: 1e308 N s is too much
    n = len(raw["bodies"])
    drop = {"name": "drop", "shape": "circle", "radius": 0.08, "mass": 0.5, "position": [0.3, 1.5],
            "velocity": [0.0, -1.0]}
    good = " ".join(flat_body(scene, drop).split())
    words = good.split()

    def with_field(k: int, value: str) -> str:
        return " ".join(words[:1 + k] + [value] + words[2 + k:])

    # body-line fields after "body": poly fixed inv_mass inv_inertia restitution friction ...
    cases = [(with_field(4, "5"), f"add_body: body {n}: restitution 5 outside [0, 1]"),
             (with_field(2, "nan"), "add_body: expected a number, found 'nan'"),
             (with_field(2, "-1"), f"add_body: body {n}: inverse mass -1 must be positive"),
             (with_field(13, "1.0"), f"add_body: body {n}: a circle turns only about an orbit"),
             (with_field(0, "+1"), "add_body: expected an integer, found '+1'"),
             (good + " foo", "add_body: unexpected 'foo' after the body"),
             (" ".join(words[:-3]), "add_body: ends early")]
    before = [f'   text := "{t}" ;\n   Say (AddBody (text, k)) ;' for t, _ in cases]
    expect = [f"error {m}" for _, m in cases]
    before += [f"   Say (ApplyImpulse ({pebble}, 1.0E308, 0.0)) ;",
               f"   Say (Teleport ({ball}, 1.0E200, 0.0, moved)) ;",
               "   Say (SetVelocity (99, 0.0, 0.0)) ;",
               "   Say (SetVelocity (-1, 0.0, 0.0)) ;"]
    expect += [f"error live input: body {pebble}: velocity would not be finite",
               f"error live input: body {ball}: teleport beyond 1e150 m",
               "error live input: body 99 does not exist",
               "error live input: body -1 does not exist"]
    after = [f"   Say (SetVelocity ({ball}, 0.0, 0.0)) ;",
             f"   Say (Teleport ({ball}, 0.5, 0.5, moved)) ;",
             f'   text := "{good}" ;\n   Say (AddBody (text, k)) ;']
    expect += ["error live input: the world is finished"] * 3
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.5)
    w.advance(1.5)
    w.finish()
    source = CHECK_PROGRAM.replace("(*BEFORE*)", "\n".join(before)).replace("(*AFTER*)", "\n".join(after))
    run = _build_and_run(tmp_path, scene, "LiveChecks", source, "scene.txt", "checks")
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr
    assert run.stderr.splitlines() == expect
    assert run.stdout == out.getvalue()
