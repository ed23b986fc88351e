"""Variants and their selection logic (the variants are derived automatically)."""
import functools
import json
import random
import subprocess
import sys

import mpmath
import pytest

from conftest import LANGS, ROOT
from max2code.toolchain.harness import build_harness
from max2code_rt.roots import smallest_root
from max2code.conformance.motion_ref import EQUATIONS as REFERENCE
from max2code.conformance.motion_ref import scale as reference_scale
from test_generated_code import SAMPLERS

ORDER = 4


def list_variants(eq, *extra):
    return json.loads(_list_variants_output(eq, *extra))


@functools.lru_cache(maxsize=None)
def _list_variants_output(eq, *extra):
    """`max2code --list-variants` run once per equation and options in this
    process (a circle-circle run takes about 5 s), its JSON read anew by each
    caller."""
    return subprocess.run([sys.executable, "-m", "max2code", "--list-variants", f"equations/{eq}.mxm", "-q", *extra],
                          capture_output=True, text=True, check=True, cwd=ROOT).stdout


def body_degree(off, body):
    """Degree in t of one body's coordinate: the orbit's Taylor order, else 2 with acceleration, else 1."""
    if f"no_orbit{body}" not in off:
        return ORDER
    return 1 if f"no_accel{body}" in off else 2


EXPECTED = {
    # squared distance: twice the larger coordinate degree; the line: the larger degree
    "circle-circle": lambda off: 2 * max(body_degree(off, 1), body_degree(off, 2)),
    "point-line": lambda off: max(body_degree(off, 1), body_degree(off, 2)),
}


@pytest.mark.slow
@pytest.mark.parametrize("eq", ["circle-circle", "point-line"])
def test_variant_degrees_follow_the_physics(eq):
    vs = list_variants(eq)
    for v in vs:
        assert v["degree"] == EXPECTED[eq](set(v["switched_off"])), v
        assert v["terms"] == v["degree"] + 1
        assert v["multiplications"] >= 0 and v["monomials"] > 0
    names = {v["name"]: v for v in vs}
    full = eq.replace("-", "_")
    assert names[full]["degree"] == (8 if eq == "circle-circle" else 4)
    assert names[f"{full}_no_orbit1_no_orbit2"]["degree"] == (4 if eq == "circle-circle" else 2)
    if eq == "circle-circle":
        assert names[f"{full}_no_accel1_no_orbit1_no_accel2_no_orbit2"]["degree"] == 2
        assert len(vs) == 64   # 6 switches, no two give the same polynomial
    else:
        assert names[f"{full}_no_accel1_no_orbit1_no_accel2_no_orbit2"]["degree"] == 1
    # cheapest first
    costs = [(v["degree"], v["multiplications"]) for v in vs]
    assert costs == sorted(costs)
    # a cheaper variant is never more general than a dearer one (dominated ones are dropped)
    for a in vs:
        for b in vs:
            if a is not b and set(a["conditions"]) <= set(b["conditions"]):
                assert (a["degree"], a["multiplications"]) > (b["degree"], b["multiplications"]), (a["name"], b["name"])


SWITCH_PARAMS = {
    "circle-circle": {"no_orbit1": ["d"], "no_accel1": ["c", "o"], "point1": ["x"],
                      "no_orbit2": ["j"], "no_accel2": ["i", "u"], "point2": ["z"]},
    "point-line": {"no_orbit1": ["d"], "no_accel1": ["c"], "no_orbit2": ["j"], "no_accel2": ["i"]},
}


def sample_with_effects_off(eq, rng):
    p = SAMPLERS[eq](rng)
    for names in SWITCH_PARAMS[eq].values():
        if rng.random() < 0.5:
            for n in names:
                p[n] = 0.0
    return p


@pytest.fixture(scope="module")
def entry_harness(generated, tmp_path_factory):
    """(file, its full coefficient function, its selection entry) of EQ in LANG:
    one harness program (build_harness) runs both."""
    cache = {}

    def get(eq, lang):
        if (eq, lang) not in cache:
            g = generated(eq, lang)
            d = str(tmp_path_factory.mktemp(f"entry-{eq}-{lang}"))
            full = build_harness(lang, g, d)
            assert g.selection.name == g.derivation.module.equation + "_coefficients"
            assert g.selection.max_degree == max(v.degree for v in g.variants)
            entry = build_harness(lang, g, d, mode="entry")
            cache[(eq, lang)] = (g, full, entry)
        return cache[(eq, lang)]
    return get


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("eq", ["circle-circle", "point-line"])
def test_selected_variant_equals_full_equation_with_the_zeros(eq, lang, entry_harness):
    g, full, entry = entry_harness(eq, lang)
    rng = random.Random(f"variants-{eq}-{lang}")
    sets = [sample_with_effects_off(eq, rng) for _ in range(500)]
    rows = [[s[n] for n in g.function.params] for s in sets]
    got_full = full.evaluate(rows)
    got_entry = entry.evaluate(rows)
    degrees = {}
    for s, f_row, e_row in zip(sets, got_full, got_entry):
        deg = int(e_row[0])
        coef = e_row[1:]
        assert len(coef) == deg + 1
        degrees[deg] = degrees.get(deg, 0) + 1
        ref = REFERENCE[eq](s, ORDER)
        sk = reference_scale(eq, s, ORDER)
        # the coefficients the selected variant drops are exactly zero in the equation
        assert all(r == 0 for r in ref[deg + 1:]), (deg, s)
        for k, c in enumerate(coef):
            assert abs(mpmath.mpf(c) - ref[k]) <= 1e-12 * max(sk[k], mpmath.mpf(1e-300)), (k, c, ref[k])
        # the same first contact in (0, 10] as the full variant
        t_full = smallest_root(f_row, 0.0, 10.0)
        t_entry = smallest_root(coef, 0.0, 10.0)
        assert (t_full is None) == (t_entry is None), (t_full, t_entry, s)
        if t_full is not None:
            assert abs(t_full - t_entry) <= 1e-12 * max(abs(t_full), 1e-300) or abs(t_full - t_entry) < 1e-13, (t_full, t_entry)
    assert len(degrees) >= 3, degrees   # the random zeros really reach several variants
    print(f"{eq} {lang}: degrees selected {dict(sorted(degrees.items()))}")


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_effects_restrict_generation(lang, tmp_path, generated):
    g = generated("circle-circle", lang, effects=("acceleration",))
    names = [v.name for v in g.variants]
    assert names and all("no_orbit1" in n and "no_orbit2" in n for n in names)
    assert max(v.degree for v in g.variants) == 4
    # no function of an orbiting variant is in the file
    everything = list_variants("circle-circle")
    outside = [v["name"] for v in everything if v["name"] not in names]
    for name in outside:
        assert f"{name}(" not in g.text and f"{name} (" not in g.text
    # still compiles warning-free, and refuses a world with an orbit
    assert g.selection.name == "circle_circle_coefficients"
    h = build_harness(lang, g, str(tmp_path), mode="entry")
    rng = random.Random(5)
    p = SAMPLERS["circle-circle"](rng)
    p["d"] = p["j"] = 0.0
    ok = h.evaluate([[p[n] for n in g.function.params]])[0]
    assert ok[0] == 4
    p["d"] = 0.5
    assert h.evaluate([[p[n] for n in g.function.params]])[0] == [-1.0]


def test_list_variants_with_effects_none():
    vs = list_variants("point-line", "--effects=none")
    assert [v["name"] for v in vs] == ["point_line_no_accel1_no_orbit1_no_accel2_no_orbit2"]


@pytest.mark.slow
@pytest.mark.parametrize("eq", ["circle-circle", "point-line"])
def test_toc_entry_same_bits_in_every_language_and_matches_the_full_equation(eq, tmp_path, generated):
    rng = random.Random(f"toc-{eq}")
    sets = [sample_with_effects_off(eq, rng) for _ in range(300)]
    if eq == "circle-circle":   # start circle 2 near circle 1, so that many pairs touch
        for s in sets:
            s["g"] = s["a"] + rng.uniform(-6, 6)
            s["r"] = s["m"] + rng.uniform(-6, 6)
    horizons = [rng.choice([1.0, 5.0, 20.0]) for _ in sets]
    answers = {}
    for lang in LANGS:
        g = generated(eq, lang)
        assert g.selection.name == g.derivation.module.equation + "_coefficients"
        h = build_harness(lang, g, str(tmp_path / lang), mode="toc")
        answers[lang] = h.evaluate([[s[n] for n in g.function.params] + [0.0, hz] for s, hz in zip(sets, horizons)])
        if lang == "c":
            full = build_harness(lang, g, str(tmp_path / lang))
            full_coef = full.evaluate([[s[n] for n in g.function.params] for s in sets])
    for lang in LANGS[1:]:
        assert answers[lang] == answers["c"], f"{lang} differs from c"
    found = 0
    for (status, t), coef, hz in zip(answers["c"], full_coef, horizons):
        expect = smallest_root(coef, 0.0, hz)
        assert status in (0.0, 1.0)
        assert (status == 1.0) == (expect is not None), (status, t, expect)
        if expect is not None:
            found += 1
            assert abs(t - expect) <= 1e-12 * abs(expect) + 1e-15, (t, expect)
    assert found >= 30   # the random sets do collide often enough to test the roots
