"""Fuzzing the command line in this process: random
argument lists and random or mutated .mxm, scene, trace and case files
(valid files with one mutation, random bytes, huge and tiny numbers, wrong
encodings).  Every run must end with exit status 0 or 1 (never an internal
error or a traceback), within a bounded time, and whatever it wrote must be
valid: JSON lines without NaN or Infinity, generated code that compiles (a
sample: C with gcc, Python byte-compiled).

The suite runs a fixed seed (hypothesis `derandomize`) and a small budget;
MAX2CODE_FUZZ_EXAMPLES=N runs N inputs per test instead (the longer run):

    MAX2CODE_FUZZ_EXAMPLES=300 python3 -m pytest -q tests/commands/test_fuzz.py
"""
import contextlib
import hashlib
import io
import json
import os
from pathlib import Path
import py_compile
import subprocess
import time

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from max2code.cli import main

pytestmark = pytest.mark.slow      # runs Maxima and the simulators on many mutated inputs

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
SCALE = int(os.environ.get("MAX2CODE_FUZZ_EXAMPLES", "0"))
SECONDS = 240.0          # one run: Maxima is given 10 s per call, simulations a few thousand events


def budget(n: int):
    # no shrinking: a failure is reported as found, and the run time stays bounded
    return settings(max_examples=SCALE or n, deadline=None, derandomize=True, database=None,
                    suppress_health_check=list(HealthCheck), phases=[Phase.explicit, Phase.generate],
                    print_blob=False)


# ------------------------------------------------------------------ running
def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    t0 = time.monotonic()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:       # --help and --version only
            code = exc.code if isinstance(exc.code, int) else 1
    took = time.monotonic() - t0
    o, e = out.getvalue(), err.getvalue()
    assert took < SECONDS, f"{argv}: took {took:.0f} s"
    assert code in (0, 1), f"{argv}: exit {code}: {e[-2000:]}"
    assert "internal error" not in e and "Traceback" not in e, f"{argv}: {e[-2000:]}"
    if code == 1 and "--help" not in argv and "-h" not in argv:
        if not e.strip() and o.rstrip().endswith("conformance: FAILED"):
            return code, o, e           # the suite ran and a case failed (a malformed case is a failing case)
        assert e.strip(), f"{argv}: exit 1 without a message"
        assert "error" in e.strip().splitlines()[-1], f"{argv}: {e}"
    return code, o, e


def _no_constant(name):
    raise ValueError(f"{name} in JSON output")


def check_json_lines(text: str, what: str) -> None:
    for k, line in enumerate(text.splitlines(), 1):
        if line.strip():
            json.loads(line, parse_constant=_no_constant)


def check_generated(path: str, lang: str) -> None:
    """Compile a sample of the generated code: every Python file; C one in three (by content)."""
    text = open(path, encoding="utf-8").read()
    if lang == "python":
        py_compile.compile(path, doraise=True)
    elif lang == "c" and int(hashlib.sha256(text.encode()).hexdigest(), 16) % 3 == 0:
        r = subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                            f"-I{ROOT}/runtimes/c/include", "-include", "m2c_roots.h", "-include", "m2c_exact.h", path],
                           capture_output=True, text=True)
        assert r.returncode == 0, f"generated C does not compile:\n{r.stderr[-3000:]}"


# ------------------------------------------------------------------ inputs
MXM = [
    "begin\na + b*t + c*t^2;\nend\n",
    ("equation fall \"a falling point\"\noption order = 2 in 1..4 \"an option\"\n"
     "parameter a \"position\"\nparameter b \"speed\"\nparameter g \"gravity\"\n"
     "begin\nP: a + b*t - g*t^2/2 $\nP + sum(t^k, k, 0, order);\nend\n"),
    "term 0 { x := }\nterm 1 { y := }\n{\n u + v*t;\n}\n",
]
SCENES = ["newtons-cradle.json", "resting-ball.json", "billiard-break.json"]
NUMBERS = ["0", "-0", "1e308", "-1e308", "1e-308", "5e-324", "1e400", "1e-400", "NaN", "Infinity", "-1",
           "123456789012345678901234567890", "0.1", "2.5", "1e150", "1e-150", "\"3\"", "null", "true", "[]", "{}"]


@st.composite
def mutated_text(draw, text: str) -> bytes:
    """`text` with one mutation, as bytes (some in another encoding)."""
    how = draw(st.sampled_from(["delete", "insert", "replace", "number", "bytes", "encoding", "truncate",
                                "duplicate", "random"]))
    n = len(text)
    i = draw(st.integers(0, max(0, n - 1)))
    if how == "delete":
        text = text[:i] + text[i + draw(st.integers(1, 8)):]
    elif how == "insert":
        text = text[:i] + draw(st.text(min_size=1, max_size=6)) + text[i:]
    elif how == "replace":
        text = text[:i] + draw(st.sampled_from(list("{}[]();$:,\"'\\/*=-+^%.0123456789t\n\r\t "))) + text[i + 1:]
    elif how == "number":
        import re
        nums = [m.span() for m in re.finditer(r"-?\d+(\.\d+)?([eE][-+]?\d+)?", text)]
        if nums:
            a, b = draw(st.sampled_from(nums))
            text = text[:a] + draw(st.sampled_from(NUMBERS)) + text[b:]
    elif how == "truncate":
        text = text[:i]
    elif how == "duplicate":
        lines = text.splitlines(True)
        k = draw(st.integers(0, max(0, len(lines) - 1)))
        text = "".join(lines[:k + 1] + lines[k:])
    elif how == "random":
        return draw(st.binary(max_size=300))
    data = text.encode("utf-8")
    if how == "bytes":
        j = draw(st.integers(0, len(data)))
        data = data[:j] + draw(st.binary(min_size=1, max_size=4)) + data[j:]
    elif how == "encoding":
        codec = draw(st.sampled_from(["utf-16", "latin-1", "utf-8-sig", "cp1252"]))
        data = (text + "é").encode(codec, errors="replace")
    return data


def _json_paths(obj, path=()):
    yield path
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _json_paths(v, path + (k,))
    elif isinstance(obj, list):
        for k, v in enumerate(obj):
            yield from _json_paths(v, path + (k,))


JSON_VALUES = st.one_of(
    st.sampled_from([0, -1, 1e308, -1e308, 1e-308, 5e-324, 1e150, 1e-150, 2 ** 63, 10 ** 30, 0.5, True, None, "x", [],
                     {}, [1e308, 1e308], [0, 0], [1, 2, 3]]),
    st.floats(allow_nan=False, allow_infinity=False), st.integers(), st.text(max_size=4))


@st.composite
def mutated_json(draw, obj) -> bytes:
    """A JSON document with one value replaced, a key removed or added, or the text mutated."""
    obj = json.loads(json.dumps(obj))
    how = draw(st.sampled_from(["value", "value", "drop", "add", "text"]))
    if how == "text":
        return draw(mutated_text(json.dumps(obj, indent=1)))
    paths = [p for p in _json_paths(obj) if p]
    path = draw(st.sampled_from(paths))
    parent = obj
    for k in path[:-1]:
        parent = parent[k]
    if how == "value":
        parent[path[-1]] = draw(JSON_VALUES)
    elif how == "drop":
        del parent[path[-1]]
    elif isinstance(parent, dict):
        parent[draw(st.sampled_from(["max_events", "frame_rate", "max_frame_rate", "zz", "tolerance"]))] = \
            draw(JSON_VALUES)
    return json.dumps(obj).encode()


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


_TRACE: list[str] = []


def cradle_trace(workdir) -> str:
    """The trace of Newton's cradle (made once)."""
    if not _TRACE:
        scene = os.path.join(ROOT, "examples", "newtons-cradle.json")
        out = workdir / "cradle.jsonl"
        code, _, err = run(["simulate", "--lang", "c", scene, "-o", out, "-q"])
        assert code == 0, err
        _TRACE.append(out.read_text())
    return _TRACE[0]


def _file(workdir, name: str, data: bytes) -> str:
    p = workdir / name
    p.write_bytes(data)
    return str(p)


# ------------------------------------------------------------------ the fuzz tests
@budget(12)
@given(st.data())
def test_fuzz_mxm(workdir, data):
    base = data.draw(st.sampled_from(MXM))
    src = _file(workdir, data.draw(st.sampled_from(["f.mxm", "int.mxm", "9 lives.mxm"])), data.draw(mutated_text(base)))
    lang = data.draw(st.sampled_from(["c", "python", "rust", "m2"]))
    extra = data.draw(st.lists(st.sampled_from([["--no-line"], ["--naive"], ["--no-variants"], ["-D", "order=3"],
                                                ["-D", "order=0"], ["--exact"], ["--real=float"],
                                                ["--effects=none"], ["--list-variants"]]), max_size=2))
    out = str(workdir / f"gen.{lang}")
    if os.path.exists(out):
        os.unlink(out)
    argv = [f"--lang={lang}", src, "-o", out, "-q", "--maxima-timeout", "10"] + [a for e in extra for a in e]
    code, _, _ = run(argv)
    if code == 0 and os.path.exists(out):
        if "--list-variants" in argv:
            json.loads(open(out, encoding="utf-8").read(), parse_constant=_no_constant)
        else:
            check_generated(out, lang)


@budget(15)
@given(st.data())
def test_fuzz_scene(workdir, data):
    name = data.draw(st.sampled_from(SCENES))
    with open(os.path.join(ROOT, "examples", name), encoding="utf-8") as fh:
        obj = json.load(fh)
    src = _file(workdir, "scene.json", data.draw(mutated_json(obj)))
    out = workdir / "trace.jsonl"
    if out.exists():
        out.unlink()
    extra = data.draw(st.sampled_from([[], ["--no-frames"], ["--max-events", "50"]]))
    code, _, _ = run(["simulate", "--lang", "c", src, "-o", out, "-q", "--max-events", "3000"] + extra)
    if code == 0:
        check_json_lines(out.read_text(), "trace")
    elif out.exists():
        # a run that stopped keeps its trace up to the stop, closed by a "stopped" line
        text = out.read_text()
        check_json_lines(text, "trace")
        assert json.loads(text.splitlines()[-1])["kind"] == "stopped", "a stopped trace ends with its stop"


@budget(8)
@given(st.data())
def test_fuzz_trace(workdir, data):
    lines = cradle_trace(workdir).splitlines()
    k = data.draw(st.integers(0, len(lines) - 1))
    how = data.draw(st.sampled_from(["json", "text"]))
    if how == "json":
        lines[k] = data.draw(mutated_json(json.loads(lines[k]))).decode("utf-8", "replace")
        blob = ("\n".join(lines) + "\n").encode()
    else:
        blob = data.draw(mutated_text("\n".join(lines[max(0, k - 3):k + 3]) + "\n"))
    tr = _file(workdir, "trace-in.jsonl", blob)
    opts = data.draw(st.sampled_from([[], ["--fps", "1e9"], ["--speed", "0"], ["--width", "-3"], ["--fps", "nan"],
                                      ["--colour-by", "time"], ["--width", "1000000000"], ["--fps", "1e-300"],
                                      ["--gif", "--gif-fps", "1e9"]]))
    run(["render", os.path.join(ROOT, "examples", "newtons-cradle.json"), tr, "-o", workdir / "pic", "-q",
         "--no-overview"] + opts)


CASE = {"id": "c1", "op": "roots", "coeffs": [0.25, -1.0, 1.0], "lo": 0.0, "hi": 1.0, "expect": 0.5,
        "roots": [[0.5, 2, 5.960464477539063e-08]]}
TOC = {"id": "t1", "op": "toc", "equation": "circle-circle", "params": dict.fromkeys("abcdefmnopqghijklrsuvwxz", 0.5),
       "horizon": 1.0, "expect": None, "tol": 1e-9}


@budget(10)
@given(st.data())
def test_fuzz_cases(workdir, data):
    case = data.draw(st.sampled_from([CASE, TOC]))
    blob = data.draw(mutated_json(case))
    src = _file(workdir, "cases.jsonl", blob + b"\n" + json.dumps(CASE).encode() + b"\n")
    run(["conformance", "--lang", "python", "--cases", src, "--quiet"])


WORDS = ["simulate", "render", "conformance", "--lang", "-l", "c", "python", "zz", "-o", "-",
         "-D", "order=2", "order", "=", "--effects", "none,orbit", "--real", "float", "--exact", "--no-line",
         "--maxima-timeout", "0", "1e9", "-5", "--cases", "--max-events", "--no-frames", "--fps", "--quiet", "-q",
         "--help", "", " ", "é", "--", "-", "x.mxm"]


@budget(25)
@given(st.lists(st.one_of(st.sampled_from(WORDS), st.text(max_size=5), st.sampled_from(["@MXM", "@SCENE", "@CASES"])),
                max_size=7))
def test_fuzz_argv(workdir, argv):
    files = {"@MXM": os.path.join(ROOT, "tests", "data", "fuzz.mxm"),
             "@SCENE": os.path.join(ROOT, "examples", "resting-ball.json"),
             "@CASES": _file(workdir, "one.jsonl", json.dumps(CASE).encode() + b"\n")}
    if not os.path.exists(files["@MXM"]):
        files["@MXM"] = _file(workdir, "fuzz.mxm", MXM[0].encode())
    argv = [files.get(a, a) for a in argv]
    # never write into the project: outputs go to the work folder
    argv = [str(workdir / "argv-out") if i > 0 and argv[i - 1] == "-o" and a not in ("-", "") else a
            for i, a in enumerate(argv)]
    if argv and argv[0] in ("conformance",) and "--cases" not in argv:
        argv += ["--cases", files["@CASES"]]
    if argv and argv[0] == "simulate":
        argv += ["--max-events", "2000"]
    run(argv + ["--maxima-timeout", "10"] if argv and argv[0] not in ("simulate", "render", "conformance") else argv)
