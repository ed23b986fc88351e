"""Progress: a run that stops keeps its trace (every runtime writes and
flushes the events before the stop, and `max2code simulate -o FILE` keeps
them in FILE, closed by a `stopped` line that names the instant and the
reason); inelastic collapse ends in a jam instead of a stuck run; horizons
count against max_events, and a spin that would need more is refused."""
from __future__ import annotations

import json
import math
import random
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from max2code.cli import main
from max2code.sim.commands import crosscheck
from max2code.sim.scene import SceneError, parse_scene
from max2code.sim.simulate import LANGS, run_scene

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path.insert(0, str(ROOT / "tests"))
from sim_scenes import pile_scene  # noqa: E402


def _simulate(capsys, *args) -> tuple[int, str]:
    code = main(["simulate", *map(str, args)])
    return code, capsys.readouterr().err


@pytest.mark.slow
def test_a_stuck_run_keeps_its_trace_in_every_runtime(tmp_path, capsys):
    """Newton's cradle with at most one event at one instant: the first blow
    passed along the row at t = 0.2 s trips the guard.  Each runtime's trace
    holds the same events up to that instant, then the stop."""
    scene = json.loads((ROOT / "examples" / "newtons-cradle.json").read_text())
    scene["max_events_at_one_time"] = 1
    path = tmp_path / "cradle.json"
    path.write_text(json.dumps(scene))
    kept = {}
    for lang in LANGS:
        out = tmp_path / f"{lang}.jsonl"
        code, err = _simulate(capsys, "--lang", lang, path, "-o", out, "-q")
        msg = f"{path}: error: {lang} simulator: more than 1 events at t = 0.20000000000000001: the scene is stuck"
        assert (code, err) == (1, f"{msg}; the trace up to then is in {out}\n")
        lines = out.read_text().splitlines()
        last = json.loads(lines[-1])
        assert last == {"kind": "stopped", "t": 0.2, "error": msg[len(f"{path}: error: "):]}
        events = [json.loads(x) for x in lines[:-1]]
        assert events and all(e["t"] <= 0.2 for e in events)
        assert any(e["kind"] == "collision" and e["t"] == 0.2 for e in events), "the instant's first event is kept"
        kept[lang] = lines[:-1]
    for lang in LANGS:
        assert kept[lang] == kept[LANGS[0]], f"{lang}'s kept trace differs from {LANGS[0]}'s"


@pytest.mark.slow      # builds and runs the C simulator
def test_a_run_over_the_event_limit_keeps_its_trace_on_standard_output(capsys):
    """Without -o the trace goes to standard output as it is made: the
    events before the limit, then the stopped line.  The simulator counts
    every event it handles (cell crossings too), so it stops first, and the
    error names the instant of its event past the limit."""
    code = main(["simulate", "--lang", "c", str(ROOT / "examples" / "ball-pit.json"), "--max-events", "50", "-q"])
    out, err = capsys.readouterr()
    lines = [json.loads(x) for x in out.splitlines()]
    assert code == 1 and 1 < len(lines) <= 51 and lines[-1]["kind"] == "stopped"
    t = lines[-1]["t"]
    assert all(e["t"] <= t for e in lines[:-1])
    head, _, tail = err.strip().partition(" at t = ")
    assert head.endswith(": error: c simulator: more than 50 events (collisions, inputs, frames, cell crossings, "
                         "horizons)"), err
    number, _, why = tail.partition(": ")
    assert float(number) == t and why == ("the run was stopped; raise max_events in the scene or --max-events, "
                                          "or shorten end_time"), err


def _pit(n: int, seed: int, restitution: float, friction: float, radius: float, end_time: float) -> dict:
    """n balls in rows in a 2 x 3 m bin, random start velocities up to 2 m/s."""
    rng = random.Random(seed)

    def wall(name, x, y, hw, hh):
        return {"name": name, "shape": "polygon", "fixed": True, "position": [x, y], "friction": friction,
                "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    bodies = [wall("floor", 1.0, -0.05, 1.1, 0.05), wall("left", -0.05, 1.5, 0.05, 1.5),
              wall("right", 2.05, 1.5, 0.05, 1.5)]
    cols = int(1.7 / (2.5 * radius))
    for k in range(n):
        bodies.append({"name": f"b{k}", "shape": "circle", "radius": radius, "mass": 0.1,
                       "restitution": restitution, "friction": friction,
                       "position": [0.2 + (k % cols) * 2.5 * radius, 0.2 + (k // cols) * 2.5 * radius],
                       "velocity": [rng.uniform(-2, 2), rng.uniform(-2, 2)]})
    return {"name": f"pit of {n} balls, seed {seed}", "end_time": end_time, "frame_rate": 0,
            "gravity": [0.0, -9.81], "bodies": bodies}


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2])
def test_a_40_ball_pit_of_restitution_0_8_completes(seed, tmp_path):
    """Seed 1 stopped at t = 0.715 s and seed 2 at t = 0.594 s with more than
    100,000 events at one instant (a ball pinched between the wall and a
    sleeping ball, met again after every solve): the jam ends it."""
    scene = parse_scene(json.dumps(_pit(40, seed, 0.8, 0.0, 0.08, 5.0)), f"pit-{seed}.json")
    tr = run_scene(scene, "c")
    assert tr.events and tr.final["t"] == 5.0


# a contact met this many times at one instant has had its cluster solved CLUSTER_JAM (4) times after
# its first CLUSTER_REPEATS (64) meetings: the next meeting jams it (docs/simulator.md, "A jam")
JAM_MEETINGS = 64 + 4


@pytest.mark.slow
def test_the_jammed_pit_gives_the_same_bytes_in_every_runtime():
    """A pit of restitution 0.8 (seed 2) to t = 0.7 s, in all four runtimes:
    the same bytes, and the run holds a jam (a contact met JAM_MEETINGS
    times at one instant, then movers falling asleep at that instant)."""
    scene = parse_scene(json.dumps(_pit(40, 2, 0.8, 0.0, 0.08, 0.7)), "pit-2-short.json")
    traces, problems = crosscheck(scene, LANGS)
    assert not problems, problems
    assert all(tr.raw == traces[LANGS[0]].raw for tr in traces.values())
    events = traces["c"].events
    met: dict = {}
    last: dict = {}
    for k, e in enumerate(events):
        if e["kind"] == "collision":
            key = (e["t"], tuple(sorted(e["bodies"])))
            met[key] = met.get(key, 0) + 1
            last[key] = k
    jammed = [key for key, n in met.items() if n >= JAM_MEETINGS]
    assert jammed, "no contact is met often enough at one instant to jam"
    for t, pair in jammed:
        after = events[last[(t, pair)] + 1:]
        assert any(e["kind"] == "sleep" and e["t"] == t for e in after), \
            f"{pair} jammed at t = {t!r}, and nothing fell asleep at that instant"


@pytest.mark.slow
@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 10 ** 6))
def test_hypothesis_made_piles_never_stick_and_agree(seed):
    """Piles of balls, boxes or both, with friction or without (bench/hunt.py's
    pile family), with at most 1000 events at one instant: every runtime
    finishes, with the same bytes."""
    raw = pile_scene(seed, end_time=0.6)
    raw["max_events_at_one_time"] = 1000
    scene = parse_scene(json.dumps(raw), f"pile-{seed}.json")
    traces, problems = crosscheck(scene, LANGS)
    assert not problems, problems
    assert all(tr.raw == traces[LANGS[0]].raw for tr in traces.values())


def _orbiters(omega: float) -> dict:
    """A ball at rest inside the orbit of four fixed circles: never touched,
    always within their reach, so each pair is followed a Taylor window at
    a time (about 2,066 windows a pair at 10 rad/s for 10 s)."""
    bodies = [{"name": f"orbiter{k}", "shape": "circle", "fixed": True, "radius": 0.05, "position": [0, 0],
               "orbit": {"radius": 0.3, "angle": k * math.pi / 2}, "angular_velocity": omega} for k in range(4)]
    bodies.append({"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1, "position": [0.0, 0.0]})
    return {"end_time": 10.0, "gravity": [0, 0], "bodies": bodies}


def test_a_spin_that_needs_more_windows_than_max_events_is_refused():
    with pytest.raises(SceneError) as err:
        parse_scene(json.dumps(_orbiters(1e9)), "orbit.json")
    msg = str(err.value)
    assert msg.startswith("orbit.json: error: bodies[0] (orbiter0): turns at 1e+09 rad/s: one pair of it followed "
                          "to end_time takes 2.06e+11 Taylor windows (0.0484 rad each), each a horizon event, more "
                          "than max_events (10000000)"), msg
    parse_scene(json.dumps({**_orbiters(1e9), "max_events": 3 * 10 ** 11}), "orbit.json")     # raised: accepted
    fixed_only = _orbiters(1e9)
    fixed_only["bodies"].pop()
    parse_scene(json.dumps(fixed_only), "orbit.json")     # nothing movable: no pair is ever predicted


@pytest.mark.slow
def test_horizons_count_against_max_events_in_every_runtime(tmp_path, capsys):
    """8,256 horizons and no trace event: with --max-events 5000 each runtime
    stops at the 5001st event it handles and names the instant."""
    path = tmp_path / "orbiters.json"
    path.write_text(json.dumps(_orbiters(10.0)))
    for lang in LANGS:
        code, err = _simulate(capsys, "--lang", lang, path, "--max-events", "5000", "-q")
        assert code == 1 and err == (f"{path}: error: {lang} simulator: more than 5000 events (collisions, inputs, frames, "
                                     "cell crossings, horizons) at t = 6.0596990545550211: the run was stopped; "
                                     "raise max_events in the scene or --max-events, or shorten end_time\n"), err
    code, err = _simulate(capsys, "--lang", "c", path, "-o", tmp_path / "all.jsonl")
    assert code == 0 and "horizons 8256," in err
