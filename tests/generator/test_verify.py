"""Verified output (max2code/generate/verify.py): every printed function is
checked against Maxima's polynomial before anything is written.  Faults
planted in the lowering must be reported as internal errors naming the
function; random equations must give variants equal to the full equation
under their conditions."""
import os
import random
import tempfile
from fractions import Fraction

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import ROOT
import max2code.generate.exact as exact_mod
import max2code.generate.lower as lower_mod
import max2code.generate.pipeline as pipeline_mod
from max2code import cli
from max2code.errors import InternalError
from max2code.generate.pipeline import GenerateRequest, generate_file
from refpoly import compare, poly_by_power, run_python, substitute_zeros, trig_env

SEGMENT = os.path.join(ROOT, "tests", "data", "equations", "segment-end.mxm")
POINT_LINE = os.path.join(ROOT, "equations", "point-line.mxm")


def generate(path, **kw):
    return generate_file(GenerateRequest(path=path, lang="python", out_name="generated.py", **kw))


# ---------------------------------------------------------------- the root cause
def test_a_product_of_two_negated_factors_is_not_negated():
    a, b = ("ref", "a"), ("ref", "b")
    assert lower_mod.mul(("neg", a), ("neg", b)) == ("*", a, b)
    assert lower_mod.mul(("neg", a), b) == ("neg", ("*", a, b))
    assert lower_mod.mul(a, ("neg", b)) == ("neg", ("*", a, b))
    assert lower_mod.mul(lower_mod.lit(-2), ("neg", b)) == ("*", lower_mod.lit(2), b)


_mul = lower_mod.mul


def old_mul(a, b):
    """A faulty mul: a negation of either factor negates the product, so
    (-a)*(-b) gives -(a*b)."""
    if a[0] == "neg" or b[0] == "neg":
        return lower_mod.neg(_mul(a[1] if a[0] == "neg" else a, b[1] if b[0] == "neg" else b))
    return _mul(a, b)


# ---------------------------------------------------------------- planted faults
def test_the_sign_fault_of_the_spinning_segment_is_caught(monkeypatch):
    monkeypatch.setattr(lower_mod, "mul", old_mul)
    with pytest.raises(InternalError, match=r"the generated function segment_end_no_accel1\w* differs from Maxima's "
                                            r"polynomial \(where gx = gy( = rc)? = 0\) in the coefficient of t\^6"):
        generate(SEGMENT, options={"order": "6"})
    # without the check the same fault is printed silently: the check is what catches it
    generate(SEGMENT, options={"order": "6"}, verify=False)


def test_a_dropped_term_is_caught(monkeypatch):
    numeric = lower_mod.Lowering.numeric

    def dropping(self, p):
        out = numeric(self, p)
        if len(out) > 2:
            del out[max(out)]
        return out

    monkeypatch.setattr(lower_mod.Lowering, "numeric", dropping)
    with pytest.raises(InternalError, match=r"the generated function point_line\w* differs from Maxima's polynomial.* "
                                            r"coefficient of t\^\d"):
        generate(POINT_LINE)


def test_a_wrongly_rounded_literal_is_caught(monkeypatch):
    lit = lower_mod.lit

    def off_by_an_ulp(v):
        n = lit(v)
        if n[0] == "lit" and n[1] not in (0.0, 1.0, 2.0):
            return ("lit", n[1] * (1 + 2 ** -52), n[2])
        return n

    monkeypatch.setattr(lower_mod, "lit", off_by_an_ulp)
    with pytest.raises(InternalError, match=r"the generated function point_line\w*: the literal .* is not the double "
                                            r"nearest"):
        generate(POINT_LINE)


def test_a_fault_in_the_shared_temporaries_is_caught(monkeypatch):
    share = lower_mod.share

    def swapped(roots, reserved, prefix="w"):
        temps, coeffs = share(roots, reserved, prefix)
        if len(coeffs) > 2:
            coeffs[1], coeffs[2] = coeffs[2], coeffs[1]
        return temps, coeffs

    monkeypatch.setattr(lower_mod, "share", swapped)
    with pytest.raises(InternalError, match=r"the generated function point_line\w* differs .* coefficient of t\^1"):
        generate(POINT_LINE)


def test_a_fault_in_the_exact_gap_is_caught(monkeypatch):
    lower_expr = exact_mod.lower_expr
    calls = []

    def negated_once(e, t):      # the first call is the whole gap's (the rest are its parts')
        first = not calls
        calls.append(e)
        n = lower_expr(e, t)
        return lower_mod.neg(n) if first else n

    monkeypatch.setattr(exact_mod, "lower_expr", negated_once)
    with pytest.raises(InternalError, match=r"the generated function point_line_gap differs from Maxima's expression"):
        generate(POINT_LINE, exact=True)


def test_a_fault_in_the_selection_is_caught(monkeypatch):
    build = pipeline_mod.build_selection

    def cheapest_everywhere(name, variants, switches, effects):
        s = build(name, variants, switches, effects)
        cases = list(s.cases)
        masks = tuple(m for c in cases for m in c.masks)
        first = cases[0]
        return type(s)(s.name, s.switches, (type(first)(first.name, first.degree, masks),), s.max_degree, s.effects,
                       s.complete)

    monkeypatch.setattr(pipeline_mod, "build_selection", cheapest_everywhere)
    with pytest.raises(InternalError, match=r"point_line_coefficients selects point_line_\w+ for the switches [\w+]+, "
                                            r"but it is exact only when"):
        generate(POINT_LINE)


def test_the_command_line_reports_it_in_one_line_with_status_2_and_writes_nothing(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(lower_mod, "mul", old_mul)
    out = tmp_path / "segment.c"
    status = cli.main(["--lang=c", SEGMENT, "-o", str(out), "-q", "-D", "order=7"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "segment-end.mxm:" in err and "internal error: the generated function segment_end_no_accel1" in err
    assert "no file was written" in err
    assert not out.exists() and not (tmp_path / "segment.h").exists()


@pytest.mark.slow
def test_the_bundled_equations_pass_in_every_form(generated):
    for eq in ("circle-circle", "point-line"):
        for kw in ({}, {"exact": True}, {"shared": False}, {"variants": False}, {"effects": ("acceleration",)}):
            generated(eq, "python", **kw)      # raises InternalError on a mismatch


# ---------------------------------------------------------------- random equations
AXES = ("x", "y")


@st.composite
def equations(draw):
    """A .mxm text: two bodies in 1 or 2 dimensions, each with a random set of
    effects, an orbit's sin and cos as Taylor sums of a random order 1..8."""
    dim = draw(st.integers(1, 2))
    order = draw(st.integers(1, 8))
    squared = dim == 2 or draw(st.booleans())
    params, coords = [], {}
    for b in (1, 2):
        vel = b == 1 or draw(st.booleans())        # something must move
        acc, orb, rad = draw(st.booleans()), draw(st.booleans()), draw(st.booleans())
        for ax in AXES[:dim]:
            params.append((f"p{b}{ax}", b, "position"))
            x = f"p{b}{ax}"
            if vel:
                params.append((f"v{b}{ax}", b, "velocity"))
                x += f" + v{b}{ax}*t"
            if acc:
                params.append((f"a{b}{ax}", b, "acceleration"))
                x += f" + a{b}{ax}*t^2/2"
            coords[b, ax] = x
        if orb:
            params += [(f"d{b}", b, "orbit_radius"), (f"w{b}", b, "angular_velocity"), (f"f{b}", b, "phase")]
            for ax in AXES[:dim]:
                trig = "COS" if ax == "x" and dim == 2 else "SIN"
                coords[b, ax] += f" + d{b}*{trig}(w{b}, f{b})"
        if rad:
            params.append((f"r{b}", b, "radius"))
    radii = " + ".join(f"r{b}" for b in (1, 2) if any(p[0] == f"r{b}" for p in params)) or "0"
    diffs = [f"(({coords[1, ax]}) - ({coords[2, ax]}))" for ax in AXES[:dim]]
    gap = (" + ".join(f"{d}^2" for d in diffs) + f" - ({radii})^2") if squared else f"{diffs[0]} - ({radii})"
    lines = ["equation random_gap \"a random gap\"", f"option order = {order} in 1..8 \"Taylor order\""]
    lines += [f"parameter {n} \"{n}\" : body {b} {e}" for n, b, e in params]
    lines += ["begin",
              "C(X) := sum((-1)^k * X^(2*k) / (2*k)!, k, 0, floor(order/2)) $",
              "S(X) := sum((-1)^k * X^(2*k+1) / (2*k+1)!, k, 0, floor((order-1)/2)) $",
              "COS(w, p) := cos(p)*C(w*t) - sin(p)*S(w*t) $",
              "SIN(w, p) := sin(p)*C(w*t) + cos(p)*S(w*t) $",
              gap + " ;", "end", ""]
    return "\n".join(lines)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=equations(), seed=st.integers(0, 2 ** 32))
def test_every_variant_of_a_random_equation_equals_the_full_equation_under_its_conditions(text, seed):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "random.mxm")
        with open(path, "w") as fh:
            fh.write(text)
        out = generate(path)                      # the check inside raises on any mismatch
    ns = run_python(out.text)
    full = poly_by_power(out.derivation.polynomial)
    params = out.function.params
    rng = random.Random(seed)
    assert out.variants
    for v in out.variants:
        expected = substitute_zeros(full, v.zeros)
        for _ in range(2):
            point = {p: Fraction(rng.choice([-1, 1]) * rng.randint(2, 64), 32) for p in params}
            point.update({z: Fraction(0) for z in v.zeros})
            got = ns[v.name](*(float(point[p]) for p in params))
            assert not compare(got, expected, trig_env(point)), (v.name, text)
