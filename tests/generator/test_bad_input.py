"""Every input gets a clear answer.  One test (or parameter) per
case the issue lists: a correct result, or one line
`FILE[:LINE[:COL]]: error: ...` naming the input, exit status 1; never a
traceback, an "internal error", a hang or a silently wrong answer."""
import json
import os
from pathlib import Path
import re
import subprocess
import sys

import pytest

from max2code.cli import main
from max2code.generate.maxima import DEFAULT_TIMEOUT

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
OK_MXM = "begin\na + b*t + c*t^2;\nend\n"


def run(capsys, *argv):
    """The CLI in this process: (exit status, stdout, stderr)."""
    try:
        code = main(list(map(str, argv)))
    except SystemExit as exc:          # --help
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def one_error_line(err: str, where: str) -> str:
    """The message after `where: error: `, checking it is the only stderr line."""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(where), (where, err)
    assert "error: " in lines[0] and "internal error" not in lines[0] and "Traceback" not in err, err
    return lines[0].split("error: ", 1)[1]


def scene(**top):
    s = {"end_time": 1.0, "gravity": [0, -9.81], "bodies": [
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0, 1], "velocity": [0, 0]},
        {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -0.5],
         "vertices": [[-5, -0.5], [5, -0.5], [5, 0.5], [-5, 0.5]]}]}
    s.update(top)
    return s


def write(tmp_path, name, data):
    p = tmp_path / name
    if isinstance(data, bytes):
        p.write_bytes(data)
    else:
        p.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return p


# ------------------------------------------------------------------ hangs
def test_frame_rate_1e9_is_refused_at_once(tmp_path, capsys):
    p = write(tmp_path, "fr.json", scene(frame_rate=1e9))
    code, out, err = run(capsys, "simulate", "--lang", "python", p)
    assert code == 1 and out == ""
    assert "frame_rate" in one_error_line(err, f"{p}: error: ")


def test_frames_beyond_max_events_are_refused(tmp_path, capsys):
    p = write(tmp_path, "fr.json", scene(frame_rate=500, end_time=100, max_events=1000))
    code, _, err = run(capsys, "simulate", "--lang", "python", p)
    assert code == 1 and "max_events" in one_error_line(err, f"{p}: error: frame_rate")


@pytest.mark.parametrize("lang", ["c", "python"])
@pytest.mark.parametrize("fault", ["overlap", "far"])
def test_the_last_scene_checks_stop_the_simulator_and_write_nothing(tmp_path, capsys, monkeypatch, fault, lang):
    """`simulate` makes the checks of the whole scene (overlaps, magnitudes)
    while the simulator reads the scene: the same one line as parse_scene,
    nothing written, to a file or to standard output; and before a build
    when the simulator must be built first."""
    from max2code.sim import scene as sc
    from max2code.sim import simulate as sim

    data = scene()
    if fault == "overlap":
        data["bodies"][0]["position"] = [0, 0.05]
    else:
        data["bodies"][0]["velocity"] = [1e160, 0]
    p = write(tmp_path, "bad.json", data)
    with pytest.raises(sc.SceneError) as want:
        sc.load_scene(str(p))
    out = tmp_path / "trace.jsonl"
    code, stdout, err = run(capsys, "simulate", "--lang", lang, p, "-o", out)
    assert code == 1 and err == str(want.value) + "\n" and stdout == "" and not out.exists()
    code, stdout, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and err == str(want.value) + "\n" and stdout == ""
    monkeypatch.setattr(sim, "built_simulator", lambda *a: None)
    monkeypatch.setattr(sim, "build_simulator", lambda *a, **k: pytest.fail("built before the scene was checked"))
    code, stdout, err = run(capsys, "simulate", "--lang", lang, p)
    assert code == 1 and err == str(want.value) + "\n" and stdout == ""


@pytest.mark.slow
def test_max_events_stops_a_run(tmp_path, capsys):
    p = write(tmp_path, "many.json", scene(frame_rate=100, end_time=1))
    out = tmp_path / "trace.jsonl"
    code, _, err = run(capsys, "simulate", "--lang", "c", p, "--max-events", "10", "-o", out, "-q")
    # the simulator counts every event it handles (the ball's cell crossings too) and stops first
    assert code == 1 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith(f"{p}: error: c simulator: more than 10 events (collisions, inputs, frames, cell crossings, "
                          "horizons) at t = "), err
    assert err.endswith(f"; the trace up to then is in {out}\n"), err
    lines = [json.loads(x) for x in out.read_text().splitlines()]
    assert [e["kind"] for e in lines[:-1]] == ["frame"] * (len(lines) - 1) and lines[-1]["kind"] == "stopped"
    assert 1 <= len(lines) - 1 <= 10, "the frames before the stop are kept"
    assert all(e["t"] <= lines[-1]["t"] for e in lines)
    assert float(err.split(" at t = ")[1].split(":")[0]) == lines[-1]["t"], "the stopped line's instant is the error's"
    code, _, err = run(capsys, "simulate", "--lang", "c", p, "--no-frames", "--max-events", "200", "-o", out, "-q")
    assert code == 0, err
    code, _, err = run(capsys, "simulate", "--lang", "c", p, "--max-events", "0")
    assert code == 1 and "--max-events" in err


def test_looping_maxima_stops_at_the_timeout(tmp_path, capsys):
    assert DEFAULT_TIMEOUT == 60.0          # our equations take about 1 s
    p = write(tmp_path, "loop.mxm", "begin\nwhile true do t;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q", "--no-cache", "--maxima-timeout", "2")
    assert code == 1 and "did not finish within 2 s" in one_error_line(err, f"{p}:2:1: error: ")


# ------------------------------------------------------------------ silently wrong
@pytest.mark.parametrize("field,body,value", [
    ("velocity", 0, [0, -1e308]),
    ("position", 0, [1e200, 0]),
    ("radius", 0, 1e300),
    ("radius", 0, 1e-300),
    ("mass", 0, 1e-310),
    ("acceleration", 0, [0, -1e300]),
])
def test_magnitudes_that_cannot_be_represented_name_the_field(tmp_path, capsys, field, body, value):
    s = scene()
    s["bodies"][body][field] = value
    p = write(tmp_path, "big.json", s)
    code, out, err = run(capsys, "simulate", "--lang", "python", p)
    assert code == 1 and out == ""
    one_error_line(err, f"{p}: error: bodies[0] (ball).{field}")


@pytest.mark.parametrize("x", [1e17, -3e16, 1e30])
def test_a_polygon_so_far_out_that_its_vertices_round_together_is_refused(tmp_path, capsys, x):
    """A 0.2 m box (and a second one beside it) placed where the doubles are
    coarser than the box: its edges vanish.  Refused at the body's position,
    never a ZeroDivisionError while the scene is checked."""
    box = [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]
    s = {"end_time": 1.0, "gravity": [0, -9.81], "bodies": [
        {"name": "far", "shape": "polygon", "fixed": True, "position": [x, 0], "vertices": box},
        {"name": "beside", "shape": "polygon", "fixed": True, "position": [x, 0.2], "vertices": box},
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [x, 0.5]}]}
    p = write(tmp_path, "far.json", s)
    for lang in ("python", "c"):
        code, out, err = run(capsys, "simulate", "--lang", lang, p)
        assert code == 1 and out == ""
        assert "vertices round together" in one_error_line(err, f"{p}: error: bodies[0] (far).position")


def test_a_polygon_far_out_but_still_resolved_is_simulated(tmp_path, capsys):
    """1e6 m out the same box is 2e-11 relative of its position: simulated (the ball lands on it)."""
    box = [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]
    s = {"end_time": 1.0, "gravity": [0, -9.81], "bodies": [
        {"name": "far", "shape": "polygon", "fixed": True, "position": [1e6, 0], "vertices": box},
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [1e6, 0.5]}]}
    p = write(tmp_path, "far.json", s)
    code, out, err = run(capsys, "simulate", "--lang", "python", p, "-q")
    assert code == 0, err
    assert any(json.loads(x).get("kind") == "collision" for x in out.splitlines())


@pytest.mark.parametrize("where,text", [
    ("end_time", '{"end_time": 1' + "0" * 400 + ', "bodies": []}'),
    ("bodies[0] (ball).position[0]", json.dumps(scene()).replace('"position": [0, 1]',
                                                               '"position": [-' + "9" * 330 + ', 1]')),
    ("bodies[0] (ball).radius", json.dumps(scene()).replace('"radius": 0.1', '"radius": 1' + "0" * 320)),
])
def test_integers_beyond_a_double_name_the_field(tmp_path, capsys, where, text):
    """JSON lets an integer be written out with any number of digits: one
    beyond the doubles' range is refused at its field, not an OverflowError."""
    p = write(tmp_path, "huge.json", text)
    code, out, err = run(capsys, "simulate", "--lang", "python", p)
    assert code == 1 and out == ""
    assert "beyond a double's range" in one_error_line(err, f"{p}: error: {where}")


@pytest.mark.parametrize("body", [["ball"], {"name": "ball"}, 3, None])
def test_an_input_naming_its_body_by_a_non_string_is_refused(tmp_path, capsys, body):
    s = scene(inputs=[{"time": 0.5, "body": body, "set_velocity": [1, 0]}])
    p = write(tmp_path, "in.json", s)
    code, out, err = run(capsys, "simulate", "--lang", "python", p)
    assert code == 1 and out == ""
    assert one_error_line(err, f"{p}: error: inputs[0].body") == (
        f"inputs[0].body: expected a body's name (a string), got {json.dumps(body)}")


def test_large_but_finite_magnitudes_are_solved(tmp_path, capsys):
    s = scene(gravity=[0, 0])
    s["bodies"][0]["velocity"] = [0, -1e100]
    p = write(tmp_path, "fast.json", s)
    code, out, err = run(capsys, "simulate", "--lang", "python", p, "-q")
    assert code == 0, err
    lines = [json.loads(x) for x in out.splitlines()]
    hits = [e for e in lines if e.get("kind") == "collision"]
    assert len(hits) == 1 and 0 < hits[0]["t"] < 1e-99          # the ball does not pass the floor
    assert "Infinity" not in out and "NaN" not in out


def test_empty_case_file_is_not_a_pass(tmp_path, capsys):
    p = write(tmp_path, "empty.jsonl", "\n")
    code, _, err = run(capsys, "conformance", "--lang", "python", "--cases", p)
    assert code == 1 and "no cases" in one_error_line(err, f"{p}: error: ")


def test_reserved_equation_name_is_refused_at_its_place(tmp_path, capsys):
    p = write(tmp_path, "e.mxm", "equation int\n" + OK_MXM)
    code, out, err = run(capsys, "--lang=c", p, "-q")
    assert code == 1 and out == ""
    assert "'int' is reserved in c, python" in one_error_line(err, f"{p}:1:10: error: ")
    v = write(tmp_path, "v.mxm", "variable lo\nbegin\na + lo;\nend\n")
    code, _, err = run(capsys, "--lang=c", v, "-q")
    assert code == 1 and "variable 'lo' is reserved" in one_error_line(err, f"{v}:1:10: error: ")


@pytest.mark.parametrize("decl,col", [("parameter fn", 11), ("parameter MOD", 11), ("parameter def", 11),
                                      ("parameter coef", 11), ("parameter _x", 11)])
def test_reserved_parameter_is_refused_at_its_place(tmp_path, capsys, decl, col):
    name = decl.split()[1]
    p = write(tmp_path, "p.mxm", f"{decl}\nparameter b\nbegin\n{name} + b*t;\nend\n")
    code, _, err = run(capsys, "--lang=python", p, "-q")
    assert code == 1 and "is reserved in" in one_error_line(err, f"{p}:1:{col}: error: ")


def test_reserved_file_name_is_renamed_and_compiles(tmp_path, capsys):
    p = write(tmp_path, "int.mxm", OK_MXM)
    out_c = tmp_path / "int.c"
    code, _, err = run(capsys, "--lang=c", p, "-q", "-o", out_c)
    assert code == 0, err
    text = out_c.read_text()
    assert "void eq_int(double a, double b, double c, double coef[3])" in text
    r = subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-c", str(out_c), "-o",
                        str(tmp_path / "int.o")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("value,words", [("-1", "must be from 1 to 8"), ("2.5", "must be a whole number"),
                                         ("9", "must be from 1 to 8"), ("x", "not a number")])
def test_option_values_are_checked(capsys, value, words):
    path = os.path.join(ROOT, "equations", "circle-circle.mxm")
    code, out, err = run(capsys, "--lang=c", path, "-q", "-D", f"order={value}")
    assert code == 1 and out == ""
    assert words in one_error_line(err, f"{path}:13:8: error: -D order={value}: ")


@pytest.mark.parametrize("value", ["-5", "0", "nan", "inf", "soon"])
def test_maxima_timeout_is_checked(tmp_path, capsys, value):
    p = write(tmp_path, "ok.mxm", OK_MXM)
    code, _, err = run(capsys, "--lang=c", p, "-q", "--maxima-timeout", value)
    assert code == 1 and "--maxima-timeout" in one_error_line(err, "max2code: error: ")


def test_simulate_dash_o_dash_is_standard_output(tmp_path, capsys, monkeypatch):
    p = os.path.join(ROOT, "examples", "newtons-cradle.json")
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "simulate", "--lang", "python", p, "-o", "-", "-q")
    assert code == 0, err
    assert not (tmp_path / "-").exists()
    lines = [json.loads(x) for x in out.splitlines()]
    assert lines[-2]["kind"] == "final" and lines[-1]["kind"] == "stats"


# ------------------------------------------------------------------ user mistakes, not internal errors
@pytest.mark.parametrize("cmd", ["generate", "list-variants", "simulate"])
@pytest.mark.parametrize("where", ["missing", "folder"])
def test_output_into_a_missing_folder_or_onto_a_folder(tmp_path, capsys, cmd, where):
    out = tmp_path / "no-such-folder" / "x.out" if where == "missing" else tmp_path
    mxm = write(tmp_path, "ok.mxm", OK_MXM)
    argv = {"generate": ["--lang=c", mxm, "-q"], "list-variants": ["--list-variants", mxm, "-q"],
            "simulate": ["simulate", "--lang", "python", os.path.join(ROOT, "examples", "newtons-cradle.json"), "-q"]}
    code, _, err = run(capsys, *argv[cmd], "-o", out)
    msg = one_error_line(err, f"-o {out}: error: ")
    assert code == 1 and ("does not exist" in msg if where == "missing" else "is a folder" in msg)


def test_a_fault_of_another_file_inside_an_output_block_is_not_blamed_on_the_output(tmp_path):
    """open_output reports its own file's faults as `-o FILE: cannot write`;
    an OSError about another file raised inside the block (a program that
    cannot start) passes through as it is, and the half-written file is gone."""
    from max2code.textio import OutputError, open_output
    out = tmp_path / "t.jsonl"
    with pytest.raises(PermissionError):
        with open_output(str(out)) as fh:
            fh.write("x")
            raise PermissionError(13, "Permission denied", "/some/where/sim")
    with pytest.raises(OutputError, match="cannot write: No space left on device"):
        with open_output(str(out)) as fh:
            raise OSError(28, "No space left on device")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_a_simulator_program_deleted_from_its_build_is_built_again(tmp_path, capsys, monkeypatch):
    """The build stamps match but the program is gone (deleted, or replaced
    by another run at that moment): simulate builds it again and runs, and
    writes its output file (not `-o FILE: cannot write`).  In a build folder
    of its own (the shared one's program may be running in another test):
    a copy of the shared build, whose stamps hold for the copy too (they
    leave the folder's path out), with the program deleted."""
    import shutil
    from max2code.sim import simulate
    from max2code.sim.scene import load_scene
    from max2code.sim.simulate import build_simulator, built_simulator
    path = os.path.join(ROOT, "examples", "newtons-cradle.json")
    scene = load_scene(path)
    shared = build_simulator("c", scene.effects, scene.taylor_order).workdir
    monkeypatch.setattr(simulate, "BUILD", tmp_path / "build")
    own = simulate._build_key("c", scene.effects, scene.taylor_order)[0]
    shutil.copytree(shared, own, ignore=shutil.ignore_patterns(".lock", "*.so", "*.pic.o"))
    program = built_simulator("c", scene.effects, scene.taylor_order).run_cmd[0]
    assert program.startswith(str(own))
    stamp = (own / "build.stamp").read_text()
    os.unlink(program)
    assert built_simulator("c", scene.effects, scene.taylor_order) is None
    out = tmp_path / "t.jsonl"
    code, _, err = run(capsys, "simulate", "--lang", "c", path, "-q", "-o", out)
    assert code == 0, err
    assert os.path.exists(program) and out.read_text().count("\n") > 100
    assert (own / "build.stamp").read_text() == stamp


def test_a_simulator_that_cannot_start_is_named(tmp_path, monkeypatch):
    """A program that exists but cannot be run is a SimulateError naming it."""
    from max2code.sim.scene import load_scene
    from max2code.sim.simulate import SimBuild, SimulateError, start_simulator
    prog = tmp_path / "sim"
    prog.write_text("not a program")           # not executable
    build = SimBuild("c", str(tmp_path), [str(prog)], {}, {})
    with pytest.raises(SimulateError, match=r"cannot start the c simulator .*sim: Permission denied"):
        start_simulator(build)


BAD_BYTES = b"\xff\xfe\x00bad"


def test_non_utf8_scene_trace_and_case_files_name_the_input(tmp_path, capsys):
    sc = write(tmp_path, "s.json", b'{"end_time": 1,\n "name": "' + BAD_BYTES + b'"}')
    code, _, err = run(capsys, "simulate", "--lang", "python", sc, "-o", tmp_path / "out.jsonl")
    assert code == 1 and "not UTF-8" in one_error_line(err, f"{sc}:2:11: error: ")
    good = os.path.join(ROOT, "examples", "newtons-cradle.json")
    tr = write(tmp_path, "t.jsonl", b'{"kind": "final"}\n' + BAD_BYTES)
    code, _, err = run(capsys, "render", good, tr, "-o", tmp_path / "pic")
    assert code == 1 and "not UTF-8" in one_error_line(err, f"{tr}:2:1: error: ")
    cs = write(tmp_path, "c.jsonl", BAD_BYTES)
    code, _, err = run(capsys, "conformance", "--lang", "python", "--cases", cs, "--quiet")
    assert code == 1 and "not UTF-8" in one_error_line(err, f"{cs}:1:1: error: ")


def test_unknown_function_in_the_maxima_text_is_located(tmp_path, capsys):
    p = write(tmp_path, "f.mxm", "parameter a\nbegin\nx: a + t$\nSin(a) * x;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q")
    assert code == 1 and "unknown function 'Sin'" in one_error_line(err, f"{p}:4:1: error: ")


@pytest.mark.parametrize("line,words", [("[1, 2]", "expected a case object"), ("{oops", "not JSON"),
                                        ('{"id": "x"}', 'no "op"')])
def test_case_lines_that_are_not_case_objects(tmp_path, capsys, line, words):
    p = write(tmp_path, "cases.jsonl", '{"id": "a", "op": "roots", "coeffs": [-1, 1], "lo": 0, "hi": 2, "expect": 1, "roots": [[1, 1, 1e-15]]}\n'
              + line + "\n")
    code, _, err = run(capsys, "conformance", "--lang", "python", "--cases", p, "--quiet")
    assert code == 1 and words in one_error_line(err, f"{p}:2")


# ------------------------------------------------------------------ misleading messages
def test_sin_of_a_t_is_not_a_polynomial(tmp_path, capsys):
    p = write(tmp_path, "s.mxm", "parameter a\nbegin\nsin(a*t) - 1;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q")
    msg = one_error_line(err, f"{p}:3:1: error: ")
    assert code == 1 and "not a polynomial in t" in msg and "does not depend" not in msg


def test_bom_and_crlf_are_accepted(tmp_path, capsys):
    p = write(tmp_path, "bom.mxm", b"\xef\xbb\xbfparameter a\r\nparameter b\r\nbegin\r\na + b*t;\r\nend\r\n")
    code, out, err = run(capsys, "--lang=python", p, "-q")
    assert code == 0, err
    assert "def bom(a, b):" in out
    (tmp_path / "plain").mkdir()
    plain = write(tmp_path / "plain", "bom.mxm", "parameter a\nparameter b\nbegin\na + b*t;\nend\n")
    _, out2, _ = run(capsys, "--lang=python", plain, "-q")
    assert out2.replace(str(plain), str(p)) == out
    sc = write(tmp_path, "s.json", b"\xef\xbb\xbf" + json.dumps(scene(), indent=1).replace("\n", "\r\n").encode())
    code, out, err = run(capsys, "simulate", "--lang", "python", sc, "-q")
    assert code == 0, err
    cs = write(tmp_path, "c.jsonl", b'\xef\xbb\xbf{"id": "a", "op": "roots", "coeffs": [-1, 1], "lo": 0, "hi": 2, '
                                    b'"expect": 1, "roots": [[1, 1, 1e-15]]}\r\n')
    code, out, err = run(capsys, "conformance", "--lang", "python", "--cases", cs, "--quiet")
    assert code == 0, out + err


def test_usage_errors_exit_1_in_one_line(capsys):
    for argv in (["--lang=zz", "x.mxm"], ["simulate"], ["conformance", "--lang", "cobol"], ["render", "--fps"]):
        code, _, err = run(capsys, *argv)
        assert code == 1, argv
        assert len(err.strip().splitlines()) == 1 and "error:" in err, err


# ------------------------------------------------------------------ contact semantics at the edges
@pytest.mark.slow
def test_overlap_at_t0_is_its_own_answer_in_python(tmp_path, capsys):
    path = os.path.join(ROOT, "equations", "circle-circle.mxm")
    out = tmp_path / "cc.py"
    code, _, err = run(capsys, "--lang=python", path, "--exact", "-q", "-o", out)
    assert code == 0, err
    ns: dict = {}
    exec(compile(out.read_text(), str(out), "exec"), ns)
    toc = ns["circle_circle_toc_exact"]
    zero = dict.fromkeys("abcdefmnopqghijklrsuvw", 0.0)

    def at(**kw):
        p = dict(zero, **kw)
        return toc(*[p[k] for k in "abcdefmnopqghijklrsuvwxz"], 10.0)

    # overlapping by 0.5 and moving apart: the overlap ends at t = 0.25, which is no contact
    assert at(a=0.0, b=-1.0, g=1.5, h=1.0, x=1.0, z=1.0) == "overlapped"
    # overlapping and moving further in
    assert at(a=0.0, b=1.0, g=1.5, x=1.0, z=1.0) == "overlapped"
    # apart and approaching: the contact
    assert at(a=0.0, b=1.0, g=3.0, x=1.0, z=1.0) == pytest.approx(1.0, rel=1e-15)


def test_huge_powers_are_refused_not_expanded(tmp_path, capsys):
    """Found by the fuzz harness: t^100000000 was expanded term by term (a hang)."""
    p = write(tmp_path, "deg.mxm", "begin\na + t^100000000;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q")
    assert code == 1 and "is above 1000" in one_error_line(err, f"{p}:2:1: error: ")
    p = write(tmp_path, "deg2.mxm", "begin\na + t^100;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q")
    assert code == 1 and "degree 100" in one_error_line(err, f"{p}:2:1: error: ")


@pytest.mark.slow
@pytest.mark.parametrize("line, message", [
    ("input 0.5 7 0 1.0 0.0", "scene: input on body 7, which does not exist"),
    ("input 0.5 -1 0 1.0 0.0", "scene: input on body -1, which does not exist"),
    ("input 0.5 0 9 1.0 0.0", "scene: unknown input mode 9"),
])
def test_a_hand_made_flat_scene_with_a_bad_input_is_refused_alike_by_every_runtime(line, message):
    """A flat scene (docs/simulator.md; the C API and add_body take them from
    users) whose input names no body or an unknown mode: every runtime
    writes the same X line and exits 1 (Python indexed the last body for
    -1 and crashed for 7; Rust wrote nothing; every runtime took mode 9)."""
    from max2code.sim.scene import compile_scene, parse_scene
    from max2code.sim.simulate import LANGS, build_simulator
    sc = parse_scene(json.dumps({"end_time": 1.0, "bodies": [
        {"name": "a", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}],
        "inputs": [{"time": 0.5, "body": "a", "set_velocity": [1.0, 0.0]}]}), "in-memory")
    flat = compile_scene(sc)
    assert "\ninput 0.5 0 0 1.0 0.0\n" in flat
    bad = flat.replace("\ninput 0.5 0 0 1.0 0.0\n", f"\n{line}\n")
    for lang in LANGS:
        build = build_simulator(lang, sc.effects, sc.taylor_order)
        proc = subprocess.run(build.run_cmd, input=bad, capture_output=True, text=True, cwd=build.workdir,
                              timeout=120)
        assert (lang, proc.returncode, proc.stdout) == (lang, 1, f"X {message}\n"), proc.stderr[-500:]
