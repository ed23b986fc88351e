"""The one check of flat text (docs/simulator.md, "Flat scene checks"): every
runtime refuses the same hostile flat scene with the same X line and exit
status 1, never a crash, a hang, a huge allocation or NaN in a trace.

Each case is the flat scene of a small valid scene (a fixed floor, a ball, a
movable box, one input) with one fault put in; the expected line is the
specification's message for the first fault."""
from __future__ import annotations

import json
import math
import subprocess

import pytest

from max2code.sim.scene import compile_scene, parse_scene
from max2code.sim.simulate import LANGS, build_simulator

SCENE = {"end_time": 2.0, "gravity": [0, -9.81], "bodies": [
    {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -1],
     "vertices": [[-3, -0.5], [3, -0.5], [3, 0.5], [-3, 0.5]]},
    {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0], "velocity": [0.5, 0]},
    {"name": "box", "shape": "polygon", "mass": 2.0, "position": [1, 0],
     "vertices": [[-0.2, -0.2], [0.2, -0.2], [0.2, 0.2], [-0.2, 0.2]]}],
    "inputs": [{"time": 0.5, "body": "ball", "set_velocity": [1.0, 0.0]}]}

BODY_FIELDS = ("poly fixed inv_mass inv_inertia restitution friction px py vx vy ax ay angle omega radius orbit "
               "orbit_angle bound window large nverts").split()
VERTEX_FIELDS = "lx ly rho beta psi h s1 s2 nx ny cover".split()


def base() -> tuple[object, str]:
    sc = parse_scene(json.dumps(SCENE), "in-memory")
    return sc, compile_scene(sc)


class Flat:
    """The base flat scene as lines, with helpers that put one fault in."""

    def __init__(self, text: str):
        self.lines = text.splitlines()

    def text(self) -> str:
        return "\n".join(self.lines) + "\n"

    def _index(self, prefix: str) -> int:
        return next(i for i, ln in enumerate(self.lines) if ln.split()[0] == prefix)

    def header(self, key: str, *values) -> "Flat":
        self.lines[self._index(key)] = " ".join([key, *map(str, values)])
        return self

    def header_field(self, key: str, k: int, value) -> "Flat":
        i = self._index(key)
        words = self.lines[i].split()
        words[1 + k] = str(value)
        self.lines[i] = " ".join(words)
        return self

    def _body_line(self, k: int) -> int:
        return [i for i, ln in enumerate(self.lines) if ln.startswith("body ")][k]

    def body(self, k: int, **fields) -> "Flat":
        i = self._body_line(k)
        words = self.lines[i].split()
        for name, v in fields.items():
            words[1 + BODY_FIELDS.index(name)] = str(v)
        self.lines[i] = " ".join(words)
        return self

    def vertex(self, k: int, j: int, **fields) -> "Flat":
        i = self._body_line(k) + 1 + j
        words = self.lines[i].split()
        assert words[0] == "v"
        for name, v in fields.items():
            words[1 + VERTEX_FIELDS.index(name)] = str(v)
        self.lines[i] = " ".join(words)
        return self

    def replace_vertices(self, k: int, rows: list[str]) -> "Flat":
        i = self._body_line(k)
        n = int(self.lines[i].split()[-1])
        self.lines[i + 1:i + 1 + n] = rows
        return self.body(k, nverts=len(rows))

    def inputs(self, *rows: str) -> "Flat":
        i = self._index("inputs")
        n = int(self.lines[i].split()[1])
        self.lines[i:i + 1 + n] = [f"inputs {len(rows)}", *rows]
        return self

    def raw(self, old: str, new: str) -> "Flat":
        t = self.text()
        assert old in t
        self.lines = t.replace(old, new, 1).splitlines()
        return self


def pentagram() -> list[str]:
    import math
    pts = [(0.2 * math.cos(math.pi / 2 + 4 * math.pi * i / 5), 0.2 * math.sin(math.pi / 2 + 4 * math.pi * i / 5))
           for i in range(5)]
    return [f"v {x!r} {y!r} 0.2 0.0 0.0 0.1 -0.1 0.1 1.0 0.0 -1" for x, y in pts]


def cases() -> list[tuple[str, object, str]]:
    """(id, fault maker on a Flat, expected X message)."""
    c = []

    def add(name, make, msg):
        c.append((name, make, msg))

    # words and numbers
    add("end-nan", lambda f: f.header("end", "nan"), "scene: expected a number, found 'nan'")
    add("end-inf", lambda f: f.header("end", "inf"), "scene: expected a number, found 'inf'")
    add("end-hex", lambda f: f.header("end", "0x1p1"), "scene: expected a number, found '0x1p1'")
    add("end-underscore", lambda f: f.header("end", "1_0"), "scene: expected a number, found '1_0'")
    add("end-overflow", lambda f: f.header("end", "1e999"), "scene: number '1e999' is beyond a double's range")
    add("end-long", lambda f: f.header("end", "1" * 70),
        "scene: expected a number, found '" + "1" * 32 + "...'")
    add("integer-19-digits", lambda f: f.header("max_same_time", "1000000000000000000"),
        "scene: expected an integer, found '1000000000000000000'")
    add("integer-plus", lambda f: f.header("max_same_time", "+5"), "scene: expected an integer, found '+5'")
    add("trailing", lambda f: f.raw("\nend\n", "\nend\nfoo\n"), "scene: unexpected 'foo' after the end")
    add("ends-early", lambda f: f.raw("\nend\n", "\n"), "scene: ends early (expected 'end')")
    # header
    add("version", lambda f: f.header("m2c-scene", 2), "scene: unknown version 2")
    add("end-negative", lambda f: f.header("end", "-1.0"), "scene: end -1 outside (0, 1e150]")
    add("end-zero", lambda f: f.header("end", "0.0"), "scene: end 0 outside (0, 1e150]")
    add("frame-negative", lambda f: f.header("frame", "-0.5"), "scene: frame -0.5 is negative")
    add("frame-too-many", lambda f: f.header("frame", "1e-15"),
        "scene: frame 1.0000000000000001e-15 gives more than 1e12 frames")
    add("tolerance-zero", lambda f: f.header("tolerance", "0.0"), "scene: tolerance 0 outside [1e-150, 1e150]")
    add("rest-speed", lambda f: f.header("rest_speed", "-1"), "scene: rest_speed -1 is negative")
    add("rest-speed-huge", lambda f: f.header("rest_speed", "1e151"),
        "scene: rest_speed 1e+151 beyond 1e150")
    add("window-angle", lambda f: f.header("window_angle", "0.7"),
        "scene: window_angle 0.69999999999999996 outside (0, 0.5]")
    add("window-angle-zero", lambda f: f.header("window_angle", "0"), "scene: window_angle 0 outside (0, 0.5]")
    add("max-same", lambda f: f.header("max_same_time", "0"), "scene: max_same_time 0 is less than 1")
    add("max-events", lambda f: f.header("max_events", "0"), "scene: max_events 0 is less than 1")
    add("max-events-negative", lambda f: f.header("max_events", "-3"), "scene: max_events -3 is less than 1")
    add("max-events-missing", lambda f: f.raw("\nmax_events ", "\nmax_event "),
        "scene: expected 'max_events', found 'max_event'")
    add("grid-origin", lambda f: f.header_field("grid", 0, "1e151"), "scene: grid origin beyond 1e150")
    add("grid-cell-nan", lambda f: f.header_field("grid", 2, "nan"), "scene: expected a number, found 'nan'")
    add("grid-cell-zero", lambda f: f.header_field("grid", 3, "0"), "scene: grid cell 0 outside [1e-150, 1e150]")
    # each pair of grid words is checked once read: a bad cell before a bad count is the cell's fault
    add("grid-cell-before-count", lambda f: f.header("grid", "0", "0", "1e308", "1", "-0.0", "2", "0"),
        "scene: grid cell 1e+308 outside [1e-150, 1e150]")
    add("grid-origin-before-cell", lambda f: f.header("grid", "1e151", "0", "x"), "scene: grid origin beyond 1e150")
    add("grid-no-cells", lambda f: f.header_field("grid", 4, "0"), "scene: grid of 0 x 2 cells")
    add("grid-huge", lambda f: f.header_field("grid", 4, "100000000"),
        "scene: grid of 100000000 x 2 cells for 3 bodies (at most max(16, 4 x bodies) cells)")
    add("bodies-huge", lambda f: f.header("bodies", "2000000000"), "scene: 2000000000 bodies (1 to 1000000)")
    add("bodies-zero", lambda f: f.header("bodies", "0"), "scene: 0 bodies (1 to 1000000)")
    # bodies
    add("poly-2", lambda f: f.body(1, poly=2), "scene: body 1: poly must be 0 or 1")
    add("large-7", lambda f: f.body(1, large=7), "scene: body 1: large must be 0 or 1")
    add("fixed-inv-mass", lambda f: f.body(0, inv_mass="1.0"), "scene: body 0: a fixed body has inverse mass 0")
    add("inv-mass-negative", lambda f: f.body(1, inv_mass="-1"), "scene: body 1: inverse mass -1 must be positive")
    add("inv-mass-nan", lambda f: f.body(1, inv_mass="nan"), "scene: expected a number, found 'nan'")
    add("inv-inertia-zero", lambda f: f.body(2, inv_inertia="0"), "scene: body 2: inverse inertia 0 must be positive")
    add("circle-inertia", lambda f: f.body(1, inv_inertia="1"), "scene: body 1: a circle has inverse inertia 0")
    add("restitution-5", lambda f: f.body(1, restitution="5"), "scene: body 1: restitution 5 outside [0, 1]")
    add("friction-negative", lambda f: f.body(1, friction="-1"), "scene: body 1: friction -1 is negative")
    add("radius-tiny", lambda f: f.body(1, radius="1e-12"),
        "scene: body 1: radius 9.9999999999999998e-13 outside [tolerance, 1e150]")
    add("radius-negative", lambda f: f.body(1, radius="-0.1"),
        "scene: body 1: radius -0.10000000000000001 outside [tolerance, 1e150]")
    add("circle-vertices", lambda f: f.body(1, nverts=1), "scene: body 1: a circle has no vertices")
    add("orbit-tiny", lambda f: f.body(1, orbit="1e-12"),
        "scene: body 1: orbit radius 9.9999999999999998e-13 outside [tolerance, 1e150]")
    add("orbit-movable", lambda f: f.body(1, orbit="0.5", bound="0.6"), "scene: body 1: an orbiting circle must be fixed")
    add("circle-spin", lambda f: f.body(1, omega="1.0"), "scene: body 1: a circle turns only about an orbit")
    add("polygon-radius", lambda f: f.body(2, radius="0.1"), "scene: body 2: a polygon has no radius or orbit")
    add("polygon-2-vertices", lambda f: f.body(2, nverts=2), "scene: body 2: 2 vertices (3 to 1024)")
    add("polygon-5000-vertices", lambda f: f.body(2, nverts=5000), "scene: body 2: 5000 vertices (3 to 1024)")
    add("window-body", lambda f: f.body(2, window="0.7"), "scene: body 2: window 0.69999999999999996 outside [0, 0.5]")
    add("bound-small", lambda f: f.body(1, bound="0.05"),
        "scene: body 1: bound 0.050000000000000003 is too small or too large")
    add("reach", lambda f: f.body(1, vx="1.5e150"), "scene: body 1: reaches more than 2e150 m from the origin by the end")
    add("reach-position", lambda f: f.body(1, px="1e300"),
        "scene: body 1: reaches more than 2e150 m from the origin by the end")
    # vertices
    add("vertex-outside", lambda f: f.vertex(2, 0, lx="-5"), "scene: body 2 vertex 0: outside the bound")
    add("vertex-rho-far", lambda f: f.vertex(2, 1, rho="1e308"), "scene: body 2 vertex 1: outside the bound")
    add("vertex-rho-negative", lambda f: f.vertex(2, 1, rho="-0.1"), "scene: body 2 vertex 1: outside the bound")
    add("vertex-h-far", lambda f: f.vertex(2, 2, h="-1e200"), "scene: body 2 vertex 2: outside the bound")
    add("vertex-s2-far", lambda f: f.vertex(2, 0, s2="0.6"), "scene: body 2 vertex 0: outside the bound")
    add("normal-not-unit", lambda f: f.vertex(2, 1, nx="2"), "scene: body 2 vertex 1: the normal is not a unit vector")
    add("cover-missing", lambda f: f.vertex(0, 0, cover="7"), "scene: body 0 vertex 0: cover 7 is not a body")
    add("cover-self", lambda f: f.vertex(0, 0, cover="0"), "scene: body 0 vertex 0: cover 0 is not a body")
    add("cover-movable", lambda f: f.vertex(0, 0, cover="2"), "scene: body 0 vertex 0: cover 2 is not a fixed body")
    add("edge-short", lambda f: f.vertex(2, 1, lx="-0.199999999999", ly="-0.2"),
        "scene: body 2 vertex 0: edge shorter than the tolerance")
    add("not-convex", lambda f: f.vertex(2, 2, lx="-0.1", ly="-0.1"),
        "scene: body 2 vertex 2: not strictly convex (counter-clockwise)")
    add("pentagram", lambda f: f.replace_vertices(2, pentagram()), "scene: body 2: the polygon winds 2 times")
    add("normal-inward", lambda f: f.vertex(2, 0, ny="1.0"),
        "scene: body 2 vertex 0: the normal does not point outward")
    # inputs
    add("inputs-huge", lambda f: f.raw("\ninputs 1\n", "\ninputs 20000000\n"),
        "scene: 20000000 inputs (0 to 10000000)")
    add("input-time-nan", lambda f: f.inputs("input nan 1 0 1.0 0.0"), "scene: expected a number, found 'nan'")
    add("input-time-late", lambda f: f.inputs("input 3.0 1 0 1.0 0.0"), "scene: input 0: time 3 outside [0, end]")
    add("input-vector-inf", lambda f: f.inputs("input 0.5 1 0 inf 0.0"), "scene: expected a number, found 'inf'")
    add("input-no-body", lambda f: f.inputs("input 0.5 7 0 1.0 0.0"), "scene: input on body 7, which does not exist")
    add("removal-vector", lambda f: f.inputs("input 0.5 1 4 1.0 0.0"), "scene: input 0: a removal has no vector")
    add("teleport-far", lambda f: f.inputs("input 0.5 1 3 1e200 0.0"), "scene: input 0: teleport beyond 1e150 m")
    add("input-after-removal", lambda f: f.inputs("input 0.5 1 4 0 0", "input 0.7 1 0 1.0 0.0"),
        "scene: input 1: body 1 was removed by input 0")
    return c


CASES = cases()


@pytest.mark.slow
def test_the_base_scene_runs():
    """Every case's base is a valid scene (so each fault is the only one)."""
    sc, flat = base()
    build = build_simulator("python", sc.effects, sc.taylor_order)
    proc = subprocess.run(build.run_cmd, input=flat, capture_output=True, text=True, cwd=build.workdir, timeout=300)
    assert proc.returncode == 0 and not proc.stdout.startswith("X"), proc.stdout[-500:]


@pytest.mark.slow
def test_a_non_ascii_byte_is_refused_at_its_offset():
    sc, flat = base()
    bad = flat.replace("tolerance", "tolérance").encode("utf-8")
    offset = bad.index("é".encode("utf-8"))
    for lang in LANGS:
        build = build_simulator(lang, sc.effects, sc.taylor_order)
        proc = subprocess.run(build.run_cmd, input=bad, capture_output=True, cwd=build.workdir, timeout=120)
        assert (lang, proc.returncode, proc.stdout) == (
            lang, 1, f"X scene: byte {offset}: not printable ASCII\n".encode()), proc.stderr[-500:]


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_every_runtime_refuses_each_fault_with_the_same_line(lang):
    sc, flat = base()
    build = build_simulator(lang, sc.effects, sc.taylor_order)
    wrong = []
    for name, make, msg in CASES:
        text = make(Flat(flat)).text()
        proc = subprocess.run(build.run_cmd, input=text, capture_output=True, text=True, cwd=build.workdir,
                              timeout=120)
        got = (proc.returncode, proc.stdout)
        if got != (1, f"X {msg}\n"):
            wrong.append(f"{name}: expected exit 1 and 'X {msg}', got exit {proc.returncode}: "
                         f"{proc.stdout[-200:]!r} {proc.stderr[-200:]!r}")
    assert not wrong, f"{len(wrong)} of {len(CASES)} cases:\n" + "\n".join(wrong)


# The Python runtime's live API (docs/simulator.md, "Flat scene checks", "Live API").

def _python_world():
    from max2code.sim.live import python_world
    sc, _ = base()
    return sc, python_world(sc)


def _ball_text(sc) -> str:
    from max2code.sim.live import flat_body
    return flat_body(sc, {"shape": "circle", "radius": 0.1, "mass": 1.0, "position": [-2.0, 0.0]})


def _set_body(text: str, **fields) -> str:
    words = text.split("\n")[0].split()
    for name, v in fields.items():
        words[1 + BODY_FIELDS.index(name)] = str(v)
    return " ".join(words) + "\n" + "\n".join(text.split("\n")[1:])


ADD_BODY_CASES = [
    ("restitution", lambda t: _set_body(t, restitution="5"), "add_body: body 3: restitution 5 outside [0, 1]"),
    ("nan", lambda t: _set_body(t, px="nan"), "add_body: expected a number, found 'nan'"),
    ("overflow", lambda t: _set_body(t, vy="1e400"), "add_body: number '1e400' is beyond a double's range"),
    ("reach", lambda t: _set_body(t, vx="1e200"),
     "add_body: body 3: reaches more than 2e150 m from the origin by the end"),
    ("vertices", lambda t: _set_body(t, nverts="2"), "add_body: body 3: a circle has no vertices"),
    ("trailing", lambda t: t + "body\n", "add_body: unexpected 'body' after the body"),
    ("non-ascii", lambda t: "b\u00e9" + t, "add_body: byte 1: not printable ASCII"),
    ("keyword", lambda t: "bodies" + t[4:], "add_body: expected 'body', found 'bodies'"),
]


@pytest.mark.parametrize("name,make,msg", ADD_BODY_CASES, ids=[c[0] for c in ADD_BODY_CASES])
def test_python_add_body_checks_its_text_as_a_scene_body(name, make, msg):
    from max2code_rt.sim import SimError
    sc, w = _python_world()
    text = _ball_text(sc)
    assert text.startswith("body ") and make(text) != text
    with pytest.raises(SimError) as err:
        w.add_body(make(text))
    assert str(err.value) == msg
    assert len(w.s.bodies) == 3
    assert w.add_body(text) == 3          # the good text still joins


def test_python_add_body_cover_counts_the_bodies_in_the_world():
    from max2code_rt.sim import SimError
    from max2code.sim.live import flat_body
    sc, w = _python_world()
    box = flat_body(sc, {"shape": "polygon", "mass": 1.0, "position": [-2.0, 1.0],
                         "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]})
    lines = box.split("\n")
    assert lines[1].startswith("v ") and lines[1].split()[-1] == "-1"
    bad = "\n".join([lines[0], lines[1][:lines[1].rindex(" ")] + " 3", *lines[2:]])
    with pytest.raises(SimError) as err:
        w.add_body(bad)
    assert str(err.value) == "add_body: body 3 vertex 0: cover 3 is not a body"
    assert w.add_body(box) == 3


def test_python_live_inputs_refuse_results_that_are_not_finite():
    from max2code_rt.sim import SimError
    sc, w = _python_world()
    w.advance(0.1)
    before = w.state(1, 0.1)
    cases = [(lambda: w.set_velocity(1, math.inf, 0.0), "live input: body 1: velocity would not be finite"),
             (lambda: w.add_velocity(1, 1e140, 0.0), None),
             (lambda: w.add_velocity(1, 1.7e308, 0.0),
              "live input: body 1: reaches more than 2e150 m from the origin by the end"),
             (lambda: w.apply_impulse(1, 1.7e308, 0.0),
              "live input: body 1: reaches more than 2e150 m from the origin by the end"),
             (lambda: w.teleport(1, math.nan, 0.0), "live input: body 1: position would not be finite"),
             (lambda: w.teleport(1, 1e150, 1e150), "live input: body 1: teleport beyond 1e150 m"),
             (lambda: w.set_velocity(3, 0.0, 0.0), "live input: body 3 does not exist"),
             (lambda: w.remove_body(2 ** 64 + 1), f"live input: body {2 ** 64 + 1} does not exist"),
             (lambda: w.add_velocity(-1, 0.0, 0.0), "live input: body -1 does not exist")]
    for make, msg in cases:
        if msg is None:                 # an accepted input: 1e140 m/s reaches 2e140 m by the end
            make()
            continue
        n = len(w.s.inputs)
        with pytest.raises(SimError) as err:
            make()
        assert str(err.value) == msg
        assert len(w.s.inputs) == n     # nothing recorded
    assert w.state(1, 0.1)[0] == before[0]


def test_python_world_refuses_inputs_and_bodies_after_finish():
    from max2code_rt.sim import SimError
    sc, w = _python_world()
    text = _ball_text(sc)
    w.advance(sc.end_time)
    w.finish()
    for call in (lambda: w.set_velocity(1, 1.0, 0.0), lambda: w.teleport(1, 0.0, 0.0), lambda: w.remove_body(1),
                 lambda: w.add_body(text)):
        with pytest.raises(SimError) as err:
            call()
        assert str(err.value) == "live input: the world is finished"


def test_the_json_check_bounds_the_event_counts_as_the_flat_check_does():
    """Every JSON-compiled scene passes the flat check: max_events_at_one_time
    (the flat scene's max_same_time, an integer of at most 18 digits) and
    max_events are whole numbers below 10^18."""
    from max2code.sim.scene import SceneError
    from max2code_rt.sim import Scene
    for field in ("max_events_at_one_time", "max_events"):
        with pytest.raises(SceneError, match=f"{field}.*below 10\\^18"):
            parse_scene(json.dumps({**SCENE, field: 1e18}), "in-memory")
    sc = parse_scene(json.dumps({**SCENE, "max_events_at_one_time": 999999999999999872}), "in-memory")
    assert Scene(compile_scene(sc)).max_same == 999999999999999872
    sc = parse_scene(json.dumps({**SCENE, "max_events": 999999999999999872}), "in-memory")
    assert Scene(compile_scene(sc)).max_events == 999999999999999872
