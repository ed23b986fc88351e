"""The simulator: scene checking, the Python reference on the examples,
zero-time chains, determinism, invariants, and the effects a scene uses."""
from __future__ import annotations

import glob
import json
import math
import os
from pathlib import Path
import subprocess
import sys

import pytest
from hypothesis import given, settings, strategies as st

from max2code.sim.invariants import check
from max2code.sim.replay import read_trace
from max2code.sim.scene import SceneError, compile_scene, load_scene, parse_scene
from max2code.sim.simulate import run_scene
from sim_scenes import random_scene  # noqa: E402

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "*.json")))


def ball(name="a", x=0.0, y=0.0, **kw):
    b = {"name": name, "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [x, y]}
    b.update(kw)
    return b


def scene_text(bodies, **kw):
    s = {"end_time": 1.0, "bodies": bodies}
    s.update(kw)
    return json.dumps(s)


BAD = [
    ("unknown scene key", scene_text([ball()], gravty=[0, 1]), "gravty: unknown key"),
    ("unknown body key", scene_text([ball(velocty=[1, 0])]), "bodies[0].velocty: unknown key"),
    ("negative mass", scene_text([ball(mass=-1.0)]), "bodies[0] (a).mass: must be positive"),
    ("zero mass", scene_text([ball(mass=0)]), "bodies[0] (a).mass: must be positive"),
    ("NaN", '{"end_time": 1, "bodies": [{"shape": "circle", "radius": NaN, "mass": 1, "position": [0, 0]}]}',
     "bodies[0] (body0).radius: must be finite"),
    ("infinite position", '{"end_time": 1, "bodies": [{"shape": "circle", "radius": 1, "mass": 1, "position": [Infinity, 0]}]}',
     "bodies[0] (body0).position[0]: must be finite"),
    ("non-convex", scene_text([{"name": "p", "shape": "polygon", "mass": 1, "position": [0, 0],
                                "vertices": [[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]]}]),
     "bodies[0] (p).vertices: the polygon is not strictly convex at vertex 2"),
    ("two vertices", scene_text([{"name": "p", "shape": "polygon", "mass": 1, "position": [0, 0],
                                  "vertices": [[0, 0], [1, 0]]}]), "bodies[0] (p).vertices: a polygon needs"),
    ("overlap", scene_text([ball("a", 0, 0), ball("b", 0.15, 0)]),
     "bodies[0] (a) and bodies[1] (b) overlap at t = 0 by 0.05"),
    ("polygon overlap", scene_text([{"name": "p", "shape": "polygon", "mass": 1, "position": [0, 0],
                                     "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}, ball("b", 1.05, 0.5)]),
     "bodies[0] (p) and bodies[1] (b) overlap"),
    ("string number", scene_text([ball(mass="1")]), "bodies[0] (a).mass: expected a number"),
    ("missing end", json.dumps({"bodies": [ball()]}), "missing required key 'end_time'"),
    ("duplicate name", scene_text([ball("a", 0, 0), ball("a", 1, 0)]), "bodies[1].name: 'a' is already"),
    ("orbit on movable", scene_text([ball(orbit={"radius": 0.5})]), "an orbiting circle must be fixed"),
    ("restitution", scene_text([ball(restitution=1.5)]), "restitution: must be at most 1"),
    ("input on fixed", scene_text([{"name": "w", "shape": "circle", "radius": 1, "fixed": True, "position": [0, 0]}],
                                  inputs=[{"time": 0.5, "body": "w", "set_velocity": [1, 0]}]),
     "inputs[0].body: 'w' is fixed"),
    ("input unknown body", scene_text([ball()], inputs=[{"time": 0.5, "body": "zz", "add_velocity": [1, 0]}]),
     'inputs[0].body: no body is named "zz"'),
    ("not json", "{", "1:2: error: not valid JSON"),
    ("bad order", scene_text([ball()], taylor_order=9), "taylor_order: must be an integer from 1 to 7"),
]


@pytest.mark.parametrize("text,expect", [(t, e) for _, t, e in BAD], ids=[n for n, _, _ in BAD])
def test_bad_scene_names_the_field(text, expect):
    with pytest.raises(SceneError) as exc:
        parse_scene(text, "bad.json")
    msg = str(exc.value)
    assert msg.startswith("bad.json"), msg
    assert expect in msg, msg


def test_bad_scene_from_the_command_line(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text(scene_text([ball(mass=-2.0)]))
    r = subprocess.run([sys.executable, "-m", "max2code", "simulate", "--lang", "python", str(p)],
                       capture_output=True, text=True)
    assert r.returncode == 1
    assert "Traceback" not in r.stderr
    assert "bodies[0] (a).mass: must be positive" in r.stderr


_json = st.recursive(st.none() | st.booleans() | st.floats(allow_nan=True) | st.integers() | st.text(max_size=5),
                     lambda kids: st.lists(kids, max_size=4) | st.dictionaries(st.text(max_size=8), kids, max_size=4),
                     max_leaves=20)


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(st.sampled_from(["end_time", "bodies", "gravity", "inputs", "frame_rate", "x"]), _json,
                       max_size=5))
def test_scene_parser_never_crashes(obj):
    try:
        parse_scene(json.dumps(obj), "h.json")
    except SceneError as exc:
        assert str(exc).startswith("h.json")


_EDGE = [0, 1, 0.5, -0.0, 2.0, 1.5, -1.0, 1e-200, 1e300, 2 ** 63, 2 ** 1100, float("inf"), True, False, None,
         "circle", "polygon", "body3", "", [1.0], [1.0, 2.0], [0, float("nan")], [True, 1.0], {"radius": 1.0}]
_field = st.one_of(st.sampled_from(_EDGE), st.floats(allow_nan=True), st.integers(-2 ** 70, 2 ** 70), st.none(),
                   st.booleans(), st.text(max_size=3),
                   st.lists(st.one_of(st.floats(allow_nan=True), st.integers(), st.none()), max_size=3))
_FIELDS = ("name", "shape", "position", "radius", "mass", "fixed", "velocity", "acceleration", "angle",
           "angular_velocity", "restitution", "friction", "comment", "orbit", "vertices", "x")
_PLAIN = ({"shape": "circle", "position": [0.25, 0.5], "radius": 0.5, "mass": 2.0, "velocity": [1.0, -1.0]},
          {"shape": "circle", "position": [0.25, 0.5], "radius": 0.5, "fixed": True, "name": "w"})


def _fast_agrees(raw, k=0, gravity=(0.0, -9.81)) -> bool:
    """scene._circle (the one-pass reading of a plain circle) accepts only
    what scene._body accepts, with the same values; anything else it leaves
    to _body (and so every error message).  True when the fast path took it."""
    from max2code.sim.scene import _body, _circle, _Reader
    names = {"body3": 9}
    fast = _circle(dict(raw), k, gravity, dict(names))
    try:
        careful = _body(_Reader("b.json"), dict(raw), k, gravity, dict(names))
    except (SceneError, TypeError, OverflowError):      # the last two: left to _body as they always were
        careful = None
    if fast is not None:
        assert careful == fast, raw
    return fast is not None


def test_fast_circle_reading_agrees_field_by_field():
    """Every field of a plain movable and a plain fixed circle removed, or
    set to each edge value."""
    taken = 0
    for base in _PLAIN:
        taken += _fast_agrees(base)
        for key in _FIELDS:
            taken += _fast_agrees({k: v for k, v in base.items() if k != key})
            for value in _EDGE:
                taken += _fast_agrees(dict(base, **{key: value}))
    assert taken > 20          # the fast path is taken, not only skipped


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(_PLAIN), st.lists(st.tuples(st.sampled_from(_FIELDS), st.booleans(), _field), max_size=3),
       st.integers(0, 5), st.sampled_from([(0.0, 0.0), (0.0, -9.81)]))
def test_fast_circle_reading_agrees_with_the_careful_one(base, changes, k, gravity):
    """The same with up to three fields changed at once."""
    raw = dict(base)
    for key, drop, value in changes:
        if drop:
            raw.pop(key, None)
        else:
            raw[key] = value
    _fast_agrees(raw, k, gravity)


def test_whole_scene_columns_agree_with_each_body():
    """scene.turning, circle_lever and make_grid read fields of all bodies
    at once; the same as asking each body, on every example and on crowds
    with a spinning orbit added."""
    import max2code.sim.scene as sc
    scenes = [load_scene(p) for p in EXAMPLES]
    for seed in range(20):
        raw = _crowd(seed)
        if seed % 2:
            raw["bodies"].append({"name": "spinner", "shape": "circle", "radius": 0.01, "fixed": True,
                                  "position": [50.0, 50.0], "orbit": {"radius": 0.5}, "angular_velocity": 1.0})
        try:
            scenes.append(parse_scene(json.dumps(raw), "crowd.json", check=False))
        except SceneError:
            pass
    assert len(scenes) > 20
    for scene in scenes:
        bodies = scene.bodies
        assert sc.turning(bodies) == [b for b in bodies if b.may_turn]
        assert sc.circle_lever(scene) == max((b.radius for b in bodies if not b.polygon and not b.turns), default=0.0)
        size = 2.0 * max((b.bound for b in bodies if not b.fixed), default=1.0) * (1.0 + 1e-6)
        assert sc.make_grid(scene).large == tuple(b.bound * 2.0 > size for b in bodies)
        assert scene.effects == tuple(e for e, on in (("acceleration", any(b.acceleration != (0.0, 0.0) for b in bodies)),
                                                      ("orbit", any(b.may_turn for b in bodies))) if on)


_json_value = st.recursive(
    st.none() | st.booleans() | st.floats(allow_nan=True) | st.integers(-10 ** 40, 10 ** 40) | st.text(max_size=4)
    | st.sampled_from([10 ** 19, 2 ** 64, -(2 ** 64) - 1, 10 ** 25 + 1, 0.1 ** 22, 123456789.123456789e-30]),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.sampled_from("abc"), inner, max_size=3),
    max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(_json_value, st.sampled_from([" ", "\n", ""]), st.booleans())
def test_big_scenes_decode_as_json_does(value, space, cut):
    """scene._decode (orjson for a big scene, when installed) gives what
    json.loads gives, whole numbers beyond 64 bits, NaN and Infinity
    included, and the same error on a text cut short."""
    import max2code.sim.scene as sc
    text = json.dumps(value, indent=1 if space == "\n" else None).replace(" ", space or " ")
    text = text[:len(text) // 2] if cut else text
    try:
        want = repr(json.loads(text))
    except json.JSONDecodeError as exc:
        want = repr(exc)
    old = sc.FAST_JSON_BYTES
    sc.FAST_JSON_BYTES = 0
    try:
        try:
            got = repr(sc._decode(text))
        except json.JSONDecodeError as exc:
            got = repr(exc)
    finally:
        sc.FAST_JSON_BYTES = old
    assert got == want


def _crowd(seed: int) -> dict:
    """Circles of mixed sizes (some fixed) crowded into a small box with a
    wall or two: overlapping pairs, touching pairs, big bodies, empty rows."""
    import random
    rng = random.Random(seed)
    side = rng.choice([0.5, 2.0, 8.0])
    bodies = []
    for k in range(rng.randint(2, 60)):
        b = {"name": f"c{k}", "shape": "circle", "radius": rng.choice([0.02, 0.05, 0.1, 0.3]),
             "position": [rng.uniform(-side, side), rng.uniform(-side, side) * rng.choice([1.0, 0.01])]}
        if rng.random() < 0.2:
            b["fixed"] = True
        else:
            b["mass"] = 1.0
        bodies.append(b)
    for k in range(rng.randint(0, 2)):
        w, h = rng.uniform(0.01, side), rng.uniform(0.01, 0.1)
        bodies.append({"name": f"w{k}", "shape": "polygon", "fixed": True,
                       "position": [rng.uniform(-side, side), rng.uniform(-side, side)],
                       "vertices": [[-w, -h], [w, -h], [w, h], [-w, h]]})
    rng.shuffle(bodies)
    return {"end_time": 1.0, "tolerance": rng.choice([1e-9, 1e-3]), "bodies": bodies}


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_overlap_check_finds_the_first_pair_of_all(seed):
    """The grid's overlap check reports the first pair (in index order) that
    a test of every pair finds, or none when every pair finds none."""
    import max2code.sim.scene as sc
    check = sc._check_overlaps
    sc._check_overlaps = lambda scene: None
    try:
        scene = parse_scene(json.dumps(_crowd(seed)), "crowd.json")
    finally:
        sc._check_overlaps = check
    tol, bodies = scene.tolerance, scene.bodies
    pairs = [(i, j) for i in range(len(bodies)) for j in range(i + 1, len(bodies))
             if not (bodies[i].fixed and bodies[j].fixed) and sc.penetration(bodies[i], bodies[j]) > tol]
    try:
        check(scene)
        got = None
    except SceneError as exc:
        got = str(exc)
    if not pairs:
        assert got is None
    else:
        i, j = min(pairs)
        assert got is not None and f"bodies[{i}] ({bodies[i].name}) and bodies[{j}] ({bodies[j].name}) overlap" in got


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_random_scenes_compile(seed):
    """Random valid scenes parse, or are refused only for an overlap; the
    compiled text round-trips every number exactly."""
    try:
        scene = parse_scene(json.dumps(random_scene(seed)), "r.json")
    except SceneError as exc:
        assert "overlap at t = 0" in str(exc)
        return
    flat = compile_scene(scene).split()
    nums = [w for w in flat if w[0].isdigit() or w[0] == "-"]
    assert all(repr(float(w)) == w for w in nums if "." in w or "e" in w)


def _run(path_or_scene, lang="python"):
    scene = load_scene(path_or_scene) if isinstance(path_or_scene, str) else path_or_scene
    return scene, run_scene(scene, lang)


def test_newtons_cradle_passes_the_momentum_through():
    scene, tr = _run(os.path.join(ROOT, "examples", "newtons-cradle.json"))
    hits = [e for e in tr.events if e["kind"] == "collision"]
    # the striker's momentum runs through the row at one instant: five
    # zero-time collisions, then the last ball flies off alone
    first = [e for e in hits if e["t"] == hits[0]["t"]]
    assert [e["bodies"] for e in first] == [["striker", "ball0"], ["ball0", "ball1"], ["ball1", "ball2"],
                                           ["ball2", "ball3"], ["ball3", "ball4"]]
    final = {b["body"]: b for b in tr.final["bodies"]}
    moving = [n for n, b in final.items() if abs(b["velocity"][0]) > 0.5]
    assert len(moving) == 1
    assert max(len([e for e in hits if e["t"] == t]) for t in {e["t"] for e in hits}) <= 5


def test_resting_ball_comes_to_rest():
    """Restitution 0.5: a few bounces, time always advancing, then the ball
    is supported by the floor (docs/simulator.md, Contact model) and stays."""
    scene, tr = _run(os.path.join(ROOT, "examples", "resting-ball.json"))
    hits = [e for e in tr.events if e["kind"] in ("collision", "support")]
    times = [e["t"] for e in hits]
    assert times == sorted(times) and len(set(times)) == len(times)     # time always advances
    assert [e["kind"] for e in hits][-1] == "support" and len(hits) < 12
    ball = next(b for b in tr.final["bodies"] if b["body"] == "ball")
    assert abs(ball["position"][1] - 0.1) <= scene.tolerance and ball["velocity"][1] == 0.0


def test_two_runs_give_identical_traces():
    path = os.path.join(ROOT, "examples", "spinning-polygons.json")
    _, a = _run(path)
    _, b = _run(path)
    assert a.raw == b.raw and a.raw


@pytest.mark.parametrize("gravity", [True, False], ids=["gravity", "no-gravity"])
def test_invariants_at_every_event(gravity):
    """Restitution 1, circles and spinning polygons: at every collision and
    every frame, no overlap beyond the tolerance and energy conserved."""
    raw = random_scene(3, gravity=gravity, spin=True, restitution_one=True, bodies=9, end_time=3.0)
    raw["frame_rate"] = 200
    raw.pop("inputs", None)      # an input adds energy: keep the system closed
    scene = parse_scene(json.dumps(raw), "long.json")
    tr = run_scene(scene, "python")
    rp = read_trace("\n".join(tr.lines()), scene, "long.json")
    rep = check(scene, rp, kinds=("collision", "input", "frame"))
    assert rep.events >= 600
    assert rep.max_overlap <= scene.tolerance, rep
    assert rep.max_energy_drift <= 1e-9, rep


@pytest.mark.slow
def test_only_the_effects_a_scene_uses():
    """No rotation: the generated code has no orbiting variant, and every
    prediction is served by a variant of degree 2 or less."""
    scene, tr = _run(os.path.join(ROOT, "examples", "gravity-box.json"))
    assert scene.effects == ("acceleration",)
    from max2code.sim.simulate import build_simulator
    b = build_simulator("python", scene.effects, scene.taylor_order)
    names = [n for v in b.variant_names.values() for n in v]
    assert all("no_orbit1" in n or n.startswith("point_edge") for n in names)
    assert all("no_orbit2" in n for n in names if n.startswith("circle_circle"))
    used = tr.stats["predictions"]
    assert used and all(n in names for n in used)
    # a scene with polygons that may turn gets the orbit effect
    spin = load_scene(os.path.join(ROOT, "examples", "spinning-polygons.json"))
    assert "orbit" in spin.effects


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_examples_replay_to_their_final_state(path):
    scene, tr = _run(path)
    rp = read_trace("\n".join(tr.lines()), scene, path)
    err, who = rp.final_error()
    assert err <= 1e-9, (err, who)
    assert math.isfinite(sum(b["position"][0] for b in tr.final["bodies"]))


@pytest.mark.slow      # `max2code simulate` runs the C simulator (its default), built on first use
def test_the_command_process_writes_everything_before_its_quick_exit(tmp_path):
    """`python -m max2code simulate` ends with os._exit after flushing (cli.run, QUICK_EXIT): the trace on
    standard output through a pipe is the whole of what -o FILE holds, the summary reaches standard error, and
    the exit statuses are main()'s."""
    ex = os.path.join(ROOT, "examples", "billiard-break.json")
    cmd = [sys.executable, "-m", "max2code", "simulate", ex]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}     # the streams buffered, as usual
    piped = subprocess.run(cmd, capture_output=True, cwd=ROOT, env=env)
    to_file = subprocess.run([*cmd, "-o", str(tmp_path / "t.jsonl"), "-q"], capture_output=True, cwd=ROOT, env=env)
    assert piped.returncode == 0 and to_file.returncode == 0, piped.stderr + to_file.stderr
    assert piped.stdout == (tmp_path / "t.jsonl").read_bytes()
    assert piped.stdout.endswith(b"\n") and b'"kind":"stats"' in piped.stdout.splitlines()[-1]
    assert piped.stderr.decode().startswith("max2code simulate: ") and to_file.stderr == b""
    missing = subprocess.run([*cmd[:-1], str(tmp_path / "none.json")], capture_output=True, text=True, cwd=ROOT,
                             env=env)
    assert missing.returncode == 1 and "Traceback" not in missing.stderr and "none.json" in missing.stderr


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10**6))
def test_grid_cells_leave_room_for_the_margin(seed):
    """Bodies in cells that are not neighbours cannot touch while each moving
    centre is at most the margin outside its cell: every small movable body
    fits a cell with a margin on both sides, and the margin is what the
    cell factor leaves (docs/simulator.md, "Hysteresis")."""
    try:
        scene = parse_scene(json.dumps(random_scene(seed)), "r.json")
    except SceneError:
        return
    from max2code.sim.scene import CELL_FACTOR, make_grid
    g = make_grid(scene)
    cell = min(g.cw, g.ch)
    assert 0.0 <= g.margin < cell / 2
    small = [b for b, large in zip(scene.bodies, g.large) if not large]
    for b in small:
        assert 2.0 * b.bound + 2.0 * g.margin <= cell
    if any(not b.fixed for b in small):
        widest = max(2.0 * b.bound for b in small if not b.fixed)
        assert g.margin >= 0.5 * (CELL_FACTOR - 1.0) * widest * (1 - 1e-9)


def _thrown_up(apex_past_edge: float):
    """A ball thrown straight up under gravity whose apex is `apex_past_edge`
    margins past the upper edge of its cell (a fixed ball far off gives the
    grid its extent); the end is when it is back where it started."""
    from max2code.sim.scene import make_grid
    raw = {"name": "thrown up", "end_time": 1.0, "gravity": [0.0, -9.81], "bodies": [
        {"name": "ball", "shape": "circle", "radius": 0.01, "mass": 1.0, "position": [0.0, 0.0]},
        {"name": "post", "shape": "circle", "radius": 0.01, "fixed": True, "position": [1.0, 1.0]}]}
    g = make_grid(parse_scene(json.dumps(raw), "up.json"))
    assert g.margin > 0.0
    edge = g.y0 + (math.floor((0.0 - g.y0) / g.ch) + 1) * g.ch
    rise = edge + apex_past_edge * g.margin
    vy = math.sqrt(2.0 * 9.81 * rise)
    raw["bodies"][0]["velocity"] = [0.0, vy]
    raw["end_time"] = 2.0 * vy / 9.81 * (1 - 1e-9)
    return parse_scene(json.dumps(raw), "up.json")


@pytest.mark.parametrize("lang", ["python", "c", "rust", "m2"])
def test_a_body_that_turns_within_the_margin_keeps_its_cell(lang):
    """Hysteresis: a centre changes cell only a margin past the edge, so a
    ball whose apex is half a margin past its cell's upper edge never
    changes cell, and one whose apex is 1.5 margins past it changes cell
    going up and again coming down."""
    assert run_scene(_thrown_up(0.5), lang).stats["events"]["cells"] == 0
    assert run_scene(_thrown_up(1.5), lang).stats["events"]["cells"] == 2


def _simulate_cmd(scene="billiard-break.json"):
    env = {k: v for k, v in os.environ.items() if k != "MAX2CODE_DEBUG"}
    return [sys.executable, "-m", "max2code", "simulate", os.path.join(ROOT, "examples", scene), "-q"], env


@pytest.mark.slow      # `max2code simulate` runs the C simulator (its default), built on first use
def test_an_output_that_cannot_be_written_is_one_plain_error():
    """Standard output on a full disk (/dev/full): one line saying that the
    output could not be written and the OS's reason, exit 1, no traceback."""
    cmd, env = _simulate_cmd()
    with open("/dev/full", "wb") as full:
        r = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=full, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                           env=env)
    assert r.returncode == 1, r.stderr
    assert r.stderr == "standard output: error: cannot write: No space left on device\n", r.stderr


@pytest.mark.slow
def test_a_closed_pipe_ends_the_command_quietly():
    """The reader of standard output gone before the trace is written (`| head -c 10`): no message, the exit
    status a shell shows for a Unix tool ended by SIGPIPE (128 + 13)."""
    cmd, env = _simulate_cmd("ball-pit.json")
    rd, wr = os.pipe()
    os.close(rd)
    try:
        r = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=wr, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                           env=env)
    finally:
        os.close(wr)
    assert (r.returncode, r.stderr) == (141, "")


@pytest.mark.slow      # `max2code simulate` runs the C simulator (its default), built on first use
def test_a_named_pipe_as_the_output_is_written_not_replaced(tmp_path):
    """-o on a device or a named pipe writes into it: a file renamed over it would replace it (as root even
    /dev/null), and its reader would get nothing."""
    import select
    import stat
    import time
    cmd, env = _simulate_cmd()
    want = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, cwd=ROOT, env=env, check=True).stdout
    fifo = tmp_path / "trace.fifo"
    os.mkfifo(fifo)
    rd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    got = bytearray()
    try:
        proc = subprocess.Popen([*cmd, "-o", str(fifo)], stdin=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=ROOT,
                                env=env)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            select.select([rd], [], [], 0.1)
            try:
                chunk = os.read(rd, 1 << 16)
            except BlockingIOError:
                continue
            got += chunk
            if not chunk:
                if proc.poll() is not None:
                    break
                time.sleep(0.01)        # no writer yet (or between writes)
        _, err = proc.communicate(timeout=60)
    finally:
        os.close(rd)
    assert proc.returncode == 0, err
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert bytes(got) == want
