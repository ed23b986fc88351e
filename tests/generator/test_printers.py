"""The printers, one node per line (no Maxima, no compiler): each test
fails in milliseconds when a target prints an expression differently."""
from __future__ import annotations

import pytest

from max2code.targets import LANGUAGES, target

x, y, z = ("ref", "x"), ("ref", "y"), ("ref", "z")


def lit(v):
    return ("lit", v)


def test_targets_are_the_only_list_of_languages():
    assert list(LANGUAGES) == ["python", "c", "rust", "m2"]
    for name, cls in LANGUAGES.items():
        assert cls.name == name and cls.extension and cls.requires and cls.links


def test_printer_is_configured_when_made():
    c = target("c")
    f = target("c", real="float")
    assert not c.single and f.single and c.renames == {} == f.renames
    assert f.expr(lit(0.1)) == "0.1f" and c.expr(lit(0.1)) == "0.1"     # two printers, neither changed
    with pytest.raises(ValueError):
        target("python", real="float")
    m = target("m2", real="float")
    assert m.float_copies(["x"]).expr(x) == "x_s" and m.expr(x) == "x"
    assert target("c", real="float").float_copies(["x"]).expr(x) == "x"   # C converts implicitly: no copies


@pytest.mark.parametrize("lang,node,text", [
    ("c", ("+", x, y), "x + y"),
    ("c", ("-", x, ("-", y, z)), "x - (y - z)"),
    ("c", ("-", ("-", x, y), z), "x - y - z"),
    ("c", ("*", ("+", x, y), z), "(x + y)*z"),
    ("c", ("/", x, ("*", y, z)), "x/(y*z)"),
    ("c", ("neg", x), "-x"),
    ("c", ("*", ("neg", x), y), "(-x)*y"),
    ("c", ("call", "sin", x), "sin(x)"),
    ("c", ("call", "abs", x), "fabs(x)"),
    ("c", lit(2.0), "2.0"),
    ("c", lit(1e-300), "1.0e-300"),
    ("c", lit(1.5e+300), "1.5e300"),
    ("m2", lit(1e-5), "1.0E-5"),
    ("m2", ("call", "abs", x), "ABS(x)"),
    ("m2", ("-", x, ("neg", y)), "x - (-y)"),
    ("python", ("call", "cos", x), "math.cos(x)"),
    ("python", ("call", "abs", x), "abs(x)"),
    ("rust", ("call", "sqrt", x), "f64::sqrt(x)"),
    ("rust", lit(3.0), "3.0"),
])
def test_one_node(lang, node, text):
    assert target(lang).expr(node) == text


@pytest.mark.parametrize("lang,node,text", [
    ("c", lit(0.1), "0.1f"),
    ("c", ("call", "sin", x), "sinf(x)"),
    ("rust", lit(0.1), "0.1_f32"),
    ("rust", ("call", "cos", x), "f32::cos(x)"),
    ("m2", ("call", "sin", x), "sinf(x)"),
])
def test_one_node_in_single_precision(lang, node, text):
    assert target(lang, real="float").expr(node) == text


@pytest.mark.parametrize("lang,text", [("c", "x == 0.0 && y == 0.0"), ("python", "x == 0.0 and y == 0.0"),
                                       ("rust", "x == 0.0 && y == 0.0"), ("m2", "(x = 0.0) AND (y = 0.0)")])
def test_zero_test(lang, text):
    assert target(lang).zero_test(["x", "y"]) == text


def test_literals_are_exact_and_never_integers():
    for v in (1.0, 0.1, 1 / 3, 2.0 ** -1074, 1.7976931348623157e308, 123456789.0):
        text = target("c").expr(lit(v))
        assert float(text) == v and ("." in text or "e" in text)
    with pytest.raises(ValueError):
        target("c").expr(lit(float("inf")))


def test_capabilities():
    assert {n for n, t in LANGUAGES.items() if t.header_extension} == {"c"}
    assert {t.gsl_baseline for t in LANGUAGES.values() if t.gsl_baseline} == {"gsl", "gsl-m2"}
    assert {n for n, t in LANGUAGES.items() if t.single_type is None} == {"python"}
    assert all(t.simulator for t in LANGUAGES.values())
