"""`max2code --exact` on equations whose polynomial is already the exact gap
(no rotation: tests/data/user-equations/): NAME_toc_exact on the polynomial
directly, with the windowed driver's contract (approaching root, overlapped
at t = 0, none); what is refused and that no error names an internal symbol."""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import mpmath
import pytest

from conftest import ROOT
from max2code.errors import SourceError
from max2code.generate.pipeline import GenerateRequest, generate_file

USER = os.path.join(ROOT, "tests", "data", "user-equations")


def _gen(path, lang="python", **kw):
    return generate_file(GenerateRequest(path=path, lang=lang, out_name="generated", exact=True, **kw))


def _module(tmp_path, name):
    g = _gen(os.path.join(USER, name + ".mxm"))
    f = tmp_path / f"{name.replace('-', '_')}.py"
    f.write_text(g.text)
    spec = importlib.util.spec_from_file_location(f.stem, f)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return g, mod


@pytest.mark.parametrize("lang", ["c", "python", "rust", "m2"])
def test_exact_gap_equations_get_toc_exact_without_windows(lang):
    g = _gen(os.path.join(USER, "sphere-sphere.mxm"), lang)
    assert g.exact.polynomial and g.exact.shift is None and g.exact.rate is None
    text = g.text
    assert "sphere_sphere_toc_exact" in text and "sphere_sphere_gap" in text
    assert "sphere_sphere_shift" not in text and "sphere_sphere_truncation" not in text
    driver = {"c": "m2c_exact_poly_toc", "python": "_poly_toc", "rust": "exact::poly_toc", "m2": "ExactToc.PolyContact"}
    assert driver[lang] in text


def test_toc_exact_contract_on_the_polynomial(tmp_path):
    """Two spheres: the first approaching root, 0 when touching and
    approaching, overlapped when inside each other at t = 0, none when they
    miss; a separating contact at t = 0 is left behind."""
    from max2code_rt.exact import OVERLAPPED

    g, m = _module(tmp_path, "sphere-sphere")
    names = g.exact.params

    def call(horizon=5.0, **p):
        full = dict.fromkeys(names, 0.0)
        full.update(p)
        return m.sphere_sphere_toc_exact(*[full[n] for n in names], horizon)

    # sphere 2 at x = 5 coming at 1 m/s, radii 1 + 1: contact at t = 3 exactly
    assert call(d=5.0, u2=-1.0, r1=1.0, r2=1.0) == 3.0
    # the same with an acceleration: the root of (5 - t - t^2/4)^2 - 4 in (0, 5], by mpmath
    want = min(r for r in (mpmath.findroot(lambda t: 5 - t - t ** 2 / 4 - 2, 1),) if 0 < r <= 5)
    got = call(d=5.0, u2=-1.0, p2=-0.5, r1=1.0, r2=1.0)
    assert abs(got - float(want)) <= 1e-15 * float(want), (got, want)
    # inside each other at t = 0, moving apart: overlapped, never the time the overlap ends
    assert call(d=1.0, u2=3.0, r1=1.0, r2=1.0) is OVERLAPPED
    # touching at t = 0: approaching is a contact at 0; separating is left behind (then none)
    assert call(d=2.0, u2=-1.0, r1=1.0, r2=1.0) == 0.0
    assert call(d=2.0, u2=1.0, r1=1.0, r2=1.0) is None
    # touching and separating, then turned back by an acceleration: the next approach counts
    back = call(d=2.0, u2=1.0, p2=-1.0, r1=1.0, r2=1.0)
    assert back == pytest.approx(2.0, rel=1e-15)
    # a miss (closest distance 3 > 2) and a contact beyond the horizon
    assert call(d=5.0, e=3.0, u2=-1.0, r1=1.0, r2=1.0) is None
    assert call(horizon=2.0, d=5.0, u2=-1.0, r1=1.0, r2=1.0) is None


def test_ball_in_arena_and_quintic_floor(tmp_path):
    from max2code_rt.exact import OVERLAPPED

    _, arena = _module(tmp_path, "ball-arena")
    # x, y, vx, vy, ax, ay, r, R: at the centre at 2 m/s, wall 5 m away for the ball's centre: t = 2.5
    assert arena.ball_arena_toc_exact(0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0, 6.0, 10.0) == 2.5
    assert arena.ball_arena_toc_exact(7.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 6.0, 10.0) is OVERLAPPED
    _, floor = _module(tmp_path, "point-floor-quintic")
    # y = 1 - t^5/120 * 120 = 1 - t^5: reaches the floor at t = 1 exactly
    assert floor.point_floor_toc_exact(1.0, 0.0, 0.0, 0.0, 0.0, -120.0, 3.0) == 1.0


TEXT = """parameter y "height (m)" : body 1 position
parameter v "velocity (m/s)" : body 1 velocity
parameter g "gravity (m/s^2)"
parameter r "radius (m)" : body 1 radius
{decl}begin
{body}end
"""


def test_what_is_refused_says_why_at_its_line(tmp_path):
    p = tmp_path / "eq.mxm"
    # a Taylor sum in the text: the polynomial approximates something
    p.write_text(TEXT.format(decl="", body="C(X) := sum(X^k/k!, k, 0, 3) $\ny + v*t*C(g) - r ;\n"))
    with pytest.raises(SourceError) as exc:
        _gen(str(p))
    assert exc.value.span.line == 6 and "sum(...)" in exc.value.message and "'exact NAME(args)" in exc.value.message
    # a rotation's role: the polynomial approximates the rotation
    p.write_text(TEXT.replace('"gravity (m/s^2)"', '"phase (rad)" : body 1 phase').format(decl="", body="y + v*t - r ;\n"))
    with pytest.raises(SourceError) as exc:
        _gen(str(p))
    assert exc.value.span.line == 3 and "phase" in exc.value.message


def test_an_exact_declaration_of_a_polynomial_motion_works_and_errors_name_no_internal_symbol(tmp_path):
    """A polynomial declared as its own exact expression (MOVE below) has no
    error term and no rate: one window.  Errors show MOVE(...), never the
    helper names max2code gives Maxima."""
    p = tmp_path / "eq.mxm"
    decl = "exact MOVE(p, u, a) { p + u*t + a*t^2/2 }\nshift y { y + v*t - g*t^2/2 }\nshift v { v - g*t }\n"
    body = "MOVE(p, u, a) := p + u*t + a*t^2/2 $\nMOVE(y, v, -g) - r ;\n"
    p.write_text(TEXT.format(decl=decl, body=body))
    g = _gen(str(p))
    assert not g.exact.polynomial and "eq_toc_exact" in g.text
    assert g.text.split("def eq_rate(")[1].split("\n\n")[0].endswith("rate = 0.0\n    return rate")  # one window
    # a wrong exact expression: Maxima's difference in the file's own names
    bad = tmp_path / "bad.mxm"
    wrong = "exact MOVE(p, u, a) { p + u*t + a*t^2 }\nshift y { y + v*t - g*t^2 }\nshift v { v - 2*g*t }\n"
    bad.write_text(TEXT.format(decl=wrong, body=body))
    r = subprocess.run([sys.executable, "-m", "max2code", "--lang=c", "--exact", "-q", str(bad)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 1 and "'MOVE' is not the Taylor polynomial" in r.stderr, r.stderr
    assert "a*t^2" in r.stderr and "__m2c" not in r.stderr and r.stderr.count("\n") == 1, r.stderr


@pytest.mark.slow
def test_rust_compiles_a_parameter_named_in_capitals(tmp_path):
    """The arena's radius R beside the ball's r: Rust's naming lint must not stop the user's names."""
    from max2code.toolchain.exact import build_exact_harness

    g = _gen(os.path.join(USER, "ball-arena.mxm"), "rust")
    assert "#![allow(non_snake_case)]" in g.text
    h = build_exact_harness("rust", g.text, g.exact, str(tmp_path))
    got, _ = h.run([[0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0, 6.0, 10.0, 1.0, 1.0, 0.0, 0.0]])
    assert got == [(1, 2.5)]
    plain = _gen(os.path.join(USER, "sphere-sphere.mxm"), "rust")
    assert "non_snake_case" not in plain.text
