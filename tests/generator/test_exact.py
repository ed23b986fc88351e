"""The exact-motion entries (max2code --exact) and their knobs: errors in
the .mxm's exact/shift declarations, byte-stable output, single precision,
the knobs of the runtimes' driver, and the reference itself against a
brute-force scan.  (The conformance of the four runtimes runs with the other
cases in test_conformance.py: tests/conformance/toc_exact.jsonl.)"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path
import random
import subprocess
import sys

import mpmath
import pytest

from max2code.conformance import exact_op
from max2code.conformance.exact_ref import Gap, reference
from max2code.errors import Max2CodeError, SourceError
from max2code.toolchain.exact import build_exact_harness
from max2code.generate.pipeline import GenerateRequest, generate_file

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
CASES = [json.loads(line) for line in open(os.path.join(ROOT, "tests", "conformance", "toc_exact.jsonl"))]

HEAD = """parameter a "line end"  : body 1 position
parameter b "its velocity" : body 1 velocity
parameter d "orbit radius" : body 1 orbit_radius
parameter e "angular velocity" : body 1 angular_velocity
parameter f "phase" : body 1 phase
parameter g "point" : body 2 position
"""
MAXIMA = """begin
C(X) := 1 - X^2/2 $
S(X) := X - X^3/6 $
SIN(w, phi) := sin(phi)*C(w*t) + cos(phi)*S(w*t) $
a + b*t + d*SIN(e, f) - g ;
end
"""
GOOD = 'exact SIN(w, phi) { sin(w*t + phi) }\nshift a { a + b*t }\nshift f { f + e*t }\n'


def _generate(tmp_path, text, lang="c", **kw):
    p = tmp_path / "eq.mxm"
    p.write_text(text)
    return generate_file(GenerateRequest(path=str(p), lang=lang, exact=True, out_name="generated", **kw))


@pytest.mark.parametrize("decl,line,col,words", [
    ('exact FOO(w, phi) { sin(w*t + phi) }\nshift a { a + b*t }\n', 7, 7, "defines no function 'FOO'"),
    (GOOD + 'shift q { q }\n', 10, 7, "'q' is not a parameter"),
    ('exact SIN(w, phi) { sin(w*t + phi) }\nshift a { a + b*t }\nshift f { f + 2*e*t }\n', 8, 7, "do not restart the clock"),
    ('exact SIN(w, phi) { sin(w*t + phi) }\n', 7, 7, "needs 'shift' declarations"),
    ('exact SIN(w, phi) { sin(2*w*t + phi) }\nshift a { a + b*t }\nshift f { f + 2*e*t }\n', 7, 7,
     "not the Taylor polynomial"),
    ('exact SIN(w, w) { sin(w*t) }\n', 7, 14, "appears twice"),
    (GOOD + 'shift a { a }\n', 10, 7, "declared twice"),
    ('shift a {   }\n', 7, 10, "needs its value"),
])
def test_exact_declaration_errors(tmp_path, decl, line, col, words):
    with pytest.raises(SourceError) as exc:
        _generate(tmp_path, HEAD + decl + MAXIMA)
    assert (exc.value.span.line, exc.value.span.column) == (line, col), str(exc.value)
    assert words in exc.value.message


def test_exact_without_declarations_and_python_float(tmp_path):
    with pytest.raises(SourceError, match="needs an 'exact NAME"):
        _generate(tmp_path, HEAD + MAXIMA)
    with pytest.raises(Max2CodeError, match="python has no single-precision"):
        _generate(tmp_path, HEAD + GOOD + MAXIMA, lang="python", real="float")


@pytest.mark.slow
def test_cli_exact_is_byte_stable_and_errors_are_one_line(tmp_path):
    outs = []
    for _ in range(2):
        r = subprocess.run([sys.executable, "-m", "max2code", "--lang=rust", "--exact", "-q", "equations/point-line.mxm"],
                           capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 0, r.stderr
        outs.append(r.stdout)
    assert outs[0] == outs[1] and "point_line_toc_exact" in outs[0] and "POINT_LINE_MOTION" in outs[0]
    bad = tmp_path / "bad.mxm"
    bad.write_text(HEAD + 'exact SIN(w, phi) { sin(w*t + phi) }\nshift f { f + 3*e*t }\n' + MAXIMA)
    r = subprocess.run([sys.executable, "-m", "max2code", "--lang=c", "--exact", "-q", str(bad)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 1 and r.stderr.count("\n") == 1 and f"{bad}:8:7: error:" in r.stderr and "__m2c" not in r.stderr, r.stderr


def _rows(equation, cases, params, **opts):
    return [exact_op.row(dict(c, options=dict(c.get("options", {}), **opts)), params) for c in cases]


@pytest.fixture(scope="module")
def point_line_c(tmp_path_factory):
    g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", "point-line.mxm"), lang="c",
                                      out_name="generated", exact=True))
    return g, build_exact_harness("c", g.text, g.exact, str(tmp_path_factory.mktemp("pl-c")))


PL = [c for c in CASES if c["equation"] == "point-line"]
PL_REGULAR = [c for c in PL if c["regular"] and c["expect"] is not None and "options" not in c]


@pytest.mark.slow
def test_knob_gsl_solver_gives_accepted_answers(point_line_c):
    g, h = point_line_c
    rows = _rows("point-line", PL, g.exact.params)
    for r in rows:
        r[-1] = 1.0     # GSL's companion-matrix solver
    got, _ = h.run(rows)
    bad = [c["id"] for c, (st, t) in zip(PL, got)
           if not exact_op.judge(c, {1: repr(t), 0: "none", 2: "overlapped"}.get(st, "unsupported")).ok]
    # the margins leave GSL's 1e-7 imaginary-part threshold nothing to decide wrongly here
    assert bad == [], bad


@pytest.mark.slow
def test_knob_refine_off_and_window_angle(point_line_c):
    """Without refinement each window's polynomial answers: the error falls
    as the window angle shrinks (order 4: about angle^5)."""
    g, h = point_line_c
    cases = [c for c in PL_REGULAR if c["kind"] in ("random", "fast")]
    worst = {}
    for angle in (1.0, 0.25, 0.0625):
        got, _ = h.run(_rows("point-line", cases, g.exact.params, window_angle=angle, refine=False))
        errs = [abs(t - c["expect"]) / c["expect"] for c, (st, t) in zip(cases, got) if st == 1]
        assert len(errs) >= len(cases) - 2
        worst[angle] = max(errs)
    assert worst[1.0] > worst[0.25] > worst[0.0625]
    assert worst[0.0625] < 1e-7 and worst[1.0] > 1e-9
    got, _ = h.run(_rows("point-line", cases, g.exact.params))
    assert max(abs(t - c["expect"]) / c["expect"] for c, (st, t) in zip(cases, got)) <= 1e-12


@pytest.mark.slow
def test_bad_options_are_errors(point_line_c):
    g, h = point_line_c
    c = PL_REGULAR[0]
    got, _ = h.run(_rows("point-line", [c, c], g.exact.params, window_angle=0.0)[:1] +
                   _rows("point-line", [c], g.exact.params, zero_tol=-1.0))
    assert [st for st, _ in got] == [-1, -1]


@pytest.mark.slow
def test_zero_tol_knob_decides_touching_at_zero(point_line_c):
    """A gap of 1e-6 at t = 0, decreasing: a contact at 0 when zero_tol covers it."""
    g, h = point_line_c
    p = {"a": 1e-6, "b": -1.0, "c": 0.0, "d": 0.0, "e": 0.0, "f": 0.0, "g": 0.0, "h": 0.0, "i": 0.0,
         "j": 0.0, "k": 0.0, "l": 0.0}
    case = {"params": p, "horizon": 1.0}
    got, _ = h.run(_rows("point-line", [case], g.exact.params, zero_tol=1e-5) +
                   _rows("point-line", [case], g.exact.params))
    assert got[0] == (1, 0.0) and got[1][0] == 1 and abs(got[1][1] - 1e-6) < 1e-20


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["c", "rust", "m2"])
def test_single_precision(lang, tmp_path):
    """--real=float: the generated arithmetic in float (C), f32 (Rust),
    SHORTREAL (Modula-2); it compiles warning-free and answers to about
    float precision."""
    g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", "point-line.mxm"), lang=lang,
                                      out_name="generated", exact=True, real="float"))
    assert {"c": "float a", "rust": "as f32", "m2": "SHORTREAL"}[lang] in g.text
    h = build_exact_harness(lang, g.text, g.exact, str(tmp_path))
    cases = [c for c in PL_REGULAR if c["kind"] == "random"]
    got, _ = h.run(_rows("point-line", cases, g.exact.params))
    errs = [abs(t - c["expect"]) / c["expect"] for c, (st, t) in zip(cases, got) if st == 1]
    assert len(errs) >= len(cases) - 2
    assert 1e-12 < max(errs) < 1e-3


def test_python_driver_api():
    from max2code_rt.exact import exact_toc
    g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", "point-line.mxm"), lang="python",
                                      out_name="generated", exact=True))
    ns: dict = {}
    exec(compile(g.text, "generated.py", "exec"), ns)
    c = PL_REGULAR[0]
    p = [c["params"][k] for k in "abcdefghijkl"]
    t = ns["point_line_toc_exact"](*p, c["horizon"])
    assert abs(t - c["expect"]) <= 1e-12 * c["expect"]
    assert exact_toc(ns["POINT_LINE_MOTION"], p, c["horizon"], refine=False) != t
    with pytest.raises(ValueError):
        exact_toc(ns["POINT_LINE_MOTION"], p, c["horizon"], window_angle=-1.0)
    assert ns["point_line_toc_exact"](*p[:-1], float("nan"), c["horizon"]) is None
    # the generated gap is the exact one
    gp = Gap("point-line", c["params"], c["horizon"])
    for s in (0.0, 0.3, 1.7):
        assert abs(ns["point_line_gap"](*p, s) - float(gp.G(s))) <= 1e-14 * float(gp.S(s))
        assert abs(ns["point_line_gap_dt"](*p, s) - float(gp.G1(s))) <= 1e-13 * float(gp.S(s) + 1)


def _gap_numpy(equation, p, t):
    """The gap written once more, in numpy doubles (for the scan only)."""
    import numpy as np

    def m(p0, v, acc, rad, w, ph):
        return p0 + v * t + acc * t * t / 2 + rad * np.sin(w * t + ph)
    if equation == "point-line":
        return m(*(p[k] for k in "abcdef")) - m(*(p[k] for k in "ghijkl"))
    dx = m(*(p[k] for k in "abcdef")) - m(*(p[k] for k in "ghijkl"))
    dy = m(*(p[k] for k in "mnodpq")) - m(*(p[k] for k in "rsujvw"))
    return dx * dx + dy * dy - (p["x"] + p["z"]) ** 2


@pytest.mark.slow
@pytest.mark.parametrize("equation", ["circle-circle", "point-line"])
def test_reference_against_a_brute_force_scan(equation):
    """The reference's first contact, against the first sign change of the
    gap on a dense grid (numpy doubles), refined by mpmath."""
    import numpy as np
    from max2code.conformance.exact_cases import _aim, _circle_random, _line_random, _point_below

    rng = random.Random(f"scan-{equation}")
    checked = overlapped = 0
    for _ in range(12):
        T = 3.0
        p = _aim(rng, (_circle_random if equation == "circle-circle" else _line_random)(rng, 8.0), equation, T, 1.3)
        if equation == "point-line" and rng.random() < 0.8:
            p = _point_below(p)          # mostly contacts; the rest may start past the line: overlapped
        ref = reference(equation, p, T)
        gp = Gap(equation, p, T)
        ts = np.linspace(0.0, T, 200001)
        v = _gap_numpy(equation, p, ts)
        if v[0] < 0.0 and float(-gp.G(0)) > float(gp.band(0)):
            assert ref.expect == "overlapped", (p, ref)     # inside each other at t = 0: never a contact
            overlapped += 1
            continue
        change = np.nonzero(np.signbit(v[1:]) != np.signbit(v[:-1]))[0]
        if len(change) == 0:
            assert ref.expect is None or ref.none_ok, (p, ref)
            continue
        i = int(change[0])
        with mpmath.workdps(40):
            first = mpmath.findroot(gp.G, (mpmath.mpf(ts[i]), mpmath.mpf(ts[i + 1])), solver="anderson")
        assert ref.expect is not None and abs(ref.expect - float(first)) <= 1e-12 * float(first), (p, ref, first)
        checked += 1
    assert checked >= 4
