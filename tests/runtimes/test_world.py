"""The live world API (docs/engine-api.md): driven in small steps
it handles the same events as one advance to the end and writes the batch
simulator's bytes; state(body, t) is the replayed exact motion.

Tests that run a runtime's simulator are parametrised by runtime: each
runtime's `sim --step DT` drives its own world (docs/engine-api.md,
"Checking a port").  Runtimes whose port of a REF: step has not been merged
yet are marked xfail(strict): they show as xfailed until the port lands, and
then fail as XPASS until the mark is removed."""
from __future__ import annotations

import json
import math
import os
from pathlib import Path
import subprocess

import pytest
from hypothesis import given, settings, strategies as st

from max2code.sim.live import flat_body, python_world
from max2code.sim.replay import read_trace
from max2code.sim.scene import compile_scene, load_scene, parse_scene
from max2code.sim.simulate import LANGS, SimulateError, build_simulator, run_scene
from sim_scenes import inputs_scene

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
EX = os.path.join(ROOT, "examples")

# REF: step -> the runtimes that have ported it (python is the reference)
PORTED = {step: {"python", "c", "rust", "m2"} for step in ("world", "inputs", "bodies", "recordings")}
PORTED["moving"] = {"python", "c", "rust", "m2"}     # support on moving fixed bodies, inputs on fixed ones (test_contact.py)


def runtimes(step: str):
    return [lang if lang in PORTED[step] else
            pytest.param(lang, marks=pytest.mark.xfail(strict=True, reason=f"{lang} port of REF step "
                                                                            f"'{step}' not merged yet"))
            for lang in LANGS]


def stepped(scene, lang: str, dt: float, live: bool = False):
    """(trace, probe lines) of the runtime's world driven in steps of dt
    (live: the scene's inputs made live at their times)."""
    build = build_simulator(lang, scene.effects, scene.taylor_order)
    proc = subprocess.run(build.run_cmd + ["--step", repr(dt)] + ["--live"] * live, input=compile_scene(scene),
                          capture_output=True, text=True, cwd=build.workdir, timeout=600)
    assert proc.returncode == 0, proc.stdout[-500:] + proc.stderr[-2000:]
    return proc.stdout, proc.stderr.splitlines()


STEP_SCENES = ["newtons-cradle.json", "platformer.json", "resting-ball.json", "spinning-polygons.json"]


@pytest.mark.slow
@pytest.mark.parametrize("name", STEP_SCENES, ids=lambda n: n[:-5])
@pytest.mark.parametrize("lang", runtimes("world"))
def test_small_steps_write_the_batch_bytes_and_states_are_the_replay(lang, name):
    """Steps of 0.0123 s (not a multiple of the frame time): the trace is the
    batch run's byte for byte, and every state(body, t) at a step equals the
    replay of the batch trace bit for bit (max2code/sim/replay.py)."""
    scene = load_scene(os.path.join(EX, name))
    batch = run_scene(scene, lang)
    trace, probe = stepped(scene, lang, 0.0123)
    assert trace == batch.raw
    rp = read_trace("\n".join(batch.lines()), scene)
    steps = [line for line in probe if line.startswith("P ")]
    counts = [int(line.split()[2]) for line in probe if line.startswith("C ")]
    n = len(scene.bodies)
    assert len(counts) == math.ceil(scene.end_time / 0.0123) - 1 and len(steps) == n * len(counts)
    # the contacts advance reported: every collision and support before the last step
    last = float(probe[-1].split()[1])
    assert sum(counts) == sum(1 for e in batch.events if e["kind"] in ("collision", "support") and e["t"] < last)
    for line in steps:
        w = line.split()
        t, k = float(w[1]), int(w[2])
        got = tuple(float(x) for x in w[3:9])
        s = rp.state_at(k, t)
        assert got == (s.px, s.py, s.vx, s.vy, s.angle, s.omega), (line, s)


@pytest.mark.parametrize("lang", runtimes("inputs"))
def test_live_inputs_write_the_bytes_of_the_same_inputs_scripted(lang):
    """Every input kind (set and add velocity, impulse, teleport; at t = 0,
    at frame times, two at one instant) made live at its time through the
    world's operations gives the scripted scene's trace byte for byte, and
    the replay of that trace (teleports move bodies) matches the states."""
    scene = parse_scene(json.dumps(inputs_scene()))
    batch = run_scene(scene, lang)
    assert batch.stats["events"]["inputs"] == len(scene.inputs)
    trace, probe = stepped(scene, lang, 0.05, live=True)
    assert trace == batch.raw
    rp = read_trace("\n".join(batch.lines()), scene)
    for line in (x for x in probe if x.startswith("P ")):
        w = line.split()
        s = rp.state_at(int(w[2]), float(w[1]))
        assert tuple(float(x) for x in w[3:9]) == (s.px, s.py, s.vx, s.vy, s.angle, s.omega), line


@pytest.mark.parametrize("lang", runtimes("bodies"))
def test_live_removals_write_the_bytes_of_the_same_removals_scripted(lang):
    """Removing a fixed ledge under a resting pebble (asleep on it: the
    removal wakes it and it falls) and then the pebble, live at their
    times: the scripted scene's bytes, and states equal to the replay (a
    removed body stays where it was removed, at rest)."""
    scene = parse_scene(json.dumps(inputs_scene(remove=True)))
    batch = run_scene(scene, lang)
    kinds = [(e["kind"], e["bodies"]) for e in batch.events if e["kind"] in ("support", "sleep", "wake")]
    assert ("support", ["pebble", "ledge"]) in kinds and ("sleep", ["pebble", "ledge"]) in kinds
    assert ("wake", ["pebble"]) in kinds
    trace, probe = stepped(scene, lang, 0.05, live=True)
    assert trace == batch.raw
    rp = read_trace("\n".join(batch.lines()), scene)
    for line in (x for x in probe if x.startswith("P ")):
        w = line.split()
        s = rp.state_at(int(w[2]), float(w[1]))
        assert tuple(float(x) for x in w[3:9]) == (s.px, s.py, s.vx, s.vy, s.angle, s.omega), line


def moving_platform_scene():
    """A platform that goes back and forth (set_velocity on a fixed
    polygon, at probe times (0.05 s steps) and between), carrying a box, with a ball
    asleep on a ledge that the platform's first input does not touch and a
    ball it wakes (asleep on it while it stands)."""
    plank = lambda name, x, y, hw, **kw: dict({"name": name, "shape": "polygon", "fixed": True,   # noqa: E731
                                               "position": [x, y], "friction": 1.0,
                                               "vertices": [[-hw, -0.05], [hw, -0.05], [hw, 0.05], [-hw, 0.05]]},
                                              **kw)
    return {"end_time": 3.0, "frame_rate": 30, "gravity": [0.0, -9.81],
            "bodies": [plank("ledge", -2.0, -0.05, 0.5), plank("platform", 0.0, -0.05, 0.8),
                       {"name": "box", "shape": "polygon", "mass": 1.0, "friction": 0.5, "position": [-0.3, 0.1],
                        "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]},
                       {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.4, 0.1]},
                       {"name": "rester", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [-2.0, 0.1]}],
            "inputs": [{"time": 0.5, "body": "platform", "set_velocity": [0.6, 0.0]},
                       {"time": 1.2, "body": "platform", "set_velocity": [-0.6, 0.0]},
                       {"time": 1.9, "body": "platform", "set_velocity": [0.0, 0.0]},
                       {"time": 2.27, "body": "platform", "set_velocity": [0.3, 0.1]}]}


@pytest.mark.parametrize("lang", runtimes("moving"))
def test_live_velocities_of_a_fixed_platform_write_the_bytes_of_the_same_inputs_scripted(lang):
    """set_velocity on a fixed polygon, live at its times: the scripted
    scene's bytes, and states equal to the replay: the movable bodies' bit
    for bit, the platform's to rounding (the world re-bases a fixed body at
    each of its collisions, which write no state line for it; the replay
    carries it from its last input)."""
    scene = parse_scene(json.dumps(moving_platform_scene()))
    batch = run_scene(scene, lang)
    kinds = [e["kind"] for e in batch.events if e["kind"] != "frame"]
    assert kinds.count("input") == 4 and "wake" in kinds and "leave" in kinds
    trace, probe = stepped(scene, lang, 0.05, live=True)
    assert trace == batch.raw
    rp = read_trace("\n".join(batch.lines()), scene)
    for line in (x for x in probe if x.startswith("P ")):
        w = line.split()
        k = int(w[2])
        s = rp.state_at(k, float(w[1]))
        got, want = tuple(float(x) for x in w[3:9]), (s.px, s.py, s.vx, s.vy, s.angle, s.omega)
        if scene.bodies[k].fixed:
            assert got == pytest.approx(want, rel=1e-14, abs=1e-15), line
        else:
            assert got == want, line


def test_a_fixed_body_takes_only_set_velocity_and_only_when_it_does_not_turn():
    from max2code_rt.sim import SimError
    scene = parse_scene(json.dumps(moving_platform_scene()))
    w = python_world(scene)
    w.advance(0.1)
    with pytest.raises(SimError, match="is fixed"):
        w.add_velocity(1, 1.0, 0.0)
    w.set_velocity(1, 0.2, 0.0)
    assert w.state(1, 0.1)[2:4] == (0.2, 0.0)


# ---- the Python API itself -------------------------------------------------

@pytest.fixture(scope="module")
def cradle():
    return load_scene(os.path.join(EX, "newtons-cradle.json"))


def _trace(scene, steps):
    """(flat trace, contacts as tuples) of the Python world advanced to each time in steps, then finished."""
    import io
    out = io.StringIO()
    w = python_world(scene, out)
    got = []
    for t in steps:
        got += w.advance(t)
    got += w.finish()
    return out.getvalue(), [(c.t, c.a, c.b, c.feature, c.i, c.j, c.px, c.py, c.nx, c.ny, c.impulse, c.support)
                            for c in got]


def test_many_small_advances_equal_one(cradle):
    """Irregular steps (some repeated, some landing exactly on event times)
    give the same contacts and bytes as one advance to the end."""
    one, c1 = _trace(cradle, [cradle.end_time])
    times = sorted({c[0] for c in c1})
    steps = sorted(set([k * 0.037 for k in range(1, 80) if k * 0.037 < cradle.end_time] + times[::3]))
    many, c2 = _trace(cradle, [t for t in steps for _ in (0, 1)])
    assert c1 and c2 == c1 and many == one
    assert one.count("\nE collision") + one.startswith("E collision") == len(c1)


def test_next_event_time_and_state_bounds(cradle):
    t0 = _trace(cradle, [cradle.end_time])[1][0][0]     # the first contact
    w = python_world(cradle)
    assert 0.0 <= w.next_event_time() <= t0
    assert w.advance(t0) == []          # events at exactly t0 stay queued
    assert w.time == t0 and w.next_event_time() == t0
    with pytest.raises(Exception, match="outside"):
        w.state(0, t0 + 1e-9)
    with pytest.raises(Exception, match="outside"):
        w.advance(t0 / 2)               # time never goes back
    with pytest.raises(Exception, match="outside"):
        w.advance(cradle.end_time * 2)
    got = w.advance(math.nextafter(t0, math.inf))
    assert got and all(c.t == t0 for c in got)
    assert w.next_event_time() > t0
    with pytest.raises(Exception, match="no body"):
        w.state(len(cradle.bodies), w.time)


def _ball(velocity, acceleration):
    return parse_scene(json.dumps({"end_time": 10, "bodies": [
        {"shape": "circle", "radius": 0.5, "mass": 1, "position": [0, 0], "velocity": velocity,
         "acceleration": acceleration}]}))


def test_a_world_without_events_idles():
    """A ball at rest in empty space: no event ever (next_event_time is inf);
    a moving one: state(t) up to its first event (a cell crossing) is the
    exact free motion, computed as the runtime computes it."""
    w = python_world(_ball([0, 0], [0, 0]))
    assert w.next_event_time() == math.inf and w.advance(7.5) == [] and w.state(0, 10.0)[:4] == (0.0,) * 4
    w = python_world(_ball([1, 2], [0, -1]))
    t = w.next_event_time()
    assert 0.0 < t < 10.0
    assert w.state(0, t)[:4] == ((1.0 + 0.5 * 0.0 * t) * t, (2.0 + 0.5 * -1.0 * t) * t, 1.0, 2.0 + -1.0 * t)


def test_a_live_input_at_an_event_time_goes_before_the_events_at_that_time():
    """advance(T) to the time of a collision, then an input: the same trace
    as the input scripted at T (inputs first at equal times), which is not
    the trace of the input made after that collision."""
    import io
    raw = inputs_scene(1.0)
    raw["inputs"] = []
    base = parse_scene(json.dumps(raw))
    _, contacts = _trace(base, [base.end_time])
    T = contacts[len(contacts) // 2][0]
    body = next(k for k, b in enumerate(base.bodies) if not b.fixed and k not in contacts[len(contacts) // 2][1:3])
    raw["inputs"] = [{"time": T, "body": base.bodies[body].name, "add_velocity": [0.25, 0.5]}]
    scripted = run_scene(parse_scene(json.dumps(raw)), "python").raw
    out = io.StringIO()
    w = python_world(base, out)
    before = [(c.t, c.a, c.b) for c in w.advance(T)]
    assert before == [c[:3] for c in contacts if c[0] < T]
    assert w.next_event_time() == T         # the collision at T is still queued
    w.add_velocity(body, 0.25, 0.5)
    w.advance(base.end_time)
    w.finish()
    assert out.getvalue() == scripted
    tt = "%.17g" % T
    assert scripted.index(f"E input {tt} ") < scripted.index(f"E collision {tt} ")


def test_teleport_into_overlap_is_refused_and_the_world_is_unchanged():
    import io
    scene = parse_scene(json.dumps(inputs_scene(1.0) | {"inputs": []}))
    ball = next(k for k, b in enumerate(scene.bodies) if b.name == "ball")
    crate = next(k for k, b in enumerate(scene.bodies) if b.name == "crate")

    def run(teleports):
        out = io.StringIO()
        w = python_world(scene, out)
        w.advance(0.3)
        before = [w.state(k, 0.3) for k in range(len(scene.bodies))]
        results = [w.teleport(ball, x, y) for x, y in teleports]
        w.advance(1.0)
        w.finish()
        return out.getvalue(), results, before, len(w.s.inputs)

    plain, _, _, _ = run([])
    cx, cy = scene.bodies[crate].position
    refused, res, _, n = run([(cx, cy), (1.0, -0.05), (-0.05, 1.0)])   # into the crate, the floor, the left wall
    assert res == [False, False, False] and n == 0 and refused == plain
    moved, res, _, n = run([(1.0, 1.5)])
    assert res == [True] and n == 1 and moved != plain
    _, res, _, _ = run([(1.0, 0.1)])            # touching the floor (radius 0.1) is not overlapping
    assert res == [True]


def test_a_scripted_teleport_into_overlap_is_an_error():
    raw = inputs_scene(1.0)
    raw["inputs"] = [{"time": 0.25, "body": "ball", "teleport": [1.0, 0.0]}]
    with pytest.raises(SimulateError, match="input 0: body .* would overlap body 0"):
        run_scene(parse_scene(json.dumps(raw)), "python")


@pytest.mark.parametrize("bad, msg", [
    ({"time": 0.1, "body": "ball", "impulse": [1, 2], "teleport": [1, 1]}, "give exactly one of set_velocity, "
                                                                           "add_velocity, impulse, teleport"),
    ({"time": 0.1, "body": "floor", "impulse": [1, 2]}, "is fixed"),
    ({"time": 0.1, "body": "ball", "teleport": [1e200, 0]}, r"s\.json: error: inputs\[0\]\.teleport: 1e\+200 m"),
    ({"time": 0.1, "body": "ball", "impulse": [1, "x"]}, "impulse"),
])
def test_bad_inputs_are_refused_with_the_field(bad, msg):
    from max2code.sim.scene import SceneError
    raw = inputs_scene(1.0)
    raw["inputs"] = [bad]
    with pytest.raises(SceneError, match=msg):
        parse_scene(json.dumps(raw), "s.json")


def _pending(w, k):
    """The queued events that are not stale and name body k."""
    out = []
    for _, _, _, ev in w.heap:
        names = (ev.a, ev.b) if hasattr(ev, "a") else (ev.body,) if hasattr(ev, "body") else ()
        if k in names and not w.is_stale(ev):
            out.append(ev)
    return out


def test_removing_a_body_drops_its_pending_events():
    import io
    raw = inputs_scene(2.0)
    raw["inputs"] = []
    scene = parse_scene(json.dumps(raw))
    ball = next(k for k, b in enumerate(scene.bodies) if b.name == "ball")
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.7)
    assert _pending(w, ball)                     # its next contact and cell crossing at least
    at = w.state(ball, 0.7)
    w.remove_body(ball)
    assert _pending(w, ball) == [] and w.state(ball, 0.7) == at[:2] + (0.0, 0.0) + at[4:5] + (0.0,)
    with pytest.raises(Exception, match="was removed"):
        w.set_velocity(ball, 1.0, 0.0)
    while w.next_event_time() < scene.end_time:     # nothing ever meets it again
        w.advance(min(w.next_event_time() + 0.01, scene.end_time))
    w.finish()
    trace = out.getvalue().splitlines()
    later = [x for x in trace if x.startswith("E ") and float(x.split()[2]) > 0.7]
    assert later and not any(x.split()[3] == str(ball) or x.split()[4] == str(ball) for x in later)
    final = next(x for x in trace if x.startswith(f"F {ball} ")).split()
    assert tuple(float(v) for v in final[2:]) == (at[0], at[1], 0.0, 0.0, at[4], 0.0)


def test_add_body_joins_the_world_and_is_refused_where_it_overlaps():
    import io
    raw = inputs_scene(1.5)
    raw["inputs"] = []
    scene = parse_scene(json.dumps(raw))
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.5)
    n = len(scene.bodies)
    drop = {"name": "drop", "shape": "circle", "radius": 0.08, "mass": 0.5, "position": [0.3, 1.5],
            "velocity": [0.0, -1.0]}
    assert w.add_body(flat_body(scene, drop | {"position": [1.0, 0.0]})) == -1      # in the floor
    assert len(w.s.bodies) == n
    k = w.add_body(flat_body(scene, drop))
    assert k == n and w.state(k, 0.5)[:4] == (0.3, 1.5, 0.0, -1.0)
    with pytest.raises(Exception, match="does not fit the grid"):
        w.add_body(flat_body(scene, drop | {"radius": 5.0, "position": [30.0, 30.0]}))
    got = w.advance(1.5)
    w.finish()
    assert any(c.a == k or c.b == k for c in got)             # it lands on the floor
    assert f"E add 0.5 {k} " in out.getvalue()


@pytest.mark.parametrize("bad, msg", [
    ([{"time": 0.1, "body": "ball", "remove": 1}], "inputs\\[0\\].remove: expected true"),
    ([{"time": 0.1, "body": "ball", "remove": True}, {"time": 0.2, "body": "ball", "impulse": [1, 0]}],
     "inputs\\[1\\].body: 'ball' was removed by inputs\\[0\\]"),
    ([{"time": 0.3, "body": "ball", "impulse": [1, 0]}, {"time": 0.2, "body": "ball", "remove": True}],
     "input listed before this one at a later time"),
])
def test_bad_removals_are_refused(bad, msg):
    from max2code.sim.scene import SceneError
    raw = inputs_scene(1.0)
    raw["inputs"] = bad
    with pytest.raises(SceneError, match=msg):
        parse_scene(json.dumps(raw), "s.json")


def test_a_fixed_body_may_be_removed():
    raw = inputs_scene(1.0)
    raw["inputs"] = [{"time": 0.2, "body": "floor", "remove": True}]
    tr = run_scene(parse_scene(json.dumps(raw)), "python")
    assert tr.final["bodies"][4]["position"][1] < -0.5          # the ball fell through where the floor was


# ---- recordings ----------------------------------------------------------------

@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """A live Python session on a scene with two scripted inputs of its own:
    inputs of every kind at times of no event, at an event's exact time and
    at the scene's own input times, a refused teleport (not recorded), a
    removal; returns (scene path, the session's flat trace, recording path)."""
    import io
    from max2code.sim.recording import write_recording
    folder = tmp_path_factory.mktemp("rec")
    raw = inputs_scene(2.0, remove=True)
    raw["inputs"] = [{"time": 0.5, "body": "crate", "set_velocity": [-1.0, 2.0]},
                     {"time": 1.1, "body": "pebble", "teleport": [1.0, 0.7]}]       # onto the ledge
    path = str(folder / "scene.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(raw, fh)
    scene = load_scene(path)
    names = {b.name: k for k, b in enumerate(scene.bodies)}
    hit = python_world(scene).advance(0.45)[3].t               # an event's exact time
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.3)
    w.apply_impulse(names["ball"], 0.5, 2.0)
    w.set_velocity(names["crate"], 0.0, 1.0)                   # two at one instant
    w.advance(hit)
    w.add_velocity(names["pebble"], 0.1, 0.1)
    w.advance(0.5)                                             # the scene's own input at 0.5 comes first
    w.teleport(names["ball"], 1.0, 1.2)
    assert not w.teleport(names["crate"], 1.0, -0.05)          # into the floor: refused, not recorded
    w.advance(1.1)
    w.set_velocity(names["pebble"], 0.0, 0.0)                  # after the scene's teleport at 1.1: it rests
    w.advance(1.4)
    w.remove_body(names["ledge"])
    w.advance(1.9)
    w.remove_body(names["pebble"])
    w.finish()
    rec = str(folder / "recording.json")
    write_recording(path, w, rec)
    return path, out.getvalue(), rec


def test_a_recording_lists_the_scene_inputs_then_the_live_ones(session):
    path, _, rec = session
    with open(rec, encoding="utf-8") as fh:
        got = json.load(fh)["inputs"]
    with open(path, encoding="utf-8") as fh:
        own = json.load(fh)["inputs"]
    assert got[:2] == own and len(got) == 2 + 7
    assert [next(k for k in e if k not in ("time", "body")) for e in got[2:]] == [
        "impulse", "set_velocity", "add_velocity", "teleport", "set_velocity", "remove", "remove"]


@pytest.mark.parametrize("lang", runtimes("recordings"))
def test_a_recording_gives_the_session_trace(session, lang):
    """The recorded scene, run by the runtime's batch simulator, writes the
    live session's trace byte for byte."""
    _, trace, rec = session
    assert run_scene(load_scene(rec), lang).raw == trace


@pytest.mark.slow
@pytest.mark.xfail(set(LANGS) - PORTED["recordings"] != set(), strict=True,
                   reason="not every runtime has ported the REF steps yet")
def test_a_recording_crosschecks(session):
    """max2code crosscheck on the recording: the four runtimes agree."""
    from max2code.sim.commands import crosscheck
    traces, problems = crosscheck(load_scene(session[2]), LANGS)
    assert not problems and len({t.raw for t in traces.values()}) == 1


def test_a_session_that_added_bodies_is_not_recorded(tmp_path):
    from max2code.sim.recording import RecordingError, write_recording
    raw = inputs_scene(1.0)
    raw["inputs"] = []
    path = str(tmp_path / "s.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(raw, fh)
    scene = load_scene(path)
    w = python_world(scene)
    w.advance(0.2)
    w.add_body(flat_body(scene, {"shape": "circle", "radius": 0.05, "mass": 1, "position": [0.3, 1.5]}))
    with pytest.raises(RecordingError, match="added 1 bodies with add_body"):
        write_recording(path, w, str(tmp_path / "r.json"))
    from max2code.sim.recording import recording
    with pytest.raises(RecordingError, match="recorded on another scene"):
        recording(os.path.join(EX, "platformer.json"), w.input_log())      # the platformer has inputs of its own


ACTIONS = st.lists(st.tuples(st.sampled_from(["event", "step", "set_velocity", "add_velocity", "apply_impulse"]),
                             st.floats(0.0, 0.2), st.integers(0, 99), st.floats(-1, 1), st.floats(-1, 1)),
                   min_size=1, max_size=40)


@settings(max_examples=4, deadline=None, derandomize=True)
@given(st.integers(min_value=0, max_value=10**6), ACTIONS)
def test_random_sessions_replay_from_their_recordings(tmp_path_factory, seed, actions):
    """Random scenes, random advances (to the next event's exact time, or by
    a step) and random live inputs between them: the session's trace equals
    its recording's, and with no inputs the batch run's."""
    import io
    from max2code.sim.recording import write_recording
    from sim_scenes import random_scene
    folder = tmp_path_factory.mktemp("random")
    path = str(folder / "scene.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(random_scene(seed, end_time=1.0), fh)
    try:
        scene = load_scene(path)
    except Exception:
        return                              # an overlapping draw (write_random_scenes draws again; here: skip)
    movable = [k for k, b in enumerate(scene.bodies) if not b.fixed]
    out = io.StringIO()
    w = python_world(scene, out)
    made = 0
    for what, dt, pick, x, y in actions:
        if what == "event":
            w.advance(min(w.next_event_time(), scene.end_time))
        elif what == "step":
            w.advance(min(scene.end_time, w.time + dt))
        else:
            getattr(w, what)(movable[pick % len(movable)], x, y)
            made += 1
    w.advance(scene.end_time)
    w.finish()
    rec = str(folder / "recording.json")
    write_recording(path, w, rec)
    assert run_scene(load_scene(rec), "python").raw == out.getvalue()
    if made == 0:
        assert run_scene(scene, "python").raw == out.getvalue()


@pytest.mark.parametrize("lang", runtimes("inputs"))
def test_a_teleported_large_movable_body_stays_out_of_the_grid(lang):
    """A movable body marked large (kept out of the grid, checked by every
    body; a flat scene or add_body can say so) is teleported like any other
    instead of crashing in the grid's removal: the same bytes as Python."""
    scene = parse_scene(json.dumps(inputs_scene()))
    target = next(i.body for i in scene.inputs if i.mode == 3)
    lines = compile_scene(scene).split("\n")
    bodies = [k for k, line in enumerate(lines) if line.startswith("body ")]
    w = lines[bodies[target]].split()
    assert w[2] == "0" and w[20] == "0"          # movable, not large
    w[20] = "1"
    lines[bodies[target]] = " ".join(w)
    flat = "\n".join(lines)
    out = {}
    for x in ("python", lang):
        build = build_simulator(x, scene.effects, scene.taylor_order)
        proc = subprocess.run(build.run_cmd, input=flat, capture_output=True, text=True, cwd=build.workdir,
                              timeout=600)
        assert proc.returncode == 0, proc.stderr[-2000:]
        out[x] = proc.stdout
    assert out["python"] == out[lang]
    assert sum(1 for line in out[lang].splitlines() if line.startswith("E input")) == len(scene.inputs)
