"""Hostile input on the Python side of the engine: JSON scenes that are
valid JSON but not a scene a double can simulate (a polygon that winds
twice, sizes below the tolerance, too many bodies, brackets nested a
million deep, a teleport beyond the doubles' safe range), titles that
matplotlib would read as mathematics, `simulate -o` stopped by a signal,
and the C world's binding (worlds dropped without close(), integers out of
the C parameters' range, inputs after finish() or with a result that is
not finite).  Each fault is one line `FILE: error: WHERE: WHAT` or a clear
SimError, never a crash, a leak or a silently wrong run."""
import gc
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from max2code.cli import main
from max2code.sim import scene as sc
from max2code.sim.scene import SceneError, load_scene, parse_scene


def run(capsys, *argv):
    code = main(list(map(str, argv)))
    out, err = capsys.readouterr()
    return code, out, err


def write(tmp_path, name, data):
    p = tmp_path / name
    p.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return p


def refused(text, path="s.json") -> str:
    """parse_scene's one line for a scene it must refuse."""
    with pytest.raises(SceneError) as exc:
        parse_scene(text if isinstance(text, str) else json.dumps(text), path)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(f"{path}: error: "), msg
    return msg[len(f"{path}: error: "):]


def ball(name="a", **kw):
    b = {"name": name, "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}
    b.update(kw)
    return b


def ngon(n, r=1.0, step=1):
    """A regular n-gon of radius r, vertex k at k * step turns of 2 pi / n (step 2 of 5: a pentagram)."""
    return [[r * math.cos(math.pi / 2 + 2 * math.pi * step * k / n), r * math.sin(math.pi / 2 + 2 * math.pi * step * k / n)]
            for k in range(n)]


# ------------------------------------------------------------------ polygons that wind more than once
def test_a_pentagram_is_not_convex_though_every_turn_is_left():
    star = {"end_time": 1, "bodies": [{"shape": "polygon", "mass": 1, "position": [0, 0], "vertices": ngon(5, step=2)}]}
    assert refused(star) == ("bodies[0] (body0).vertices: the polygon is not convex: its edges wind 2 times around it "
                             "(it crosses itself)")
    # seven points, every third: winds three times
    assert "wind 3 times" in refused({"end_time": 1, "bodies": [
        {"shape": "polygon", "fixed": True, "position": [0, 0], "vertices": ngon(7, step=3)}]})
    # the convex ones, either winding, pass
    for pts in (ngon(5), ngon(5)[::-1], ngon(1024), [[0, 0], [1, 0], [0, 1]]):
        s = parse_scene(json.dumps({"end_time": 1, "bodies": [{"shape": "polygon", "mass": 1, "position": [0, 0],
                                                               "vertices": pts}]}))
        assert len(s.bodies[0].vertices) == len(pts)


def test_a_fixed_pentagram_is_refused_by_simulate_too(tmp_path, capsys):
    """A fixed polygon is the C reader's case (scene_c.py): it hands the fault to Python."""
    p = write(tmp_path, "star.json", {"end_time": 1, "bodies": [
        {"name": "star", "shape": "polygon", "fixed": True, "position": [0, 0], "vertices": ngon(5, step=2)},
        ball(position=[5.0, 0.0])]})
    code, out, err = run(capsys, "simulate", p)
    assert code == 1 and out == ""
    assert err.startswith(f"{p}: error: bodies[0] (star).vertices: the polygon is not convex")


# ------------------------------------------------------------------ sizes below the tolerance
def test_sizes_below_the_tolerance_are_refused_naming_the_field_and_both_values():
    tiny = {"end_time": 1, "bodies": [ball(radius=1e-12), ball("b", radius=1e-12, position=[1e-11, 0])]}
    assert refused(tiny) == ("bodies[0] (a).radius: 1e-12 m is less than the tolerance (1e-09 m), within which "
                             "contacts are found; scale the scene or lower the tolerance")
    # the same scene with a tolerance below its sizes is simulated
    assert parse_scene(json.dumps({**tiny, "tolerance": 1e-13})).bodies[0].radius == 1e-12
    arm = {"end_time": 1, "bodies": [{"name": "arm", "shape": "circle", "radius": 0.1, "fixed": True,
                                      "position": [0, 0], "orbit": {"radius": 1e-10}}]}
    assert refused(arm).startswith("bodies[0] (arm).orbit.radius: 1e-10 m is less than the tolerance (1e-09 m)")
    sliver = {"end_time": 1, "bodies": [{"name": "p", "shape": "polygon", "mass": 1, "position": [0, 0],
                                         "vertices": [[0, 0], [1, 0], [1, 4e-10], [0, 1]]}]}
    assert refused(sliver).startswith("bodies[0] (p).vertices: the edge from vertex ")
    assert "is 4e-10 m long, less than the tolerance (1e-09 m)" in refused(sliver)


@pytest.mark.parametrize("lang", ["c", "python"])
def test_simulate_refuses_a_radius_below_the_tolerance(tmp_path, capsys, lang):
    """Two circles of 1e-12 m with the default 1e-9 m tolerance: refused before
    any run (the C reader's case as well as Python's), not a collision at
    t = 0.25 s with the bodies 2.5e-12 m apart."""
    p = write(tmp_path, "tiny.json", {"end_time": 1, "bodies": [
        ball(radius=1e-12, velocity=[1e-11, 0]), ball("b", radius=1e-12, position=[1e-11, 0])]})
    code, out, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and out == ""
    assert err == f"{p}: error: bodies[0] (a).radius: 1e-12 m is less than the tolerance (1e-09 m), within which " \
                  "contacts are found; scale the scene or lower the tolerance\n"


# ------------------------------------------------------------------ how big a scene may be
def test_the_counts_are_checked_before_any_body_or_input_is_read(monkeypatch):
    monkeypatch.setattr(sc, "MAX_BODIES", 3)
    monkeypatch.setattr(sc, "MAX_INPUTS", 2)
    monkeypatch.setattr(sc, "_circle", lambda *a: pytest.fail("a body was read"))
    monkeypatch.setattr(sc, "_body", lambda *a: pytest.fail("a body was read"))
    four = {"end_time": 1, "bodies": [ball(f"b{k}", position=[k, 0]) for k in range(4)]}
    assert refused(four) == "bodies: 4 bodies is more than 3, the most a scene may have"
    three = {"end_time": 1, "bodies": four["bodies"][:3],
             "inputs": [{"time": 0, "body": "b0", "add_velocity": [1, 0]}] * 3}
    assert refused(three) == "inputs: 3 inputs is more than 2, the most a scene may have"


def test_the_limits_are_the_documented_ones():
    assert (sc.MAX_BODIES, sc.MAX_VERTICES, sc.MAX_INPUTS, sc.COUNT_LIMIT) == (10 ** 6, 1024, 10 ** 7, 10 ** 18)
    with open(os.path.join(ROOT, "docs", "simulator.md"), encoding="utf-8") as f:
        doc = " ".join(f.read().split())
    for fact in ("1,000,000 bodies", "1,024 vertices", "10,000,000 inputs", f"{sc.MAX_NESTING} levels",
                 f"{sc.BYTES_PER_BODY} bytes per body", f"{sc.BYTES_PER_VERTEX} per vertex",
                 f"{sc.BYTES_PER_INPUT} per input", sc.MEMORY_ENV, "below 10^18"):
        assert fact in doc, fact


def test_a_polygon_of_more_than_1024_vertices_is_refused():
    big = {"end_time": 1, "bodies": [{"name": "p", "shape": "polygon", "fixed": True, "position": [0, 0],
                                      "vertices": ngon(1025)}]}
    assert refused(big) == "bodies[0].vertices: 1,025 vertices is more than 1,024, the most a polygon may have"


@pytest.mark.parametrize("lang", ["c", "python"])
def test_a_scene_whose_memory_estimate_passes_the_limit_is_refused(tmp_path, capsys, monkeypatch, lang):
    bodies = [ball(f"b{k}", position=[k, 0]) for k in range(100)]
    p = write(tmp_path, "many.json", {"end_time": 1, "bodies": bodies})
    need = sc.estimate_memory(100, 0, 0)
    assert need == sc.BYTES_BASE + 100 * sc.BYTES_PER_BODY
    monkeypatch.setenv(sc.MEMORY_ENV, str(need - 1))
    code, out, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and out == ""
    assert err == (f"{p}: error: scene: needs about 16 MB in the engine (100 bodies x {sc.BYTES_PER_BODY} B + "
                   f"0 vertices x {sc.BYTES_PER_VERTEX} B + 0 inputs x {sc.BYTES_PER_INPUT} B + 16 MB), more than "
                   f"the limit of 16 MB; set {sc.MEMORY_ENV}=BYTES to raise it\n")
    monkeypatch.setenv(sc.MEMORY_ENV, str(need))
    assert run(capsys, "simulate", "--lang", lang, p, "-q")[0] == 0
    monkeypatch.setenv(sc.MEMORY_ENV, "lots")
    code, out, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and err == f"{sc.MEMORY_ENV}: error: expected a positive number of bytes (such as 4e9), got 'lots'\n"


@pytest.mark.slow
def test_the_memory_estimate_holds_the_c_engines_peak(tmp_path):
    """The C simulator's peak resident size for a scene of many circles,
    polygons and inputs is within the estimate (measured from a small
    launcher: a child's peak counts its parent's size at the fork)."""
    from max2code.sim.scene import compile_scene
    from max2code.sim.simulate import build_simulator
    n, polys, inputs = 30000, 40, 30000
    side = math.ceil(math.sqrt(n))
    bodies = [ball(f"b{k}", position=[(k // side) * 1.0, (k % side) * 1.0], velocity=[0.1 * (k % 7 - 3), 0.0])
              for k in range(n)]
    bodies += [{"name": f"p{j}", "shape": "polygon", "fixed": True, "position": [-50.0 - 25.0 * j, -50.0],
                "vertices": ngon(1024, 10.0)} for j in range(polys)]
    scene = parse_scene(json.dumps({"end_time": 0.5, "bodies": bodies, "inputs": [
        {"time": 0.5 * k / inputs, "body": "b0", "add_velocity": [0.0, 0.0]} for k in range(inputs)]}))
    flat = tmp_path / "flat.txt"
    flat.write_text(compile_scene(scene), encoding="ascii")
    build = build_simulator("c", scene.effects, scene.taylor_order)
    launcher = ("import os, subprocess, sys\n"
                "p = subprocess.Popen(sys.argv[2:], stdin=open(sys.argv[1], 'rb'), stdout=subprocess.DEVNULL)\n"
                "print(os.wait4(p.pid, 0)[2].ru_maxrss * 1024)\n")
    peak = int(subprocess.run([sys.executable, "-c", launcher, str(flat), *build.run_cmd], cwd=build.workdir,
                              capture_output=True, text=True, check=True).stdout)
    estimate = sc.estimate_memory(n + polys, 1024 * polys, inputs)
    assert peak <= estimate, (peak, estimate)


@pytest.mark.parametrize("key", ["max_events", "max_events_at_one_time"])
@pytest.mark.parametrize("lang", ["c", "python"])
def test_event_limits_stay_below_10_to_the_18(tmp_path, capsys, key, lang):
    p = write(tmp_path, "big.json", f'{{"end_time": 1, "{key}": 1000000000000000000, "bodies": '
                                    '[{"shape": "circle", "radius": 0.1, "mass": 1, "position": [0, 0]}]}')
    code, out, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and err == f"{p}: error: {key}: must be a whole number below 10^18, got 1e+18\n"
    p = write(tmp_path, "ok.json", {"end_time": 1, key: 999999999999999000, "bodies": [ball()]})
    code, out, err = run(capsys, "simulate", "--lang", lang, p, "-q")
    assert code == 0, err


# ------------------------------------------------------------------ nesting
def test_a_million_nested_brackets_are_refused_before_decoding(tmp_path):
    """In a process of its own: the decoder crashed (signal 11) on it."""
    p = write(tmp_path, "deep.json", "[" * 10 ** 6 + "]" * 10 ** 6)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))
    r = subprocess.run([sys.executable, "-m", "max2code", "simulate", str(p)], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode == 1 and r.stdout == ""
    assert r.stderr == f"{p}: error: nested too deeply (more than {sc.MAX_NESTING} levels of brackets; " \
                       "a scene needs 5)\n"


def test_nesting_is_counted_outside_strings_and_up_to_the_limit():
    assert sc.nesting(b'{"a": "[[[[\\"]]]]", "b": [[1], {"c": [2]}], "d": "\\\\"}') == 4
    assert sc.nesting(b"[]" * 1000) == 1 and sc.nesting(b"") == 0 and sc.nesting(b'"[[["') == 0
    assert sc.nesting(b"[{" * 50 + b"}]" * 50) == 100
    assert sc.nesting(b"[" * 1000 + b"]" * 1000) == sc.MAX_NESTING + 1
    assert sc.nesting(b"[[]" * 300 + b"]" * 300) == sc.MAX_NESTING + 1
    assert sc.nesting(b"[[[[]]") == 4          # not JSON (the decoder says where): measured all the same
    base = '{"end_time": 1, "bodies": [{"shape": "circle", "radius": 0.1, "mass": 1, "position": [0, 0]}], "comment": '
    depth = sc.MAX_NESTING - 1                 # the scene's own braces make one more
    assert len(parse_scene(base + "[" * depth + "]" * depth + "}").bodies) == 1
    assert refused(base + "[" * (depth + 1) + "]" * (depth + 1) + "}").startswith("nested too deeply")


def test_the_c_reader_takes_no_scene_nested_deeper_than_the_limit():
    """scene_c.py makes no nesting check: the C reader's own bound on a
    passed-over value (MAX_DEPTH, plus the scene's brace) must stay within
    the Python reader's."""
    with open(os.path.join(ROOT, "runtimes", "c", "tools", "m2c_scene_flat.c"), encoding="utf-8") as f:
        c_depth = int(re.search(r"#define MAX_DEPTH (\d+)", f.read()).group(1))
    assert c_depth + 1 <= sc.MAX_NESTING


# ------------------------------------------------------------------ inputs named in magnitude errors
def test_a_teleport_beyond_the_safe_range_names_the_input():
    s = {"end_time": 1, "bodies": [ball()], "inputs": [{"time": 0.1, "body": "a", "add_velocity": [1, 0]},
                                                        {"time": 0.5, "body": "a", "teleport": [1e200, 0]}]}
    assert refused(s) == ("inputs[1].teleport: 1e+200 m from the origin is more than 1e+150 m, where squares "
                          "overflow; scale the scene")
    s["inputs"][1]["teleport"] = [9e149, 0]         # within the range, but the motion after it is not
    s["inputs"][0]["add_velocity"] = [2e149, 0]
    assert refused(s).startswith("inputs[0].add_velocity: with it bodies[0] (a) reaches 1.1e+150 m from the origin")
    s["inputs"][0]["add_velocity"] = [1, 0]
    s["bodies"][0]["velocity"] = [2e149, 0]         # the body's own motion from where the teleport puts it
    assert refused(s).startswith("inputs[1].teleport: with it bodies[0] (a) reaches 1.1e+150 m from the origin")
    s["inputs"][1]["teleport"] = [1, 0]
    s["bodies"][0]["velocity"] = [0, 0]
    s["inputs"].append({"time": 0.6, "body": "a", "set_velocity": [1e151, 0]})
    assert refused(s).startswith("inputs[2].set_velocity: takes the speed of bodies[0] (a) to 1e+151 m/s")


# ------------------------------------------------------------------ titles are text
@pytest.mark.parametrize("name", ["$\\frac{1}{$", "$x_$ and $\\sqrt{$"])
def test_render_draws_any_scene_name_as_text(tmp_path, capsys, name):
    """matplotlib reads text between dollars as mathematics: a scene named
    `$\\frac{1}{$` was an internal error of `render`; it is drawn as written."""
    pytest.importorskip("PIL")
    p = write(tmp_path, "s.json", {"name": name, "end_time": 0.5, "bodies": [
        ball(velocity=[1.0, 0.0]), ball("b", position=[0.5, 0.0])]})
    trace = tmp_path / "s.jsonl"
    assert run(capsys, "simulate", "--lang", "python", p, "-o", trace, "-q")[0] == 0
    out = tmp_path / "pics"
    code, _, err = run(capsys, "render", p, trace, "-o", out, "--gif", "--gif-fps", "4", "--gif-width", "160")
    assert code == 0, err
    assert os.path.getsize(f"{out}-overview.png") > 1000 and os.path.getsize(f"{out}.gif") > 100


# ------------------------------------------------------------------ signals during `simulate -o`
def _children(pid: int) -> list[int]:
    """The processes whose parent is pid (from /proc)."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", encoding="ascii", errors="replace") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.append(int(entry))
    return out


@pytest.mark.slow
@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads /proc for the child process")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_during_simulate_removes_the_temporary_output_and_stops_the_simulator(tmp_path, signum):
    """A run that would write gigabytes of frames, stopped by a signal once its
    temporary output holds some: exit status 128 + the signal, one line on
    standard error, no file left in the output's folder, the simulator gone."""
    wall = {"shape": "polygon", "fixed": True}
    p = write(tmp_path, "long.json", {"end_time": 1e5, "frame_rate": 1000, "max_events": 10 ** 9, "bodies": [
        ball(velocity=[1.3, 0.7]), ball("b", position=[0.5, 0.5], velocity=[-0.4, 0.9]),
        {**wall, "name": "floor", "position": [0, -2], "vertices": [[-3, -0.5], [3, -0.5], [3, 0.5], [-3, 0.5]]},
        {**wall, "name": "top", "position": [0, 2], "vertices": [[-3, -0.5], [3, -0.5], [3, 0.5], [-3, 0.5]]},
        {**wall, "name": "left", "position": [-2, 0], "vertices": [[-0.5, -1.5], [0.5, -1.5], [0.5, 1.5], [-0.5, 1.5]]},
        {**wall, "name": "right", "position": [2, 0], "vertices": [[-0.5, -1.5], [0.5, -1.5], [0.5, 1.5], [-0.5, 1.5]]}]})
    outdir = tmp_path / "out"
    outdir.mkdir()
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))
    proc = subprocess.Popen([sys.executable, "-m", "max2code", "simulate", str(p), "-o", str(outdir / "trace.jsonl"),
                             "-q"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 600       # a first build of the simulator may take minutes
        children = []
        while time.monotonic() < deadline:
            temps = list(outdir.iterdir())
            if temps and temps[0].stat().st_size > 1 << 20:
                children = _children(proc.pid)
                if children:
                    break
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.05)
        assert children and temps, "the run did not start writing"
        proc.send_signal(signum)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + signum, err
    assert err == ("max2code: terminated\n" if signum == signal.SIGTERM else "max2code: interrupted\n")
    assert list(outdir.iterdir()) == []
    for pid in children:
        assert not os.path.exists(f"/proc/{pid}"), f"the simulator {pid} still runs"


# ------------------------------------------------------------------ the C world's binding
TWO = {"end_time": 2.0, "bodies": [ball(velocity=[1.0, 0.0]), ball("b", position=[1.0, 0.0]),
                                   {"name": "wall", "shape": "polygon", "fixed": True, "position": [3.0, 0.0],
                                    "vertices": [[-0.1, -1], [0.1, -1], [0.1, 1], [-0.1, 1]]}]}


@pytest.fixture(scope="module")
def c_world():
    """(library, flat text) of TWO: CWorld(library, text, out) makes a world.
    It builds the C world library, so the tests using it are slow tests."""
    from max2code.sim.scene import compile_scene
    from max2code.sim.simulate import world_library
    scene = parse_scene(json.dumps(TWO))
    return str(world_library(scene, "c")), compile_scene(scene)


def open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


@pytest.mark.slow
@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="counts the open descriptors in /proc")
def test_worlds_dropped_without_close_free_their_trace_files(c_world):
    """3,000 worlds with a trace, dropped without close() while the cyclic
    collector is off: each is freed as its last reference goes (no cycle
    keeps it), so the descriptors do not grow ("Too many open files" after
    10^4 before)."""
    import io
    from max2code.sim.cworld import CWorld
    lib, text = c_world
    gc.collect()
    before = open_fds()
    was = gc.isenabled()
    gc.disable()
    try:
        for _ in range(3000):
            w = CWorld(lib, text, io.StringIO())
            w.advance(0.1)
            del w
        grown = open_fds() - before
    finally:
        if was:
            gc.enable()
    assert grown <= 2, f"{grown} descriptors more after 3,000 worlds"


@pytest.mark.slow
def test_a_dropped_world_passes_its_whole_trace_on_and_close_is_idempotent(c_world):
    import io
    from max2code.sim.cworld import CWorld
    lib, text = c_world
    closed, dropped = io.StringIO(), io.StringIO()
    w = CWorld(lib, text, closed)
    w.advance(1.0)
    w.finish()
    w.close()
    w.close()
    with pytest.raises(Exception, match="the world is closed"):
        w.advance(1.5)
    w = CWorld(lib, text, dropped)
    w.advance(1.0)
    w.finish()
    del w
    assert dropped.getvalue() == closed.getvalue() and "\nN " in closed.getvalue()


@pytest.mark.slow
def test_integer_arguments_outside_the_c_range_are_refused_not_wrapped(c_world):
    """ctypes passes 2^32 on as the C int 0: state(2**32, t) gave body 0."""
    from max2code.sim.cworld import CWorld
    from max2code_rt.sim import SimError
    lib, text = c_world
    with CWorld(lib, text) as w:
        assert w.state(0, 0.0)[:2] == (0.0, 0.0)
        for body in (2 ** 32, 2 ** 31, -1, 3, -2 ** 32):
            with pytest.raises(SimError, match=re.escape(f"no body {body} (the world has 3)")):
                w.state(body, 0.0)
            with pytest.raises(SimError, match=re.escape(f"live input: body {body} does not exist")):
                w.set_velocity(body, 1.0, 0.0)
        for body in (1.0, "0", None):
            with pytest.raises(SimError, match="a body is an index"):
                w.add_velocity(body, 1.0, 0.0)
        with pytest.raises(SimError, match="vx: expected a number"):
            w.set_velocity(0, "fast", 0.0)
        with pytest.raises(SimError, match="x: expected a number"):
            w.teleport(0, 10 ** 400, 0.0)
        with pytest.raises(SimError, match="add_body: the body's text: the flat text is ASCII"):
            w.add_body("body 0 0 1.0\u00e9")
        assert w.input_log() == [] and w.state(0, 0.0)[2:4] == (1.0, 0.0)


@pytest.mark.parametrize("engine", ["c", "python"])
def test_live_inputs_after_finish_or_with_a_velocity_that_is_not_finite_are_refused(engine):
    from max2code.sim.live import open_world
    from max2code_rt.sim import SimError
    w = open_world(TWO, engine)
    w.advance(0.1)
    w.add_velocity(0, 1e140, 0.0)                # 1e140 m/s reaches about 1e140 m by the end: made
    before = (w.input_log(), w.state(0, w.time))
    far = "live input: body 0: reaches more than 2e150 m from the origin by the end"
    with pytest.raises(SimError, match=re.escape(far)):
        w.add_velocity(0, 1e308, 0.0)            # finite, but far beyond the scene's reach by the end
    with pytest.raises(SimError, match=re.escape(far)):
        w.apply_impulse(0, 1e308, 0.0)           # mass 1 kg
    with pytest.raises(SimError, match=re.escape("live input: body 0: velocity would not be finite")):
        w.set_velocity(0, math.inf, 0.0)
    w.add_velocity(0, -1e140, 0.0)               # made
    assert (w.input_log()[:-1], w.state(0, w.time)) != before and w.input_log()[:-1] == before[0]
    w.finish()
    for call in (lambda: w.set_velocity(0, 1.0, 0.0), lambda: w.add_velocity(0, 1.0, 0.0),
                 lambda: w.apply_impulse(0, 1.0, 0.0), lambda: w.teleport(0, 0.0, 5.0), lambda: w.remove_body(1),
                 w.finish):
        with pytest.raises(SimError, match=re.escape("live input: the world is finished")):
            call()
    if engine == "c":
        w.close()
