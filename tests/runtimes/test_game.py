"""The PyGame platformer (examples/game/game.py) runs headless
(SDL_VIDEODRIVER=dummy) from its key script: on the C engine through
max2code.sim.cworld and on the pure-Python reference, with the same live
inputs, the same outcome and the same trace bytes; its recording (the
session as a scene) gives the session's trace in the batch simulators."""
from __future__ import annotations

import json
import os
from pathlib import Path
import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

pytest.importorskip("pygame")

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
GAME = os.path.join(ROOT, "examples", "game", "game.py")
KEYS = os.path.join(ROOT, "examples", "game", "keys.txt")
FRAMES = 1200          # 20 s at 60 frames per second


def play(*args, timeout=600):
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy")
    env["PYTHONPATH"] = os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python"), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, GAME, *args], capture_output=True, text=True, env=env, timeout=timeout)


@pytest.fixture(scope="module")
def sessions(tmp_path_factory):
    folder = tmp_path_factory.mktemp("game")
    out = {}
    for engine in ("c", "python"):
        trace = str(folder / f"{engine}.trace")
        rec = str(folder / f"{engine}-recording.json")
        proc = play("--keys", KEYS, "--frames", str(FRAMES), "--engine", engine, "--trace", trace,
                    "--shots", str(folder / engine), "--every", "600", "--record", rec)
        assert proc.returncode == 0, proc.stderr[-3000:]
        with open(trace, encoding="ascii") as fh:
            out[engine] = (proc.stdout, fh.read(), folder / engine, rec)
    return out


def test_game_runs_headless_from_its_key_script(sessions):
    line, trace, shots, _ = sessions["c"]
    assert line.startswith(f"game: {FRAMES} frames to t = 20.000 s on the c engine"), line
    # the script plays the game: gems taken (teleported to the shelf), live inputs made
    gems = int(line.split("gems ")[1].split("/")[0])
    inputs = int(line.split("live inputs ")[1].split(";")[0])
    assert gems >= 1 and inputs >= 10, line
    assert trace.count("E input") == inputs
    assert sorted(os.listdir(shots)) == ["frame00600.png", "frame01200.png"]


def test_both_engines_play_the_same_game(sessions):
    c_line, c_trace, _, c_rec = sessions["c"]
    py_line, py_trace, _, py_rec = sessions["python"]
    assert c_line.split(" engine:")[1].split("; engine")[0] == py_line.split(" engine:")[1].split("; engine")[0]
    assert c_trace == py_trace
    with open(c_rec, encoding="utf-8") as a, open(py_rec, encoding="utf-8") as b:
        assert a.read() == b.read()
    # the committed recording (bench/idle.py's game scene) is this session's
    with open(c_rec, encoding="utf-8") as a, open(os.path.join(ROOT, "examples", "game", "recording.json"),
                                                   encoding="utf-8") as b:
        assert a.read() == b.read()


def test_the_recording_replays_the_session_in_python_and_c(sessions):
    """The recording (level.json with the session's 30-odd live inputs
    scripted, teleports included) run by the batch simulators writes the
    session's trace, byte for byte."""
    from max2code.sim.commands import crosscheck
    from max2code.sim.scene import load_scene
    _, trace, _, rec = sessions["c"]
    scene = load_scene(rec)
    assert len(scene.inputs) >= 10 and any(i.mode == 3 for i in scene.inputs)      # teleports recorded
    traces, problems = crosscheck(scene, ("python", "c"))
    assert not problems, problems
    assert traces["python"].raw == traces["c"].raw == trace


@pytest.mark.parametrize("lang", ["rust", "m2"])
def test_the_recording_crosschecks_in_the_other_runtimes(sessions, lang):
    from max2code.sim.commands import crosscheck
    from max2code.sim.scene import load_scene
    _, trace, _, rec = sessions["c"]
    traces, problems = crosscheck(load_scene(rec), ("c", lang))
    assert not problems, problems
    assert traces[lang].raw == trace


def test_a_bad_key_script_is_one_line(tmp_path):
    bad = tmp_path / "keys.txt"
    bad.write_text("10 right down\n20 fly down\n")
    proc = play("--keys", str(bad), "--frames", "5")
    assert proc.returncode == 1
    assert proc.stderr.strip() == (f"{bad}:2: error: expected 'FRAME KEY down|up' with KEY one of "
                                   f"left, right, jump, got '20 fly down'")
    proc = play("--scene", str(tmp_path / "none.json"), "--frames", "5")
    assert (proc.returncode, proc.stderr.strip()) == (1, f"{tmp_path / 'none.json'}: error: cannot read: "
                                                         "No such file or directory")


LEDGE_END = os.path.join(ROOT, "tests", "data", "game-stuck-keys.txt")


def test_a_stuck_engine_is_one_line(tmp_path):
    """The engine's guard against a stuck scene (more than max_events_at_one_time
    events at one instant; here 1, so the first instant the guard counts two
    events at trips it: a row of three touching balls added to the level and
    struck end-on, as in Newton's cradle, passes the blow along in three
    collisions at t = 0.15 s): the game stops with one line naming the scene
    and the time, exit 1, no traceback and no recording."""
    with open(os.path.join(ROOT, "examples", "game", "level.json"), encoding="utf-8") as fh:
        level = json.load(fh)
    level["max_events_at_one_time"] = 1
    for name, x, vx in (("striker", 14.0, 2.0), ("row0", 14.5, 0.0), ("row1", 14.7, 0.0), ("row2", 14.9, 0.0)):
        level["bodies"].append({"name": name, "shape": "circle", "radius": 0.1, "mass": 1.0,
                                "position": [x, 8.0], "velocity": [vx, 0.0]})
    scene = tmp_path / "level.json"
    scene.write_text(json.dumps(level))
    rec = tmp_path / "rec.json"
    proc = play("--scene", str(scene), "--keys", KEYS, "--frames", str(FRAMES), "--quiet", "--record", str(rec))
    assert proc.returncode == 1
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{scene}: error: the engine stopped before t = "), lines
    assert lines[0].endswith(": the scene is stuck") and "more than 1 events at t = 0.1499" in lines[0], lines
    assert not rec.exists()


def test_the_hero_runs_off_a_ledge_end():
    """Once stuck at t = 10.057 s (the support and its leave alternated at
    ledge1's left end); the hero now leaves the edge and plays on."""
    proc = play("--keys", LEDGE_END, "--frames", "700")
    assert proc.returncode == 0, proc.stderr[-500:]


@pytest.mark.parametrize("engine", ["c", "python"])
def test_the_lift_carries_the_hero(engine):
    """The hero put on the lift (a fixed plank rising at 0.6 m/s) lands, is
    supported and rides up with it: its centre stays on the plank's top,
    exactly, and moves with the plank's speed.  At the top of the shaft the
    game loop sends the lift down (a live set_velocity on a fixed polygon):
    the hero, still rising, leaves it, falls back on it and rides it down.
    Both engines, through the game's own rules (Game.step turns the lift)."""
    sys.path.insert(0, os.path.dirname(GAME))
    try:
        import game as game_mod
    finally:
        sys.path.pop(0)
    from max2code.sim.live import open_world
    from max2code.sim.scene import parse_scene
    with open(os.path.join(ROOT, "examples", "game", "level.json"), encoding="utf-8") as fh:
        raw = json.load(fh)
    # the level without its boulders and gems, which would knock the hero off
    raw["bodies"] = [b for b in raw["bodies"] if not b["name"].startswith(("boulder", "gem"))]
    scene = parse_scene(json.dumps(raw), "level-lift.json")
    names = [b.name for b in scene.bodies]
    lift, hero = names.index("lift"), names.index("hero")
    world = open_world(scene, engine)
    game = game_mod.Game(world, scene)
    top = 0.08 + 0.25                               # the plank's half height + the hero's radius
    assert world.teleport(hero, 11.3, 3.0 + top + 1e-3)
    world.set_velocity(hero, 0.0, 0.0)
    turn = (game_mod.LIFT_Y[1] - 3.0) / 0.6        # s: the lift reaches the top of its shaft
    riding = {"up": 0, "down": 0, "off": 0}
    for frame in range(1, 60 * 9):
        t = frame / 60.0
        game.contacts(world.advance(t))
        game.step(t)
        _, ly, _, lvy, _, _ = world.state(lift, t)
        x, y, vx, vy, _, _ = world.state(hero, t)
        on = abs(y - (ly + top)) <= 1e-9 and vy == lvy and x == 11.3 and vx == 0.0
        if 0.5 <= t < turn - 0.01:                  # landed (a 1 mm fall) and carried up since
            assert on and lvy == 0.6, (t, x, y, vx, vy, ly, lvy)
            riding["up"] += 1
        elif t >= turn + 0.5:                       # fell back on the descending lift and carried down
            assert on and lvy == -0.6, (t, x, y, vx, vy, ly, lvy)
            riding["down"] += 1
        elif not on:
            riding["off"] += 1
    assert riding["up"] > 300 and riding["down"] > 100 and riding["off"] > 0, riding
    assert game.inputs == 1                         # the lift's one turn (the test's own inputs aside)
