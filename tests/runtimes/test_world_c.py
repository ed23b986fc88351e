"""The C world API (runtimes/c/include/m2c_world.h, docs/engine-api.md):
the example program of the docs compiles warning-free against the
libm2c_world.so that world_library builds beside the simulator and reports
the contacts of the batch trace; the library is built on demand, not by the
simulator's build; two worlds at once, driven in different steps through
ctypes, write the batch bytes."""
from __future__ import annotations

import ctypes
import math
import os
from pathlib import Path
import subprocess

import pytest

from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator, run_scene, world_library
from max2code.toolchain.c import FLAGS, WORLD_LIBRARY, CToolchain

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
INCLUDE = os.path.join(ROOT, "runtimes", "c", "include")
EXAMPLE = os.path.join(ROOT, "runtimes", "c", "examples", "world_loop.c")


def test_the_world_library_is_built_on_demand_once_per_simulator_build():
    """The simulator's build makes only its program (`max2code simulate` needs
    no shared library); world_library makes the library from the same
    generated files and the same simulator build, and a second call finds it
    made (its stamp names the simulator build it was made from)."""
    scene = load_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    build = build_simulator("c", scene.effects, scene.taylor_order)
    variants = {eq: len(n) for eq, n in build.variant_names.items()}
    program = CToolchain().sim_build(build.workdir, build.generated, variants)
    world = CToolchain().world_build(build.workdir, build.generated, variants)
    assert not any(WORLD_LIBRARY in arg or arg == "-fPIC" for cmd in program for arg in cmd)
    assert world[-1][world[-1].index("-o") + 1] == os.path.join(build.workdir, WORLD_LIBRARY)
    assert all(g in (arg for cmd in world for arg in cmd) for g in build.generated.values())
    lib = world_library(scene)
    assert lib == Path(build.workdir) / WORLD_LIBRARY and lib.exists()
    stamps = Path(build.workdir) / "world.stamp", Path(build.workdir) / "build.stamp"
    assert stamps[0].read_text() == stamps[1].read_text()
    made = lib.stat().st_mtime_ns
    assert world_library(scene) == lib and lib.stat().st_mtime_ns == made


def test_the_docs_example_program_runs(tmp_path):
    scene = load_scene(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    lib = world_library(scene)
    exe = tmp_path / "world_loop"
    subprocess.run([*FLAGS, f"-I{INCLUDE}", EXAMPLE, str(lib), f"-Wl,-rpath,{lib.parent}", "-lm", "-o", str(exe)],
                   check=True)
    flat = tmp_path / "cradle.txt"
    flat.write_text(compile_scene(scene))
    out = subprocess.run([str(exe), str(flat), "1"], capture_output=True, text=True, check=True).stdout.splitlines()
    batch = run_scene(scene, "c")
    contacts = [e for e in batch.events if e["kind"] in ("collision", "support")]
    assert sum(1 for line in out if line.startswith("contact ")) == len(contacts) > 0
    assert out[-1].startswith(f"{len(contacts)} contacts")
    assert sum(1 for line in out if line.startswith("frame ")) == int(scene.end_time * 60) // 30
    bad = subprocess.run([str(exe), str(tmp_path / "missing.txt"), "0"], capture_output=True, text=True)
    assert bad.returncode == 1 and "missing.txt" in bad.stderr


class _Lib:
    """The C world through ctypes (the calls this test needs)."""

    def __init__(self, path):
        lib = ctypes.CDLL(str(path))
        vp, d = ctypes.c_void_p, ctypes.c_double
        lib.m2c_world_new.restype = vp
        lib.m2c_world_new.argtypes = [ctypes.c_char_p, vp]
        lib.m2c_world_advance.argtypes = [vp, d, vp, vp]
        lib.m2c_world_finish.argtypes = [vp, vp, vp]
        lib.m2c_world_free.argtypes = [vp]
        lib.m2c_world_error.restype = ctypes.c_char_p
        lib.m2c_world_error.argtypes = [vp]
        lib.m2c_world_last_error.restype = ctypes.c_char_p
        lib.m2c_world_next_event_time.restype = d
        lib.m2c_world_next_event_time.argtypes = [vp]
        lib.m2c_world_time.restype = d
        lib.m2c_world_time.argtypes = [vp]
        self.lib = lib
        libc = ctypes.CDLL(None)
        libc.fopen.restype = vp
        libc.fopen.argtypes = [ctypes.c_char_p, ctypes.c_char_p]
        libc.fclose.argtypes = [vp]
        self.libc = libc


@pytest.mark.parametrize("name", ["platformer.json", "spinning-polygons.json"])
def test_two_worlds_at_once_write_the_batch_bytes(tmp_path, name):
    scene = load_scene(os.path.join(ROOT, "examples", name))
    c = _Lib(world_library(scene))
    lib, flat = c.lib, compile_scene(scene).encode()
    files = [c.libc.fopen(str(tmp_path / f"w{k}.txt").encode(), b"w") for k in range(2)]
    worlds = [lib.m2c_world_new(flat, f) for f in files]
    assert all(worlds), lib.m2c_world_last_error()
    end, t, steps = scene.end_time, 0.0, 0
    while t < end:                          # world 1 in steps of 0.013 s, asking for the next event each time
        t = min(end, t + 0.013)
        assert lib.m2c_world_advance(worlds[1], t, None, None) == 0, lib.m2c_world_error(worlds[1])
        assert lib.m2c_world_next_event_time(worlds[1]) >= t
        steps += 1
        if steps % 50 == 0:                 # world 0 catches up now and then
            assert lib.m2c_world_advance(worlds[0], t / 2, None, None) == 0
    assert lib.m2c_world_advance(worlds[0], end, None, None) == 0
    assert lib.m2c_world_advance(worlds[0], end / 2, None, None) == -1      # time never goes back
    assert b"outside" in lib.m2c_world_error(worlds[0])
    for w in worlds:
        assert lib.m2c_world_finish(w, None, None) == 0
        lib.m2c_world_free(w)
    for f in files:
        c.libc.fclose(f)
    batch = run_scene(scene, "c").raw
    assert (tmp_path / "w0.txt").read_text() == batch
    assert (tmp_path / "w1.txt").read_text() == batch
    assert lib.m2c_world_new(b"m2c-scene 9", None) is None
    assert b"version" in lib.m2c_world_last_error()


def _c_session(scene, path, ops):
    """The flat trace of the C world with the ops [(t, name, body, x, y)]
    made live (advance to t first), then finished; and what each returned."""
    from max2code.sim.live import python_world  # noqa: F401  (the same scene compile as the reference's)
    c = _Lib(world_library(scene))
    lib = c.lib
    for name in ("set_velocity", "add_velocity", "apply_impulse", "teleport"):
        f = getattr(lib, f"m2c_world_{name}")
        f.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_double]
    fh = c.libc.fopen(str(path).encode(), b"w")
    w = lib.m2c_world_new(compile_scene(scene).encode(), fh)
    results = []
    for t, name, body, x, y in ops:
        assert lib.m2c_world_advance(w, t, None, None) == 0, lib.m2c_world_error(w)
        results.append(getattr(lib, f"m2c_world_{name}")(w, body, x, y))
    assert lib.m2c_world_finish(w, None, None) == 0, lib.m2c_world_error(w)
    lib.m2c_world_free(w)
    c.libc.fclose(fh)
    return path.read_text(), results


def _py_session(scene, ops):
    import io
    from max2code.sim.live import python_world
    out = io.StringIO()
    w = python_world(scene, out)
    results = []
    for t, name, body, x, y in ops:
        w.advance(t)
        r = getattr(w, name)(body, x, y)
        results.append(int(r) if name == "teleport" else 0)
    w.finish()
    return out.getvalue(), results


def test_live_inputs_and_teleports_refused_or_made_as_the_reference(tmp_path):
    """Teleports of a circle, a turned box and a small circle to a grid of
    places over the box (into walls, the floor, each other, free space),
    with velocity inputs between: C refuses exactly the teleports the
    reference refuses and writes its bytes."""
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.scene import parse_scene
    scene = parse_scene(json.dumps(inputs_scene(2.0) | {"inputs": []}))
    names = [b.name for b in scene.bodies]
    ops, t = [], 0.0
    grid = [-0.05 + 0.3 * k for k in range(8)]
    for n, who in enumerate(("ball", "crate", "pebble")):
        for k, (x, y) in enumerate((x, y) for x in grid for y in grid):
            t = round(t + 0.007, 6)
            ops.append((t, "teleport", names.index(who), x, y))
            if k % 9 == 0:
                ops.append((t, ("set_velocity", "add_velocity", "apply_impulse")[(k // 9) % 3], names.index(who),
                            0.3 - 0.1 * n, 0.2))
    assert t < scene.end_time
    ref, want = _py_session(scene, ops)
    got_trace, got = _c_session(scene, tmp_path / "c.txt", ops)
    assert got == want
    assert 0 < sum(want) < len([o for o in ops if o[1] == "teleport"])      # some refused, some made
    assert got_trace == ref


def test_a_scripted_teleport_into_overlap_is_the_references_error():
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.scene import parse_scene
    from max2code.sim.simulate import SimulateError
    raw = inputs_scene(1.0)
    raw["inputs"] = [{"time": 0.25, "body": "ball", "teleport": [1.0, 0.0]}]
    msgs = []
    for lang in ("python", "c"):
        with pytest.raises(SimulateError, match="input 0: body .* would overlap body 0") as exc:
            run_scene(parse_scene(json.dumps(raw)), lang)
        msgs.append(str(exc.value).split("simulator: ")[1])
    assert msgs[0] == msgs[1]


def test_add_body_made_or_refused_as_the_reference(tmp_path):
    """Bodies added live (a circle, a spinning triangle, a circle into the
    left wall: refused, a fixed ledge, the circle again) give the
    reference's indices and bytes; a bad text is refused with a message."""
    import io
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.live import flat_body, python_world
    from max2code.sim.scene import parse_scene
    raw = inputs_scene(2.0) | {"inputs": []}
    scene = parse_scene(json.dumps(raw))
    new = [{"name": "new1", "shape": "circle", "radius": 0.07, "mass": 0.5, "position": [1.0, 1.2],
            "velocity": [0.3, 0.0]},
           {"name": "new2", "shape": "polygon", "mass": 1.0, "position": [0.6, 1.5],
            "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.0, 0.12]], "angular_velocity": 2.0},
           {"name": "bad", "shape": "circle", "radius": 0.2, "mass": 0.5, "position": [0.05, 1.0]},
           {"name": "ledge", "shape": "polygon", "fixed": True, "position": [1.5, 1.0],
            "vertices": [[-0.3, -0.02], [0.3, -0.02], [0.3, 0.02], [-0.3, 0.02]]}]
    texts = [flat_body(scene, b).rstrip("\n") for b in new]     # as the live API makes them (the scene's window)
    ops = [(0.2, texts[0]), (0.7, texts[1]), (0.9, texts[2]), (1.0, texts[3]), (1.3, texts[0])]
    out = io.StringIO()
    w = python_world(scene, out)
    want = []
    for t, text in ops:
        w.advance(t)
        want.append(w.add_body(text))
    w.advance(scene.end_time)
    w.finish()
    c = _Lib(world_library(scene))
    lib = c.lib
    lib.m2c_world_add_body.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    fh = c.libc.fopen(str(tmp_path / "c.txt").encode(), b"w")
    cw = lib.m2c_world_new(compile_scene(scene).encode(), fh)
    got = []
    for t, text in ops:
        assert lib.m2c_world_advance(cw, t, None, None) == 0
        got.append(lib.m2c_world_add_body(cw, text.encode()))
    assert lib.m2c_world_add_body(cw, b"body 0 0 1") == -2 and b"add_body: ends early" in lib.m2c_world_error(cw)
    assert lib.m2c_world_add_body(cw, (texts[0] + " x").encode()) == -2
    assert b"unexpected 'x' after the body" in lib.m2c_world_error(cw)
    assert lib.m2c_world_advance(cw, scene.end_time, None, None) == 0
    assert lib.m2c_world_finish(cw, None, None) == 0
    lib.m2c_world_free(cw)
    c.libc.fclose(fh)
    assert got == want and -1 in want and want[0] == len(scene.bodies)
    assert (tmp_path / "c.txt").read_text() == out.getvalue()


class _CRecorded:
    """What max2code/sim/recording.py reads of a world (input_log(), added),
    from a C world through its input-log calls."""

    def __init__(self, lib, w):
        class Input(ctypes.Structure):
            _fields_ = [("t", ctypes.c_double), ("body", ctypes.c_int), ("mode", ctypes.c_int),
                        ("x", ctypes.c_double), ("y", ctypes.c_double)]
        lib.m2c_world_input_count.argtypes = [ctypes.c_void_p]
        lib.m2c_world_input.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(Input)]
        lib.m2c_world_added.restype = ctypes.c_longlong
        lib.m2c_world_added.argtypes = [ctypes.c_void_p]
        self.log = []
        for k in range(lib.m2c_world_input_count(w)):
            e = Input()
            assert lib.m2c_world_input(w, k, ctypes.byref(e)) == 0
            self.log.append((e.t, e.body, e.mode, e.x, e.y))
        assert lib.m2c_world_input(w, len(self.log), ctypes.byref(Input())) == -1
        self.added = lib.m2c_world_added(w)

    def input_log(self):
        return self.log


def test_a_c_session_recorded_replays_in_c_and_python(tmp_path):
    """A live session in the C world (inputs of every kind, one at an
    event's exact time, a refused teleport, removals), written as a scene
    from C's input log: the batch simulators of C and Python write the
    session's trace again."""
    import json
    import sys
    from sim_scenes import inputs_scene
    from max2code.sim.recording import write_recording
    raw = inputs_scene(2.0, remove=True)
    raw["inputs"] = [{"time": 0.5, "body": "crate", "set_velocity": [-1.0, 2.0]}]
    path = str(tmp_path / "scene.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(raw, fh)
    scene = load_scene(path)
    names = {b.name: k for k, b in enumerate(scene.bodies)}
    c = _Lib(world_library(scene))
    lib = c.lib
    for name in ("set_velocity", "add_velocity", "apply_impulse", "teleport"):
        getattr(lib, f"m2c_world_{name}").argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double,
                                                       ctypes.c_double]
    lib.m2c_world_remove_body.argtypes = [ctypes.c_void_p, ctypes.c_int]
    fh = c.libc.fopen(str(tmp_path / "session.txt").encode(), b"w")
    w = lib.m2c_world_new(compile_scene(scene).encode(), fh)
    assert lib.m2c_world_advance(w, 0.3, None, None) == 0
    assert lib.m2c_world_apply_impulse(w, names["ball"], 0.5, 2.0) == 0
    assert lib.m2c_world_set_velocity(w, names["crate"], 0.0, 1.0) == 0
    hit = lib.m2c_world_next_event_time(w)                                   # an event's exact time
    assert 0.3 < hit < 0.5
    assert lib.m2c_world_advance(w, hit, None, None) == 0
    assert lib.m2c_world_add_velocity(w, names["pebble"], 0.1, 0.1) == 0
    assert lib.m2c_world_advance(w, 0.5, None, None) == 0
    assert lib.m2c_world_teleport(w, names["ball"], 1.0, 1.2) == 1
    assert lib.m2c_world_teleport(w, names["crate"], 1.0, -0.05) == 0        # into the floor: refused
    assert lib.m2c_world_advance(w, 1.4, None, None) == 0
    assert lib.m2c_world_remove_body(w, names["ledge"]) == 0
    assert lib.m2c_world_remove_body(w, names["ledge"]) == -1 and b"removed" in lib.m2c_world_error(w)
    assert lib.m2c_world_advance(w, 1.9, None, None) == 0
    assert lib.m2c_world_remove_body(w, names["pebble"]) == 0
    assert lib.m2c_world_finish(w, None, None) == 0
    rec_world = _CRecorded(lib, w)
    lib.m2c_world_free(w)
    c.libc.fclose(fh)
    assert len(rec_world.log) == 1 + 6 and rec_world.added == 0
    rec = str(tmp_path / "recording.json")
    write_recording(path, rec_world, rec)
    session = (tmp_path / "session.txt").read_text()
    for lang in ("c", "python"):
        assert run_scene(load_scene(rec), lang).raw == session, lang


def test_random_c_sessions_replay_from_their_recordings(tmp_path):
    """Random scenes driven in the C world: advances to the next event's
    exact time or by steps, live set/add velocity and impulses between
    them; each session, recorded from C's input log, replays byte for byte
    in the batch simulators of C and Python."""
    import json
    import random
    import sys
    from sim_scenes import random_scene
    from max2code.sim.recording import write_recording
    done = 0
    for seed in range(40):
        if done == 4:
            break
        path = str(tmp_path / f"scene{seed}.json")
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(random_scene(seed, end_time=1.0), fh)
        try:
            scene = load_scene(path)
        except Exception:
            continue                        # an overlapping draw
        rng = random.Random(seed)
        movable = [k for k, b in enumerate(scene.bodies) if not b.fixed]
        c = _Lib(world_library(scene))
        lib = c.lib
        for name in ("set_velocity", "add_velocity", "apply_impulse"):
            getattr(lib, f"m2c_world_{name}").argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double,
                                                           ctypes.c_double]
        trace = tmp_path / f"session{seed}.txt"
        fh = c.libc.fopen(str(trace).encode(), b"w")
        w = lib.m2c_world_new(compile_scene(scene).encode(), fh)
        made = 0
        for _ in range(30):
            what = rng.choice(["event", "step", "set_velocity", "add_velocity", "apply_impulse"])
            now = lib.m2c_world_time(w)
            if what == "event":
                assert lib.m2c_world_advance(w, min(lib.m2c_world_next_event_time(w), scene.end_time), None,
                                             None) == 0
            elif what == "step":
                assert lib.m2c_world_advance(w, min(scene.end_time, now + rng.uniform(0.0, 0.2)), None, None) == 0
            else:
                body = movable[rng.randrange(len(movable))]
                assert getattr(lib, f"m2c_world_{what}")(w, body, rng.uniform(-1, 1), rng.uniform(-1, 1)) == 0
                made += 1
        assert lib.m2c_world_advance(w, scene.end_time, None, None) == 0, lib.m2c_world_error(w)
        assert lib.m2c_world_finish(w, None, None) == 0, lib.m2c_world_error(w)
        recorded = _CRecorded(lib, w)
        lib.m2c_world_free(w)
        c.libc.fclose(fh)
        assert len(recorded.log) == len(scene.inputs) + made
        rec = str(tmp_path / f"recording{seed}.json")
        write_recording(path, recorded, rec)
        for lang in ("c", "python"):
            assert run_scene(load_scene(rec), lang).raw == trace.read_text(), (seed, lang)
        done += 1
    assert done == 4


def test_add_body_text_and_live_inputs_are_checked_in_c():
    """add_body's text gets the scene's body checks (WHAT add_body, the new
    body's index, covers among the world's bodies); a live input whose
    velocity or position would not be finite, a teleport beyond 1e150 m, a
    body index that does not exist (also one beyond 32 bits) and anything
    after finish are refused, each leaving the world unchanged."""
    import json
    from max2code.sim.cworld import CWorld
    from max2code.sim.live import flat_body
    from max2code_rt.sim import SimError
    from max2code.sim.scene import parse_scene
    raw = {"end_time": 2.0, "gravity": [0, -9.81], "bodies": [
        {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -1],
         "vertices": [[-3, -0.5], [3, -0.5], [3, 0.5], [-3, 0.5]]},
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 0.5, "position": [0.0, 0.0]},
        {"name": "box", "shape": "polygon", "mass": 2.0, "position": [1, 0],
         "vertices": [[-0.05, -0.05], [0.05, -0.05], [0.05, 0.05], [-0.05, 0.05]]}]}
    scene = parse_scene(json.dumps(raw))
    box = flat_body(scene, raw["bodies"][2] | {"name": "box2", "position": [2, 0]})
    lines = box.splitlines()

    def body_with(**fields):
        words = lines[0].split()
        names = ("poly fixed inv_mass inv_inertia restitution friction px py vx vy ax ay angle omega radius "
                 "orbit orbit_angle bound window large nverts").split()
        for name, v in fields.items():
            words[1 + names.index(name)] = v
        return "\n".join([" ".join(words), *lines[1:]]) + "\n"

    def vertex_with(j, k, v):
        words = lines[1 + j].split()
        words[k] = v
        return "\n".join([lines[0], *lines[1:1 + j], " ".join(words), *lines[2 + j:]]) + "\n"

    def refused(call, *args):
        with pytest.raises(SimError) as exc:
            call(*args)
        return str(exc.value)

    w = CWorld(str(world_library(scene)), compile_scene(scene))
    try:
        w.advance(0.1)
        log = w.input_log()
        assert refused(w.add_body, body_with(restitution="5")) == "add_body: body 3: restitution 5 outside [0, 1]"
        assert refused(w.add_body, body_with(inv_mass="nan")) == "add_body: expected a number, found 'nan'"
        assert refused(w.add_body, body_with(nverts="5000")) == "add_body: body 3: 5000 vertices (3 to 1024)"
        assert refused(w.add_body, body_with(vx="1e300")) == (
            "add_body: body 3: reaches more than 2e150 m from the origin by the end")
        assert refused(w.add_body, vertex_with(0, 11, "3")) == "add_body: body 3 vertex 0: cover 3 is not a body"
        assert refused(w.add_body, vertex_with(1, 9, "2")) == (
            "add_body: body 3 vertex 1: the normal is not a unit vector")
        assert refused(w.add_body, box + "x\n") == "add_body: unexpected 'x' after the body"
        assert refused(w.add_body, box.replace("body", "body\x01", 1)) == "add_body: byte 4: not printable ASCII"
        assert w.body_count() == 3 and w.added == 0
        assert refused(w.apply_impulse, 1, 1e308, 0.0) == "live input: body 1: velocity would not be finite"
        assert refused(w.set_velocity, 1, math.inf, 0.0) == "live input: body 1: velocity would not be finite"
        assert refused(w.teleport, 1, math.nan, 0.0) == "live input: body 1: position would not be finite"
        assert refused(w.teleport, 1, 1e200, 0.0) == "live input: body 1: teleport beyond 1e150 m"
        assert refused(w.set_velocity, 7, 1.0, 0.0) == "live input: body 7 does not exist"
        assert refused(w.set_velocity, 2 ** 32 + 1, 1.0, 0.0) == f"live input: body {2 ** 32 + 1} does not exist"
        assert w.input_log() == log
        assert w.add_body(box) == 3
        w.set_velocity(1, 0.5, 0.0)
        w.advance(w.end_time())
        w.finish()
        assert refused(w.set_velocity, 1, 1.0, 0.0) == "live input: the world is finished"
        assert refused(w.add_body, box) == "live input: the world is finished"
    finally:
        w.close()
