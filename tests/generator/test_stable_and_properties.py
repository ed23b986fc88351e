"""Byte-stable output, and property-based tests of both parsers."""
import os
from pathlib import Path
import subprocess
import sys
from fractions import Fraction

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import LANGS
from max2code.errors import SourceError
from max2code.generate.expr import Add, Mul, Num, Pow, Sym, to_maxima, to_poly
from max2code.generate.mxm import parse_mxm
from max2code.generate.reader import MaximaOutputError, read_expr

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_generating_twice_gives_identical_bytes(tmp_path, lang):
    outs = []
    for i, cache in enumerate(["--no-cache", ""]):
        (tmp_path / str(i)).mkdir()
        out = tmp_path / str(i) / "circle-circle.out"
        args = [sys.executable, "-m", "max2code", f"--lang={lang}", "equations/circle-circle.mxm", "-o", str(out), "-q"]
        env = dict(os.environ, MAX2CODE_CACHE=str(tmp_path / "cache"))
        subprocess.run(args + ([cache] if cache else []), check=True, cwd=ROOT, env=env)
        outs.append(out.read_bytes())
    # the second run reads Maxima's result from the cache: the bytes must not change
    assert outs[0] == outs[1]
    assert b"\r" not in outs[0]


# ---- the .mxm parser: any text gives a module or a SourceError, never a crash
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(list("{}%/\n \tabt01;$\"=*+-") + ["begin", "end", "term ", "polynomial terms ",
                                                                  "initialise ", "finalise ", "parameter ", "option ", "for c "]),
                max_size=30).map("".join))
def test_mxm_parser_never_crashes(text):
    try:
        m = parse_mxm(text, "fuzz.mxm")
    except SourceError as exc:
        assert str(exc).startswith("fuzz.mxm:")
        assert exc.span.line >= 1 and exc.span.column >= 1
        assert exc.span.line <= text.count("\n") + 1
    else:
        assert m.maxima_text.strip()


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 12), st.sampled_from(["", " for c", " for m2"])), min_size=1, max_size=6),
       st.integers(1, 6))
def test_term_blocks_in_order_parse_and_out_of_order_fail(terms, n):
    text = f"polynomial terms {n}\n" + "".join(f"term {k}{tag} {{ x }}\n" for k, tag in terms) + "begin\nt;\nend\n"
    per_tag = {}
    for k, tag in terms:
        per_tag.setdefault(tag, []).append(k)
    ordered = all(v == list(range(len(v))) for v in per_tag.values())
    counts_ok = all(len(v) == n for v in per_tag.values())
    if ordered and counts_ok:
        parse_mxm(text, "x.mxm")
    else:
        with pytest.raises(SourceError):
            parse_mxm(text, "x.mxm")


# ---- the Maxima-output reader: printing a random polynomial Maxima's way
# and reading it back gives the same polynomial
SYMS = ["a", "b", "t", "%pi", "x1"]


@st.composite
def exprs(draw, depth=3):
    if depth == 0 or draw(st.booleans()):
        if draw(st.booleans()):
            return Num(Fraction(draw(st.integers(-50, 50)), draw(st.integers(1, 9))))
        return Sym(draw(st.sampled_from(SYMS)))
    kind = draw(st.sampled_from(["add", "mul", "pow"]))
    if kind == "pow":
        return Pow(draw(exprs(depth - 1)), Num(Fraction(draw(st.integers(0, 3)))))
    items = tuple(draw(st.lists(exprs(depth - 1), min_size=2, max_size=3)))
    return Add(items) if kind == "add" else Mul(items)


@settings(max_examples=300, deadline=None)
@given(exprs())
def test_reader_round_trips_expressions(e):
    text = to_maxima(e)
    back = read_expr(text)
    assert to_poly(back)[0] == to_poly(e)[0]


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("ab t%pi()+-*/^=,.0123'456789e")), max_size=40))
def test_reader_rejects_or_reads_never_crashes(text):
    try:
        read_expr(text)
    except MaximaOutputError as exc:
        assert exc.column >= 1


def test_reader_precedence_and_exact_numbers():
    e = read_expr("-a^2*b/3+2.5e-1*t^-1")
    terms, _ = to_poly(e)
    assert terms == {(("a", 2), ("b", 1)): Fraction(-1, 3), (("t", -1),): Fraction(1, 4)}
    assert to_poly(read_expr("2^3^2"))[0] == {(): Fraction(512)}
