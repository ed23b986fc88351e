"""The flat trace's converters (max2code/sim/simulate.py) write the same
bytes: `feed` (one checked line at a time), `feed_chunk` (many lines at
once) and `feed_events` with the C converter (the path of `max2code
simulate`: whole events, runtimes/c/tools/m2c_trace_json.c, Python for the
chunks it does not take), on every example's trace cut into chunks anywhere
between lines (between events for the C path), and on lines made to hit
each special case (whole numbers, minus zero, exponents, states of still
circles); a non-finite number or a bad line is the same error from all."""
import json
import random
import unittest.mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from max2code import facts
from max2code.paths import ROOT
from max2code.sim.scene import load_scene, parse_scene
from max2code.sim.simulate import SimBuild, SimulateError, TraceConverter, build_simulator, run_scene

EXAMPLES = sorted((ROOT / "examples").glob("*.json"))


def slow(scene, build, text, **kw):
    out = []
    conv = TraceConverter(scene, build, out.append, **kw)
    for line in text.splitlines():
        conv.feed(line)
    ends = conv.finish()      # writes the last event, the final states and the statistics
    return "".join(out), ends


def fast(scene, build, text, cuts, **kw):
    out = []
    conv = TraceConverter(scene, build, out.append, **kw)
    lines = text.splitlines(keepends=True)
    bounds = [0, *sorted(cuts), len(lines)]
    for a, b in zip(bounds, bounds[1:]):
        conv.feed_chunk("".join(lines[a:b]))
    ends = conv.finish()      # writes the last event, the final states and the statistics
    return "".join(out), ends


def in_c(scene, build, text, cuts, **kw):
    """feed_events with the C converter, the trace cut before the lines
    `cuts` (moved back to where an event begins)."""
    out = []
    conv = TraceConverter(scene, build, out.append, accelerate=True, **kw)
    assert conv._c is not None, "the C converter did not build"
    lines = text.splitlines(keepends=True)
    starts = sorted({k for k in cuts if not lines[k].startswith("S")})
    bounds = [0, *starts, len(lines)]
    for a, b in zip(bounds, bounds[1:]):
        conv.feed_events("".join(lines[a:b]).encode())
    ends = conv.finish()      # writes the last event, the final states and the statistics
    return "".join(out), ends


def in_c_sized(scene, build, text, cuts, **kw):
    """in_c, each chunk given as the first `size` bytes of a longer buffer
    (as stream_scene gives them: no slice), the bytes after it the start of
    a trace line that must not be read."""
    out = []
    conv = TraceConverter(scene, build, out.append, accelerate=True, **kw)
    lines = text.splitlines(keepends=True)
    starts = sorted({k for k in cuts if not lines[k].startswith("S")})
    bounds = [0, *starts, len(lines)]
    for a, b in zip(bounds, bounds[1:]):
        chunk = "".join(lines[a:b]).encode()
        conv.feed_events(chunk + b"E collision\nF 0 1.0 2.0", len(chunk))
    ends = conv.finish()
    return "".join(out), ends


def in_c_streamed(scene, build, text, cuts, **kw):
    """in_c as `max2code simulate` runs it: the C converter's output, the
    final states included, written as bytes as they come (write_bytes),
    in order with the rest."""
    out = []
    conv = TraceConverter(scene, build, out.append, accelerate=True,
                          write_bytes=lambda b: out.append(str(b, "ascii")), **kw)
    lines = text.splitlines(keepends=True)
    starts = sorted({k for k in cuts if not lines[k].startswith("S")})
    bounds = [0, *starts, len(lines)]
    for a, b in zip(bounds, bounds[1:]):
        conv.feed_events("".join(lines[a:b]).encode())
    stats = conv._finish()
    return "".join(out), stats


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_fast_path_writes_the_same_bytes_on_every_example(path):
    scene = load_scene(str(path))
    trace = run_scene(scene, "c")
    build = build_simulator("c", scene.effects, scene.taylor_order)
    n = len(trace.raw.splitlines())
    rng = random.Random(path.stem)
    want = slow(scene, build, trace.raw)
    assert want[0].count("\n") == len(trace.events) + 2
    for k in (0, 1, 7):
        cuts = rng.sample(range(1, n), min(k, n - 1))
        assert fast(scene, build, trace.raw, cuts) == want
    assert fast(scene, build, trace.raw, [], frames=False) == slow(scene, build, trace.raw, frames=False)
    for k in (0, 1, 7, n // 3):
        cuts = rng.sample(range(1, n), min(k, n - 1))
        assert in_c(scene, build, trace.raw, cuts) == want
    assert in_c(scene, build, trace.raw, [n // 2], frames=False) == slow(scene, build, trace.raw, frames=False)
    for k in (0, 7, n // 3):
        cuts = rng.sample(range(1, n), min(k, n - 1))
        assert in_c_sized(scene, build, trace.raw, cuts) == want
    f_lines = [k for k, x in enumerate(trace.raw.splitlines()) if x.startswith("F ")]
    for cuts in ([], [n // 3], f_lines[1::2], rng.sample(range(1, n), min(7, n - 1))):     # F lines in pieces
        assert in_c_streamed(scene, build, trace.raw, cuts) == (want[0], want[1][1])


@pytest.mark.slow      # builds and runs the C simulator
def test_the_c_converter_takes_collisions_and_states(monkeypatch):
    """On a trace of collisions and states the C code converts every chunk
    (Python is not asked), and the bytes are Python's."""
    scene = load_scene(str(ROOT / "examples" / "billiard-break.json"))
    trace = run_scene(scene, "c")
    build = build_simulator("c", scene.effects, scene.taylor_order)
    events = "".join(x for x in trace.raw.splitlines(keepends=True) if x[0] in "ES" and " frame " not in x)
    want = slow(scene, build, events)
    assert events.count("E collision") > 10
    monkeypatch.setattr(TraceConverter, "feed_chunk", lambda self, text: pytest.fail("Python converted " + text[:80]))
    n = len(events.splitlines())
    assert in_c(scene, build, events, [n // 4, n // 2]) == want


@pytest.mark.slow      # builds and runs the C simulator
def test_without_a_c_compiler_the_command_says_so_and_writes_the_same_bytes(monkeypatch):
    """When the C converter cannot be built, `auto` converts in Python
    after one note, `c` refuses with one line, `python` is silent; the
    trace is the same bytes on every path."""
    from max2code.sim import trace_json
    from max2code.sim.simulate import stream_scene

    scene = load_scene(str(ROOT / "examples" / "billiard-break.json"))

    def run(converter):
        out, notes = [], []
        stream_scene(scene, "c", out.append, converter=converter, warn=notes.append)
        return "".join(out), notes

    want, notes = run("c")
    assert notes == [] and want.count("\n") > 100
    assert run("python") == (want, [])
    monkeypatch.setattr(trace_json.TOOL, "_tried", True)
    monkeypatch.setattr(trace_json.TOOL, "_lib", None)
    monkeypatch.setattr(trace_json.TOOL, "_why", "gcc not found")
    got, notes = run("auto")
    assert got == want
    assert notes == ["max2code simulate: note: the C trace converter cannot be built (gcc not found); "
                     "converting the trace in Python (the same bytes, slower)"]
    with pytest.raises(SimulateError, match=r"^max2code simulate: error: --converter c: the C trace converter "
                                            r"cannot be built \(gcc not found\)$"):
        run("c")


SCENE = parse_scene(json.dumps({"end_time": 2.0, "bodies": [
    {"name": "a", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]},
    {"name": "b", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [1.0, 0.0]},
    {"name": "box", "shape": "polygon", "mass": 1.0, "position": [3.0, 0.0],
     "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]}],
    "inputs": [{"time": 0.5, "body": "a", "set_velocity": [1.0, 0.0]}]}), "<convert>")
BUILD = SimBuild("c", ".", [], {"circle_circle": ["cc0", "cc1"], "point_edge": ["pe0", "pe1", "pe2"]})
LINES = """E collision 0 0 1 0 -1 -1 0.5 0 1 -0 2
S 0 0 0 0 -1 0 0 0 0 0
S 1 0 1 0 1 -0 0 0 0 0
E frame 0.016666666666666666 -1 -1 -1 -1 -1 0 0 0 0 0
E input 0.5 0 -1 -1 0 -1 0 0 0 0 0
S 0 0.5 1.5 2.5 1 0 0 0 0 -9.8100000000000005
E support 0.75 2 1 1 3 2 3.0000000000000004 1e-05 0 1 1.5e+20
S 2 0.75 3.25 1e+20 -2 0 0.25 -3 0 -9.81
E stop 1 2 1 -1 -1 2 0 0 0 0 0
S 2 1 3 0 0 0 0 0 0 0
E leave 1.5 2 1 -1 -1 3 0 0 0 0 0
E collision 1.75 2 0 1 0 -1 4.25 0.125 -1 0 0.5
S 2 1.75 3.5 0.25 0.5 0.5 0.125 -0.5 0 0
F 0 1 2 3 4 0 0
F 1 -0 0.5 1e-300 -1 0 0
F 2 3 4 5 6 0.5 -0.25
N collisions 2
N stale 0
N sleeps 4
V circle_circle 1 12
V point_edge 0 0
V point_edge 2 7
"""


def test_special_lines_convert_alike():
    n = len(LINES.splitlines())
    want = slow(SCENE, BUILD, LINES)
    assert '"velocity":[-1.0,0.0]' in want[0] and '"impulse":1.5e+20' in want[0]
    assert want[1][1]["events"] == {"collisions": 2, "stale": 0, "sleeps": 4}
    assert want[1][1]["predictions"] == {"cc1": 12, "pe2": 7}
    for cuts in ([], [1], [2, 5], list(range(1, n))):
        assert fast(SCENE, BUILD, LINES, cuts) == want
        assert in_c(SCENE, BUILD, LINES, cuts) == want
    assert fast(SCENE, BUILD, LINES, [3], frames=False) == slow(SCENE, BUILD, LINES, frames=False)
    assert in_c(SCENE, BUILD, LINES, [3, 4], frames=False) == slow(SCENE, BUILD, LINES, frames=False)


def test_the_c_converter_takes_the_final_states(monkeypatch):
    """The F lines (one per body: 10^5 of them at the end of a big gas's trace) are converted in C, with
    Python's bytes, whole numbers, minus zero and exponents included."""
    finals = "".join(x for x in LINES.splitlines(keepends=True) if x.startswith("F"))
    want = slow(SCENE, BUILD, finals)
    assert '{"body":"b","position":[-0.0,0.5],"velocity":[1e-300,-1.0]' in want[0]
    monkeypatch.setattr(TraceConverter, "feed_chunk", lambda self, text: pytest.fail("Python converted " + text))
    assert in_c(SCENE, BUILD, finals, []) == want


@pytest.mark.parametrize("bad", ["S 0 0 nan 0 0 0 0 0 0 0", "S 0 0 1 inf 0 0 0 0 0 0", "S 0 0 1 0 -NaN 0 0 0 0 0",
                                 "S 9 0 1 0 0 0 0 0 0 0", "E collision 1 0 1 7 -1 -1 0 0 1 0 1",
                                 "E bounce 1 0 1 0 -1 -1 0 0 1 0 1", "Q 1 2", "N collisions 1.5",
                                 "E collision 1 0 1 0 -1 -1 0 0 1 0 inf",
                                 # a negative body index is refused, never read from the end of the names
                                 "S -1 0 1 0 0 0 0 0 0 0", "E collision 1 -1 0 0 -1 -1 0 0 1 0 1",
                                 "E stop 1 2 -1 -1 -1 2 0 0 0 0 0", "V point_edge -1 3"])
def test_bad_lines_are_the_same_error(bad):
    text = LINES.replace("S 0 0 0 0 -1 0 0 0 0 0\n", bad + "\n", 1)
    with pytest.raises(SimulateError) as a:
        slow(SCENE, BUILD, text)
    with pytest.raises(SimulateError) as b:
        fast(SCENE, BUILD, text, [4])
    with pytest.raises(SimulateError) as c:
        in_c(SCENE, BUILD, text, [3, 4])
    assert str(a.value) == str(b.value) == str(c.value) and "bad trace line 2" in str(a.value)


@pytest.mark.parametrize("bad", ["F 1 -0 0.5 nan -1 0 0", "F 7 -0 0.5 1e-300 -1 0 0", "F 1 -0 0.5 1e-300 -1 0",
                                 "F 1 -0 0.5 1e-300 -1 0 -inf", "F -1 -0 0.5 1e-300 -1 0 0"])
def test_bad_final_states_are_the_same_error(bad):
    """The final states (converted a block at a time on the command's path)."""
    text = LINES.replace("F 1 -0 0.5 1e-300 -1 0 0\n", bad + "\n", 1)
    with pytest.raises(SimulateError) as a:
        slow(SCENE, BUILD, text)
    for cuts in ([4], [13], [14], [15], [16]):
        with pytest.raises(SimulateError) as b:
            fast(SCENE, BUILD, text, cuts)
        with pytest.raises(SimulateError) as c:
            in_c(SCENE, BUILD, text, cuts)
        assert str(a.value) == str(b.value) == str(c.value) and "bad trace line 15" in str(a.value)


@pytest.mark.parametrize("names", [["a", "b c", "x~!{}"], ['quote"d'], ["back\\slash"], ["del\x7f"], ["é"],
                                   ["tab\t"], ["plain", "line\nbreak"], ["\u2603", "ok"]])
def test_names_are_their_json(names):
    from max2code.sim.simulate import _json_names
    assert _json_names(names) == [json.dumps(n) for n in names]


# ---- hypothesis-made traces: the three paths write the same bytes ----

def _g17(x: float) -> str:
    return "%.17g" % x      # how every runtime writes a number


NUMBERS = st.one_of(st.floats(allow_nan=False, allow_infinity=False).map(_g17),
                    st.integers(-10 ** 6, 10 ** 6).map(str),
                    st.sampled_from(["0", "-0", "1", "-1", "0.5", "1e+20", "1e-300", "-2.5e-05", "4.9406564584124654e-324",
                                     "1.7976931348623157e+308", "123456789012345678"]))
BODY = st.integers(0, 2)
INDEX = st.integers(-1, 4)          # a vertex or edge of SCENE, or -1


ALL_KINDS = ["collision", "support", "stop", "leave", "sleep", "wake", "input", "frame"]
COMMON_KINDS = ["collision", "support", "frame"]      # the lines the C converter takes (with states)


@st.composite
def events(draw, kinds=tuple(ALL_KINDS)):
    """One event line of SCENE's trace and its state lines."""
    kind = draw(st.sampled_from(kinds))
    t = draw(NUMBERS)
    if kind in ("collision", "support"):
        feat = 1 if kind == "support" else draw(st.integers(0, 1))
        nums = " ".join(draw(NUMBERS) for _ in range(5))
        head = f"E {kind} {t} {draw(BODY)} {draw(BODY)} {feat} {draw(INDEX)} {draw(INDEX)} {nums}"
    elif kind in ("stop", "leave", "sleep"):
        head = f"E {kind} {t} {draw(BODY)} {draw(BODY)} -1 -1 {draw(INDEX)} 0 0 0 0 0"
    elif kind == "wake":
        head = f"E wake {t} {draw(BODY)} -1 -1 -1 {draw(INDEX)} 0 0 0 0 0"
    elif kind == "input":
        head = f"E input {t} {draw(BODY)} -1 -1 0 -1 0 0 0 0 0"
    else:
        head = f"E frame {t} -1 -1 -1 -1 -1 0 0 0 0 0"
    states = [] if kind == "frame" else [f"S {draw(BODY)} {t} " + " ".join(draw(NUMBERS) for _ in range(8))
                                         for _ in range(draw(st.integers(0, 3)))]
    return [head, *states]


@st.composite
def traces(draw, kinds=tuple(ALL_KINDS), tail=True):
    """A trace of SCENE (`tail`: with the final states, counters and
    variants), and where to cut it."""
    lines = [x for ev in draw(st.lists(events(kinds), min_size=1, max_size=25)) for x in ev]
    if tail:
        lines += [f"F {k} " + " ".join(draw(NUMBERS) for _ in range(6)) for k in range(3)]
        lines += [f"N {name} {draw(st.integers(0, 10 ** 12))}" for name in facts.STAT_NAMES]
        lines += [f"V circle_circle {k} {draw(st.integers(0, 99))}" for k in range(2)]
        lines += [f"V point_edge {k} {draw(st.integers(0, 99))}" for k in range(3)]
    text = "".join(x + "\n" for x in lines)
    cuts = draw(st.lists(st.integers(1, len(lines) - 1), max_size=6, unique=True)) if len(lines) > 1 else []
    return text, cuts


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(traces(), st.booleans())
def test_made_traces_convert_alike(trace, frames):
    """Python line by line, Python by chunks and the C converter give the
    same bytes on any trace, cut anywhere (the C path between events)."""
    text, cuts = trace
    want = slow(SCENE, BUILD, text, frames=frames)
    assert fast(SCENE, BUILD, text, cuts, frames=frames) == want
    assert in_c(SCENE, BUILD, text, cuts, frames=frames) == want
    assert in_c_streamed(SCENE, BUILD, text, cuts, frames=frames) == (want[0], want[1][1])


@pytest.mark.slow
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(traces(tuple(COMMON_KINDS), tail=False), st.booleans())
def test_made_traces_of_the_common_lines_convert_in_c(trace, frames):
    """On traces of collisions, supports, frames and states (the lines a
    run writes by the million) the C converter takes every chunk, and its
    bytes are Python's."""
    text, cuts = trace
    want = slow(SCENE, BUILD, text, frames=frames)
    assert fast(SCENE, BUILD, text, cuts, frames=frames) == want

    def refuse(self, chunk):
        raise AssertionError("Python converted " + chunk[:80])
    with unittest.mock.patch.object(TraceConverter, "feed_chunk", refuse):
        assert in_c(SCENE, BUILD, text, cuts, frames=frames) == want
