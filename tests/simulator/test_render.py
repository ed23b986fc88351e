"""`max2code render` and the replay under it (max2code/sim/replay.py,
max2code/draw/render.py): the replay is exact (the final states of every
example scene simulated in Python, bit for bit in practice, 1e-9 asserted),
the contact points of the trace lie on the replayed bodies, the animated SVG
is well-formed and animates what moves where the replay says, the overview
and the GIF are written, and bad input is one clean line."""
import json
import math
import os
import re
import xml.etree.ElementTree as ET

import pytest

from conftest import ROOT
from max2code.cli import main
from max2code.draw.render import animated_svg, have_pillow, sample_times
from max2code.sim.replay import TraceError, advance, load_trace, read_trace
from max2code.sim.scene import load_scene
from max2code.sim.simulate import run_scene

SVG = "{http://www.w3.org/2000/svg}"
# gravity-box simulated to its end takes ~20 s in Python (30 000 collisions while the balls settle): its first
# 1.5 s (~1500 collisions) keeps the suite fast; the others run to their end_time.
EXAMPLES = {"billiard-break": None, "gravity-box": 1.5, "spinning-polygons": None, "newtons-cradle": None,
            "resting-ball": None}
# a fixed circle orbiting the origin knocks a ball away (the orbit geometry: position + R (cos, sin)(angle + a))
ORBIT = {"name": "orbit", "end_time": 2.0, "frame_rate": 20, "bodies": [
    {"name": "arm", "shape": "circle", "radius": 0.1, "fixed": True, "position": [0.0, 0.0],
     "orbit": {"radius": 0.4, "angle": 0.5}, "angular_velocity": 2.0},
    {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [-0.9, 0.3], "velocity": [1.0, 0.0]},
    {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -1.1],
     "vertices": [[-1.5, -0.1], [1.5, -0.1], [1.5, 0.1], [-1.5, 0.1]]}]}


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """name -> (scene path, trace path), each scene simulated once in Python."""
    d = tmp_path_factory.mktemp("render")
    cache = {}

    def get(name):
        if name not in cache:
            if name == "orbit":
                raw = ORBIT
            else:
                with open(os.path.join(ROOT, "examples", name + ".json"), encoding="utf-8") as f:
                    raw = json.load(f)
                if EXAMPLES[name] is not None:
                    raw["end_time"] = EXAMPLES[name]
            scene_path = str(d / f"{name}.json")
            with open(scene_path, "w", encoding="utf-8") as f:
                json.dump(raw, f)
            trace = run_scene(load_scene(scene_path), "python")
            trace_path = str(d / f"{name}.jsonl")
            with open(trace_path, "w", encoding="utf-8") as f:
                f.write("\n".join(trace.lines()) + "\n")
            cache[name] = (scene_path, trace_path)
        return cache[name]

    return get


def _replay(simulated, name):
    scene_path, trace_path = simulated(name)
    scene = load_scene(scene_path)
    return scene, load_trace(trace_path, scene, tolerance=None)


# ---------------------------------------------------------------- replay
@pytest.mark.parametrize("name", list(EXAMPLES) + ["orbit"])
def test_replay_reproduces_the_final_states(simulated, name):
    scene, rp = _replay(simulated, name)
    assert rp.final is not None and len(rp.final) == len(scene.bodies)
    for k, f in rp.final.items():
        s = rp.state_at(k, scene.end_time)
        who = scene.bodies[k].name
        for got, want in ((s.px, f.px), (s.py, f.py), (s.vx, f.vx), (s.vy, f.vy), (s.angle, f.angle)):
            assert abs(got - want) <= 1e-9, (who, got, want)
        assert s.omega == f.omega, who
    assert rp.final_error()[0] <= 1e-9


@pytest.mark.parametrize("name", list(EXAMPLES) + ["orbit"])
def test_positions_are_continuous_across_every_state_change(simulated, name):
    """A collision or input changes velocities, never positions: each new
    state starts where the previous one, carried forward, arrives."""
    scene, rp = _replay(simulated, name)
    changes = 0
    for k, b in enumerate(scene.bodies):
        for prev, new in zip(rp.states[k], rp.states[k][1:]):
            p = advance(prev, b, new.t)
            assert math.hypot(p.px - new.px, p.py - new.py) <= 1e-9 * max(1.0, abs(new.px), abs(new.py)), b.name
            assert abs(p.angle - new.angle) <= 1e-9 * max(1.0, abs(new.angle)), b.name
            changes += 1
    assert changes >= len(rp.collisions)      # each collision changes at least one movable body


@pytest.mark.parametrize("name", list(EXAMPLES) + ["orbit"])
def test_contact_points_lie_on_both_replayed_bodies(simulated, name):
    scene, rp = _replay(simulated, name)
    assert rp.collisions
    for e in rp.collisions:
        a, b = e.bodies
        shape_a, shape_b = rp.shape_at(a, e.t), rp.shape_at(b, e.t)
        px, py = e.point
        if e.feature in ("circle-circle", "circle-vertex", "circle-edge"):
            (cx, cy), r = shape_a[1], shape_a[2]
            assert abs(math.hypot(px - cx, py - cy) - r) <= 1e-6, (e.line, e.feature)
        if e.feature == "circle-circle":
            (cx, cy), r = shape_b[1], shape_b[2]
            assert abs(math.hypot(px - cx, py - cy) - r) <= 1e-6, (e.line, e.feature)
        else:
            # on polygon B: a vertex of it (circle-vertex) or on the line of an edge (circle-edge, vertex-edge)
            pts = shape_b[1]
            n = len(pts)
            gaps = []
            for k in range(n):
                (x0, y0), (x1, y1) = pts[k], pts[(k + 1) % n]
                ln = math.hypot(x1 - x0, y1 - y0)
                gaps.append(abs((px - x0) * (y1 - y0) - (py - y0) * (x1 - x0)) / ln)
            assert min(gaps) <= 1e-6, (e.line, e.feature, min(gaps))


def test_orbiting_circle_is_drawn_where_the_scene_says(simulated):
    scene, rp = _replay(simulated, "orbit")
    for t in (0.0, 0.3, 1.7):
        kind, (x, y), r = rp.shape_at("arm", t)
        a = 2.0 * t + 0.5
        assert kind == "circle" and r == 0.1
        assert math.hypot(x - 0.4 * math.cos(a), y - 0.4 * math.sin(a)) <= 1e-12


def test_state_at_between_and_at_changes(simulated):
    scene, rp = _replay(simulated, "billiard-break")
    k = rp.body_index("ball1")
    times, states = rp.times[k], rp.states[k]
    # several changes at one instant (ball1 hits ball2 and ball3 together): a query there sees the last
    same = [i for i in range(1, len(times)) if times[i] == times[i - 1]]
    assert same
    i = same[0]
    assert rp.state_at(k, times[i]) == states[max(j for j in range(len(times)) if times[j] == times[i])]
    # between two changes: the exact motion from the earlier one
    t0, t1 = times[1], next(t for t in times if t > times[1])
    mid = 0.5 * (t0 + t1)
    s = rp.state_at("ball1", mid)
    base = rp.segment(k, t0)
    b = scene.bodies[k]
    dt = mid - base.t
    assert s.px == base.px + (base.vx + 0.5 * b.acceleration[0] * dt) * dt
    assert s.vy == base.vy + b.acceleration[1] * dt


# ---------------------------------------------------------------- pictures
def _moving(rp):
    out = []
    for k, b in enumerate(rp.scene.bodies):
        s = rp.states[k][0]
        turns = s.omega != 0.0 and (b.polygon or b.orbit_radius > 0.0)
        if len(rp.states[k]) > 1 or s.vx or s.vy or b.acceleration != (0.0, 0.0) or turns:
            out.append(k)
    return out


@pytest.mark.parametrize("name", list(EXAMPLES) + ["orbit"])
def test_animated_svg_animates_every_moving_body_where_the_replay_has_it(simulated, name):
    scene, rp = _replay(simulated, name)
    times = sample_times(rp)
    assert len(times) == 1 + len(rp.frame_times) + (rp.frame_times[-1] < scene.end_time)
    root = ET.fromstring(animated_svg(rp, times))
    assert root.tag == SVG + "svg"
    shapes = root.findall(f".//{SVG}polygon[@class='body']") + root.findall(f".//{SVG}circle[@class='body']")
    assert len(shapes) == len(scene.bodies)
    moves = root.findall(f".//{SVG}animateTransform[@type='translate']")
    moving = _moving(rp)
    assert len(moves) == len(moving)
    turning = [k for k in moving if (scene.bodies[k].polygon or scene.bodies[k].orbit_radius > 0)
               and len({round(math.degrees(rp.state_at(k, t).angle), 2) for t in times}) > 1]
    assert len(root.findall(f".//{SVG}animateTransform[@type='rotate']")) == len(turning)
    size = max(scene.bodies[k].bound for k in range(len(scene.bodies)))
    for k, anim in zip(sorted(moving, key=lambda k: k), moves):
        values = [tuple(map(float, v.split())) for v in anim.get("values").split(";")]
        keys = [float(x) for x in anim.get("keyTimes").split(";")]
        assert len(values) == len(keys) >= 2 and keys[0] == 0.0 and keys[-1] == 1.0
        assert all(x <= y for x, y in zip(keys, keys[1:]))
        for kt, (x, y) in zip(keys, values):
            s = rp.state_at(k, kt * scene.end_time)
            assert math.hypot(x - s.px, y - s.py) <= 2e-4 * max(1.0, size), (scene.bodies[k].name, kt)
    flashes = root.findall(f".//{SVG}g[@id='collisions']/{SVG}circle")
    assert len(flashes) == min(len(rp.collisions), 2000)


def test_render_command_writes_svg_overview_gif_and_frames(simulated, tmp_path, capsys):
    pytest.importorskip("PIL")
    scene_path, trace_path = simulated("newtons-cradle")
    out = tmp_path / "pics" / "cradle"
    rc = main(["render", scene_path, trace_path, "-o", str(out), "--gif", "--png-frames", "--gif-fps", "5",
               "--gif-width", "320"])
    assert rc == 0
    err = capsys.readouterr().err
    assert "wrote" in err and "cradle.svg (181 key frames" in err
    ET.parse(str(out) + ".svg")
    ET.parse(str(out) + "-overview.svg")
    with open(str(out) + "-overview.png", "rb") as f:
        png = f.read()
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and len(png) > 10000
    from PIL import Image
    with Image.open(str(out) + ".gif") as gif:
        assert gif.n_frames == 16 and gif.size[0] == 320          # 0, 0.2, ..., 3.0 s
    frames = sorted(os.listdir(str(out) + "-frames"))
    assert len(frames) == 16 and frames[0] == "frame-00000.png"


def test_overview_coloured_by_time_and_fps_without_frame_events(simulated, tmp_path):
    scene_path, trace_path = simulated("resting-ball")
    with open(trace_path, encoding="utf-8") as f:
        lines = [ln for ln in f if '"kind":"frame"' not in ln]
    bare = tmp_path / "no-frames.jsonl"
    bare.write_text("".join(lines), encoding="utf-8")
    scene = load_scene(scene_path)
    rp = load_trace(str(bare), scene)
    assert rp.frame_times == []
    assert len(sample_times(rp)) == 1 + 30 * 5            # the scene's frame_rate
    assert len(sample_times(rp, 8.0)) == 1 + 8 * 5
    rc = main(["render", scene_path, str(bare), "-o", str(tmp_path), "--fps", "8", "--colour-by", "time", "-q"])
    assert rc == 0
    assert (tmp_path / "no-frames-overview.png").stat().st_size > 10000
    root = ET.parse(str(tmp_path / "no-frames.svg")).getroot()
    anim = root.find(f".//{SVG}animateTransform[@type='translate']")
    assert len(anim.get("keyTimes").split(";")) <= 41


def test_without_pillow_the_gif_is_skipped_with_a_message(simulated, tmp_path, capsys, monkeypatch):
    import max2code.draw.render as rt
    monkeypatch.setattr(rt, "have_pillow", lambda: False)
    scene_path, trace_path = simulated("newtons-cradle")
    assert main(["render", scene_path, trace_path, "-o", str(tmp_path / "x"), "--gif", "--no-overview"]) == 0
    assert "need Pillow" in capsys.readouterr().err
    assert (tmp_path / "x.svg").exists() and not (tmp_path / "x.gif").exists()
    assert have_pillow() in (True, False)


# ---------------------------------------------------------------- errors
def _error(capsys, argv) -> str:
    rc = main(["render"] + argv)
    err = capsys.readouterr().err
    assert rc == 1, err
    assert "Traceback" not in err and "internal error" not in err
    assert len(err.strip().splitlines()) == 1, err
    return err


def test_missing_files_are_one_line_errors(simulated, tmp_path, capsys):
    scene_path, trace_path = simulated("newtons-cradle")
    missing = str(tmp_path / "nope.jsonl")
    assert missing in _error(capsys, [scene_path, missing, "-o", str(tmp_path / "o")])
    assert "nope.json" in _error(capsys, [str(tmp_path / "nope.json"), trace_path, "-o", str(tmp_path / "o")])


def test_a_trace_of_another_scene_is_refused(simulated, tmp_path, capsys):
    cradle_scene, cradle_trace = simulated("newtons-cradle")
    billiard_scene, billiard_trace = simulated("billiard-break")
    err = _error(capsys, [cradle_scene, billiard_trace, "-o", str(tmp_path / "o")])
    assert billiard_trace in err and "is not in" in err and "another scene" in err
    # a scene file given as the trace: the example (indented JSON) and the one-line copy
    example = os.path.join(ROOT, "examples", "newtons-cradle.json")
    err = _error(capsys, [cradle_scene, example, "-o", str(tmp_path / "o")])
    assert example + ":1: error: not a JSON trace line" in err
    err = _error(capsys, [cradle_scene, cradle_scene, "-o", str(tmp_path / "o")])
    assert cradle_scene + ":1: error: this is a scene, not a trace" in err
    # same names, but the ceiling (never in a collision) sits elsewhere: the final states differ
    with open(cradle_scene, encoding="utf-8") as f:
        raw = json.load(f)
    raw["bodies"][1]["position"][1] += 0.01
    moved = tmp_path / "moved.json"
    moved.write_text(json.dumps(raw), encoding="utf-8")
    err = _error(capsys, [str(moved), cradle_trace, "-o", str(tmp_path / "o")])
    assert cradle_trace + ": error: does not match" in err and "ceiling ends at" in err
    # the striker starts elsewhere: its first collision puts it where the replay is not
    raw["bodies"][1]["position"][1] -= 0.01
    raw["bodies"][4]["position"][0] -= 0.01
    moved.write_text(json.dumps(raw), encoding="utf-8")
    err = _error(capsys, [str(moved), cradle_trace, "-o", str(tmp_path / "o")])
    assert re.search(re.escape(cradle_trace) + r":\d+: error: does not match", err) and "striker is at" in err


@pytest.mark.parametrize("line, message", [
    ('{"t":0.1,"kind":"collision","bodies":["striker","wall"],"point":[0,0],"normal":[1,0],"impulse":1}',
     "body \"wall\" is not in"),
    ('{"t":0.1,"kind":"teleport"}', "unknown kind"),
    ('{"t":9.0,"kind":"frame"}', "after the end_time"),
    ('{"t":0.1,"kind":"input","bodies":["floor"],"states":[{"body":"floor","position":[0,0],"velocity":[1,0],'
     '"angle":0,"angular_velocity":0}]}', "which is fixed"),
    ('{"t":0.1,"kind":"input","bodies":["striker"],"states":[{"body":"striker","position":[0,"x"],'
     '"velocity":[1,0],"angle":0,"angular_velocity":0}]}', "expected [x, y] for 'position'"),
    ('[1, 2]', "expected an object with a 'kind'"),
    ('', "empty trace"),
])
def test_bad_trace_lines_name_the_file_and_line(simulated, line, message):
    scene = load_scene(simulated("newtons-cradle")[0])
    with pytest.raises(TraceError) as exc:
        read_trace(line + "\n", scene, "bad.jsonl")
    assert str(exc.value).startswith("bad.jsonl") and message in str(exc.value)
    if line:
        assert str(exc.value).startswith("bad.jsonl:1: ")
