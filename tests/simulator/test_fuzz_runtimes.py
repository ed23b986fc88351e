"""The four simulators under hostile input (bench/fuzz.py): mutated flat
scenes and random live sessions give the same answer in C, Rust, Python and
Modula-2, with exit status 0 or 1, in bounded time and memory; and each
fault the fuzzing found, pinned as a case of its own."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import pytest

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path.insert(0, str(ROOT / "bench"))

import fuzz  # noqa: E402  (bench/fuzz.py)
from max2code.sim.scene import SceneError, parse_scene  # noqa: E402
from max2code.sim.simulate import LANGS  # noqa: E402


@pytest.fixture(scope="module")
def runners():
    return fuzz.runners(LANGS)


@pytest.fixture(scope="module")
def bases():
    return fuzz.base_scenes()


def answers(runners, data: bytes, step=None) -> dict:
    """lang -> (exit status, stdout, stderr) of one input."""
    out = {}
    for lang, r in runners.items():
        run = r.run(data, step)
        assert not run.timed_out and run.signal is None, (lang, run.err[-500:])
        out[lang] = (run.status, run.out.decode("latin-1"), run.err.decode("latin-1"))
    return out


def one_answer(got: dict) -> tuple[int, str]:
    """The exit status and the last line of stdout, the same in every
    runtime (all of stdout and stderr are the same too)."""
    assert len(set(got.values())) == 1, {k: (v[0], v[1][-300:], v[2][-300:]) for k, v in got.items()}
    status, out, _ = next(iter(got.values()))
    return status, out.splitlines()[-1] if out else ""


def live_text(bases, name: str, *inputs: str) -> bytes:
    """A base scene with these live input lines (`T BODY MODE X Y`)."""
    text = bases[name][1]
    head = text[:text.index("\ninputs ")]
    return (f"{head}\ninputs {len(inputs)}\n" + "".join(f"input {i}\n" for i in inputs) + "end\n").encode()


# ------------------------------------------------------------------ the fixed-seed run
@pytest.mark.slow
def test_a_fixed_seed_fuzz_run_finds_every_runtime_agreeing(runners):
    """300 mutated scenes and 60 live sessions (seed 1): no disagreement, no
    crash, no timeout; both refusals and acceptances (the run is not
    vacuous)."""
    tally = fuzz.fuzz(300, 60, 1, LANGS, rs=runners)
    figs = tally.figures()
    assert figs["inputs"] == 360
    assert (figs["disagreements"], figs["crashes"], figs["timeouts"]) == (0, 0, 0), "\n".join(tally.failures)
    assert figs["refused"] > 50 and figs["accepted"] > 20, figs
    assert all(0 < v < 1024 for v in figs["peak_memory_mb"].values()), figs


def test_the_mutations_are_reproducible_and_varied(bases):
    import random
    a = [fuzz.mutated_scene(random.Random(7), bases) for _ in range(3)]
    b = [fuzz.mutated_scene(random.Random(7), bases) for _ in range(3)]
    assert a == b
    rng = random.Random(3)
    kinds = {fuzz.mutate(rng, bases["ledge"][1])[0] for _ in range(300)}
    assert kinds == {"flip", "insert", "swap", "number", "count", "truncate", "duplicate", "drop", "copy-body"}
    for kind in range(200):                     # an empty text (a truncation to nothing) mutates too
        assert isinstance(fuzz.mutate(rng, "")[1], bytes)


def test_a_disagreement_and_a_crash_are_counted():
    """check() itself: one runtime's other X line is a disagreement, a
    signal or exit status 2 a crash, a run out of time a timeout."""
    def run(status=1, out=b"X scene: a\n", sig=None, timed_out=False):
        r = fuzz.Run()
        r.status, r.out, r.signal, r.timed_out = status, out, sig, timed_out
        return r
    t = fuzz.Tally()
    assert not fuzz.check("same", b"", {"c": run(), "rust": run()}, t)
    assert fuzz.check("other", b"", {"c": run(), "rust": run(out=b"X scene: b\n")}, t)
    assert fuzz.check("signal", b"", {"c": run(), "rust": run(status=None, sig=11)}, t)
    assert fuzz.check("exit 2", b"", {"c": run(), "rust": run(status=2)}, t)
    assert fuzz.check("no X", b"", {"c": run(out=b"E x\n"), "rust": run(out=b"E x\n")}, t)
    assert fuzz.check("slow", b"", {"c": run(), "rust": run(status=None, out=b"", timed_out=True)}, t)
    assert (t.inputs, t.disagreements, t.crashes, t.timeouts) == (6, 3, 4, 1)
    # out of time where every other runtime found the scene stuck: slow, not a fault
    stuck = b"E x\nX more than 100000 events at t = 0.5: the scene is stuck\n"
    assert not fuzz.check("stuck", b"", {"c": run(out=stuck), "rust": run(out=stuck), "m2": run(out=stuck),
                                         "python": run(status=None, out=b"", timed_out=True)}, t)
    assert (t.timeouts, t.slow, t.refused) == (1, 1, 7)


# ------------------------------------------------------------------ what the fuzzing found
@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_negative_body_of_a_live_input_has_the_one_message_in_every_runtime(runners, bases):
    """Rust's `--live` reader named a negative body `no body -1`."""
    for body in (-1, -2147483648):
        got = answers(runners, live_text(bases, "ledge", f"0.5 {body} 1 1.0 0.0"), 0.25)
        assert one_answer(got) == (1, f"X live input: body {body} does not exist")


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_rest_speed_whose_square_overflows_is_refused(runners, bases):
    """rest_speed 1e160 ran with another horizon count in Modula-2 (its
    square is infinite); it is now refused by the flat check in every runtime
    and by the JSON check."""
    text = bases["wheel"][1]
    for v, expect in (("1e160", "X scene: rest_speed 1e+160 beyond 1e150"),
                      ("1e308", "X scene: rest_speed 1e+308 beyond 1e150")):
        bad = text.replace("\nrest_speed 0.05\n", f"\nrest_speed {v}\n").encode()
        got = answers(runners, bad)
        assert one_answer(got) == (1, expect)
    ok = text.replace("\nrest_speed 0.05\n", "\nrest_speed 1e150\n").encode()
    assert one_answer(answers(runners, ok))[0] == 0
    raw = dict(fuzz.BASES["wheel"], rest_speed=1e151)
    with pytest.raises(SceneError, match="rest_speed: 1e\\+151 m/s is more than 1e\\+150 m/s"):
        parse_scene(json.dumps(raw), "in-memory")


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_live_velocity_that_would_carry_a_body_out_of_range_is_refused(runners, bases):
    """add_velocity(1e308) on a ball (finite, so accepted before) would put
    it at 2e308 m by the end: refused with the scene's reach message in
    every runtime; a teleport near 1e150 m with the ball's velocity is
    still taken, and a fast one that stays in range too."""
    far = "X live input: body 1: reaches more than 2e150 m from the origin by the end"
    for line in ("0.5 1 1 1e+308 0.0", "0.5 1 0 0.0 -2e+150", "0.5 1 2 1e+200 0.0"):
        assert one_answer(answers(runners, live_text(bases, "ledge", line), 0.25)) == (1, far), line
    for line in ("0.0 1 3 1e+150 0.0", "0.5 1 3 9e+149 0.0", "0.5 1 0 1e+6 0.0"):
        assert one_answer(answers(runners, live_text(bases, "ledge", line), 0.5))[0] == 0, line


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_scripted_input_that_would_carry_a_body_out_of_range_stops_the_run(runners, bases):
    """An impulse of -1e308 scripted on the box's ball (not finite, or 2e308
    m by the end) made every runtime write NaN, then disagree: a scripted
    input is held to the live inputs' reach rule when it is handled, from
    the body's state at its time, with an X line naming the input and the
    instant (the trace's lines before it as usual); scripted inputs that
    stay in range (the ledge's ball fast, or teleported near 1e150 m) still
    run."""
    far = "reaches more than 2e150 m from the origin by the end"
    cases = (("0.0 3 2 -1e308 3.0", f"X input 0: body 3 at t = 0: {far}"),
             ("0.5 3 1 1e+200 0.0", f"X input 0: body 3 at t = 0.5: {far}"),
             ("0.25 4 0 0.0 -2e+150", f"X input 0: body 4 at t = 0.25: {far}"))
    for line, expect in cases:
        assert one_answer(answers(runners, live_text(bases, "box", line))) == (1, expect), line
    for line in ("0.5 1 1 1e+6 0.0", "0.5 1 3 9e+149 0.0"):
        assert one_answer(answers(runners, live_text(bases, "ledge", line)))[0] == 0, line


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_polygon_with_a_negative_bound_is_refused_by_rule_7_in_every_runtime(runners, bases):
    """C and Rust skipped 0 <= BOUND for a polygon and refused its first
    vertex as outside the bound (rule 9) where Python and Modula-2 refused
    the body line (rule 7, checked first)."""
    text = bases["ledge"][1]
    line = next(x for x in text.splitlines() if x.startswith("body 1 0 0.5 "))
    words = line.split()
    words[18] = "-0.1"
    bad = text.replace(line, " ".join(words)).encode()
    assert one_answer(answers(runners, bad)) == (1, "X scene: body 2: bound -0.10000000000000001 is too small or too large")


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_modula2_writes_its_probe_lines_before_a_refused_live_teleport(runners, bases):
    """A live teleport onto another body stops the run; Modula-2 lost the
    probe's buffered state lines (stderr empty) where the others wrote
    them."""
    got = answers(runners, live_text(bases, "ledge", "0.6 1 3 0.0 -1.0"), 0.25)
    status, last = one_answer(got)
    assert (status, last) == (1, "X live input 0: teleport refused (the body would overlap another)")
    assert got["m2"][2].count("\nP 0.5 ") == 3 and got["m2"][2] == got["c"][2]


def test_python_world_refuses_far_motion_and_leaves_the_world_as_it_was():
    from max2code.sim.live import python_world
    from max2code_rt.sim import SimError
    sc = parse_scene(json.dumps(fuzz.BASES["ledge"]), "in-memory")
    w = python_world(sc)
    w.advance(0.25)
    before = w.state(1, 0.25)
    n = len(w.s.inputs)
    for call in (lambda: w.add_velocity(1, 1e308, 0.0), lambda: w.set_velocity(1, 0.0, 2e150),
                 lambda: w.apply_impulse(1, 1e300, 0.0)):
        with pytest.raises(SimError, match="^live input: body 1: reaches more than 2e150 m from the origin by the end$"):
            call()
    assert len(w.s.inputs) == n and w.state(1, 0.25) == before
    w.add_velocity(1, 1e140, 0.0)               # 2e140 m by the end: taken
    assert math.isfinite(w.state(1, 0.25)[2]) and len(w.s.inputs) == n + 1


def test_python_add_body_counts_against_max_bodies(monkeypatch):
    """add_body on a world that has MAX_BODIES bodies is refused before its
    text is read (the limit lowered to the world's 3 bodies here)."""
    from max2code.sim.live import flat_body, python_world
    from max2code_rt.sim import SimError
    import max2code_rt.sim.live as live
    sc = parse_scene(json.dumps(fuzz.BASES["ledge"]), "in-memory")
    w = python_world(sc)
    text = flat_body(sc, {"shape": "circle", "radius": 0.1, "mass": 1.0, "position": [-2.0, 1.0]})
    monkeypatch.setattr(live, "MAX_BODIES", 3)
    with pytest.raises(SimError, match="^add_body: the world has 3 bodies \\(at most 3\\)$"):
        w.add_body(text)
    with pytest.raises(SimError, match="^add_body: the world has 3 bodies"):
        w.add_body("not a body at all")
    monkeypatch.setattr(live, "MAX_BODIES", 4)
    assert w.add_body(text) == 3


def _many_fixed_circles(n: int) -> str:
    """A flat scene of n fixed circles of radius 0.1 m, 1 m apart in rows of 1000."""
    rows = [f"body 0 1 0.0 0.0 1.0 0.0 {k % 1000}.0 {k // 1000}.0 0.0 0.0 0.0 0.0 0.0 0.0 0.1 0.0 0.0 0.1 0.0 0 0"
            for k in range(n)]
    head = ["m2c-scene 1", "end 1.0", "frame 0.0", "tolerance 1e-09", "rest_speed 0.05", "window_angle 0.1",
            "max_same_time 100000", "max_events 1000000", "grid -1.0 -1.0 10.0 10.0 101 101 0.1", f"bodies {n}"]
    return "\n".join(head + rows + ["inputs 0", "end"]) + "\n"


@pytest.mark.slow
def test_c_add_body_counts_against_max_bodies():
    """The C world (ctypes) refuses add_body at MAX_BODIES bodies with the
    Python world's line: a scene of 999,999 fixed circles, then two add_body."""
    from max2code.sim.cworld import CWorld
    from max2code.sim.live import flat_body
    from max2code.sim.simulate import world_library
    from max2code_rt.sim import SimError
    sc = parse_scene(json.dumps(fuzz.BASES["ledge"]), "in-memory")
    w = CWorld(str(world_library(sc, "c")), _many_fixed_circles(999_999))
    assert w.body_count() == 999_999
    one = flat_body(sc, {"shape": "circle", "radius": 0.1, "fixed": True, "position": [2000.0, 0.0]})
    two = flat_body(sc, {"shape": "circle", "radius": 0.1, "fixed": True, "position": [2002.0, 0.0]})
    assert w.add_body(one) == 999_999
    with pytest.raises(SimError, match="^add_body: the world has 1000000 bodies \\(at most 1000000\\)$"):
        w.add_body(two)
    w.close()


def _vertex_field(text: str, body: int, vertex: int, field: int, value: str) -> bytes:
    """The flat text with word `field` (1: LX ... 10: NY) of a body's vertex line replaced."""
    lines = text.splitlines(True)
    starts = [i for i, ln in enumerate(lines) if ln.startswith("body ")]
    k = starts[body] + 1 + vertex
    words = lines[k].split()
    assert words[0] == "v"
    words[field] = value
    lines[k] = " ".join(words) + "\n"
    return "".join(lines).encode()


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_a_vertex_whose_distance_or_edge_line_is_beyond_the_bound_is_refused(runners, bases):
    """A wall's vertex distance RHO of 1.8e308 (or -1e308) was read without a
    check: Python's broad phase stopped on an infinite corner (exit 3) where
    the others ran on.  Rule 9 bounds RHO by the bound and H, S1, S2 by
    twice it, in every runtime; the compiled values pass."""
    text = bases["box"][1]
    msg = "X scene: body 1 vertex 3: outside the bound"
    for field, value in ((3, "1.7976931348623157e308"), (3, "-1e308"), (3, "1.01"), (3, "-0.5"),
                         (6, "1e308"), (6, "-2.1"), (7, "-1e200"), (8, "2.1")):
        bad = _vertex_field(text, 1, 3, field, value)
        assert one_answer(answers(runners, bad)) == (1, msg), (field, value)
    for field, value in ((3, "1.004987562112089"), (3, "0"), (6, "-2.0"), (8, "2.0")):
        assert one_answer(answers(runners, _vertex_field(text, 1, 3, field, value)))[0] == 0, (field, value)


def test_a_run_out_of_time_where_the_others_hit_max_events_is_slow_not_a_timeout():
    """An orbiting post turning at 1e151 rad/s (or 2147483647) passes every
    check and meets horizons so often that C stops at max_events (10^7) in
    about 10 s; Python needs about 500 s for them, past the harness's 20 s,
    and Modula-2 13 s or more.  Out of time where at least two runtimes
    ended in time, all with the same max_events X line, is slow, as where
    they found the scene stuck; one runtime alone does not make it so."""
    stop = (b"X more than 10000000 events (collisions, inputs, frames, cell crossings, horizons) at "
            b"t = 7.9139339851708088e-144" + fuzz.STOPPED + b"\n")

    def run(status=1, out=stop, timed_out=False):
        r = fuzz.Run()
        r.status, r.out, r.timed_out = status, out, timed_out
        return r
    t = fuzz.Tally()
    slow = run(status=None, out=b"", timed_out=True)
    assert not fuzz.check("slow", b"", {"c": run(), "rust": run(), "m2": run(), "python": slow}, t)
    assert (t.timeouts, t.slow) == (0, 1)
    assert not fuzz.check("two slow", b"", {"c": run(), "rust": run(), "m2": slow, "python": slow}, t)
    assert (t.timeouts, t.slow) == (0, 3)
    assert fuzz.check("alone", b"", {"c": run(), "python": slow}, t)
    assert fuzz.check("alone of three", b"", {"c": run(), "m2": slow, "python": slow}, t)
    other = run(out=stop.replace(b"7.9139339851708088e-144", b"1e-143"))
    assert fuzz.check("differ", b"", {"c": run(), "rust": other, "m2": run(), "python": slow}, t)
    assert t.timeouts == 4


@pytest.mark.slow     # builds the four runtimes' simulators (the runners fixture)
def test_an_orbit_turning_at_1e151_rad_s_is_stopped_by_max_events_alike(runners, bases):
    """The scene of the test above with max_events 20000: every runtime
    stops it with the same X line (bounded by max_events, not hung)."""
    text = bases["wheel"][1]
    post = next(x for x in text.splitlines() if x.startswith("body 0 1 "))
    words = post.split()
    words[14] = "1e151"                         # OMEGA
    bad = text.replace(post, " ".join(words)).replace("\nmax_events 10000000\n", "\nmax_events 20000\n")
    status, last = one_answer(answers(runners, bad.encode()))
    assert status == 1 and last.startswith("X more than 20000 events (") and last.endswith(fuzz.STOPPED.decode())
