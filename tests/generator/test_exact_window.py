"""The generated window entry (NAME_window, docs/exact-motion.md): the
coefficients of the shifted parameters and the truncation bound over the
window in one function that computes the shared sines and cosines once.  It
must give the values of NAME_shift, NAME_coefficients and NAME_truncation
to the bit, for every variant the selection can pick, and the drivers must
answer the same with and without it."""
from __future__ import annotations

import dataclasses
import os
from pathlib import Path
import random

import pytest

from max2code.generate.pipeline import GenerateRequest, generate_file

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def _module(equation: str, **kw):
    g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", f"{equation}.mxm"), lang="python",
                                      out_name="generated", exact=True, **kw))
    ns: dict = {}
    exec(compile(g.text, "generated.py", "exec"), ns)
    return g, ns


def _draws(n: int, nparams: int, zeros: list[list[int]], seed: int):
    """Random parameters, some of whose groups are exactly zero (so that
    every switch of the selection is taken both ways)."""
    rng = random.Random(seed)
    for _ in range(n):
        p = [rng.uniform(-3.0, 3.0) for _ in range(nparams)]
        for group in zeros:
            if rng.random() < 0.5:
                for i in group:
                    p[i] = 0.0
        yield p, rng.uniform(0.0, 4.0), rng.uniform(1e-3, 0.7)


@pytest.mark.slow
@pytest.mark.parametrize("equation,variants", [("circle-circle", True), ("point-line", True),
                                               ("circle-circle", False)])
def test_window_is_shift_coefficients_and_truncation_to_the_bit(equation, variants):
    g, ns = _module(equation, variants=variants)
    name = g.exact.name
    window, shift = ns[f"{name}_window"], ns[f"{name}_shift"]
    coef = ns[f"{name}_coefficients" if variants else name]
    trunc = ns[f"{name}_truncation"]
    assert ns[f"{name.upper()}_MOTION"].window is not None
    params = list(g.exact.params)
    # the parameters each switch of the selection tests: zero them now and then
    groups = [[params.index(z) for z in zs] for _, zs in g.selection.switches] if g.selection else []
    assert groups or not variants
    degrees = set()
    for p, t0, h in _draws(400, len(params), groups, seed=31):
        q = shift(*p, t0)
        want_c, want_e = coef(*q), trunc(*q, h)
        got_c, got_e = window(*p, t0, h)
        assert [float(x).hex() for x in got_c] == [float(x).hex() for x in want_c]
        assert float(got_e).hex() == float(want_e).hex()
        degrees.add(len(want_c) - 1)
    if g.selection:
        assert len(degrees) >= 2      # variants of several degrees were taken


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["c", "rust", "m2", "python"])
def test_window_entry_is_generated_and_recorded(lang):
    """Every target but Modula-2 gets the window entry; Modula-2 records
    none (gm2's time grows with the square of a module's length, and the
    entry repeats every variant), so its driver calls the entries one by one."""
    g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", "circle-circle.mxm"), lang=lang,
                                      out_name="generated", exact=True))
    assert ("circle_circle_window" in g.text) == (lang != "m2")
    record = {"c": "circle_circle_window_v\n};", "rust": "window: Some(circle_circle_window_v)",
              "m2": ".hasWindow := FALSE", "python": "window=lambda p, t0, h: circle_circle_window(*p, t0, h)"}
    assert record[lang] in g.text
    # single precision: no window entry, the driver calls shift, coefficients and truncation
    if lang != "python":
        f = generate_file(dataclasses.replace(GenerateRequest(path=os.path.join(ROOT, "equations",
                                                                                "circle-circle.mxm"),
                                                              lang=lang, out_name="generated", exact=True),
                                              real="float"))
        assert "circle_circle_window" not in f.text


@pytest.mark.slow
@pytest.mark.parametrize("equation", ["circle-circle", "point-line"])
def test_python_driver_answers_the_same_without_the_window_entry(equation):
    """A motion without the window field (made by hand) takes shift,
    coefficients and truncation one by one: the same answers to the bit."""
    import json

    from max2code_rt.exact import exact_toc

    g, ns = _module(equation)
    motion = ns[f"{g.exact.name.upper()}_MOTION"]
    plain = dataclasses.replace(motion, window=None)
    cases = [json.loads(line) for line in open(ROOT / "tests" / "conformance" / "toc_exact.jsonl")]
    cases = [c for c in cases if c["equation"] == equation][:60]
    assert len(cases) == 60
    contacts = 0
    for c in cases:
        p = [c["params"][k] for k in g.exact.params]
        a = exact_toc(motion, p, c["horizon"])
        b = exact_toc(plain, p, c["horizon"])
        assert (a.hex() if isinstance(a, float) else a) == (b.hex() if isinstance(b, float) else b), c["id"]
        contacts += isinstance(a, float)
    assert contacts > 10
