"""Generated code compiles warning-free in every language and its
coefficients equal an independent exact evaluation of the equation."""
import random

import mpmath
import pytest

from conftest import EQUATIONS, LANGS
from max2code.toolchain.harness import build_harness
from max2code.conformance.motion_ref import EQUATIONS as REFERENCE
from max2code.conformance.motion_ref import scale as reference_scale

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

N_SETS = 200
REL_TOL = 1e-12


def random_params(names, rng):
    out = {}
    for n in names:
        out[n] = rng.uniform(-10.0, 10.0)
    return out


def circle_params(rng):
    def body(pos, vel, acc, rad, w, ph):
        return {pos: rng.uniform(-20, 20), vel: rng.uniform(-5, 5), acc: rng.uniform(-3, 3),
                rad: rng.uniform(0, 2), w: rng.uniform(-4, 4), ph: rng.uniform(-mpmath.pi, mpmath.pi)}
    p = {}
    p.update(body("a", "b", "c", "d", "e", "f"))
    p.update({"m": rng.uniform(-20, 20), "n": rng.uniform(-5, 5), "o": rng.uniform(-3, 3),
              "p": rng.uniform(-4, 4), "q": rng.uniform(-3.2, 3.2)})
    p.update(body("g", "h", "i", "j", "k", "l"))
    p.update({"r": rng.uniform(-20, 20), "s": rng.uniform(-5, 5), "u": rng.uniform(-3, 3),
              "v": rng.uniform(-4, 4), "w": rng.uniform(-3.2, 3.2)})
    p.update({"x": rng.uniform(0.01, 3), "z": rng.uniform(0.01, 3)})
    return {k: float(v) for k, v in p.items()}


def line_params(rng):
    p = {}
    for pos, vel, acc, rad, w, ph in (("a", "b", "c", "d", "e", "f"), ("g", "h", "i", "j", "k", "l")):
        p.update({pos: rng.uniform(-20, 20), vel: rng.uniform(-5, 5), acc: rng.uniform(-3, 3),
                  rad: rng.uniform(0, 2), w: rng.uniform(-4, 4), ph: rng.uniform(-3.2, 3.2)})
    return p


SAMPLERS = {"circle-circle": circle_params, "point-line": line_params}


@pytest.fixture(scope="module")
def harnesses(generated, tmp_path_factory):
    cache = {}

    def get(eq, lang):
        if (eq, lang) not in cache:
            g = generated(eq, lang)
            cache[(eq, lang)] = (g, build_harness(lang, g, str(tmp_path_factory.mktemp(f"{eq}-{lang}"))))
        return cache[(eq, lang)]
    return get


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("eq", EQUATIONS)
def test_coefficients_match_independent_reference(eq, lang, harnesses):
    g, h = harnesses(eq, lang)
    rng = random.Random(f"{eq}-{lang}-2026")
    sets = [SAMPLERS[eq](rng) for _ in range(N_SETS)]
    names = g.function.params
    got = h.evaluate([[s[n] for n in names] for s in sets])
    assert len(got) == N_SETS
    worst_scaled = worst_plain = 0.0
    for s, coeffs in zip(sets, got):
        ref = REFERENCE[eq](s)
        sk = reference_scale(eq, s)
        assert len(coeffs) == len(ref)
        for k, (x, r, scale) in enumerate(zip(coeffs, ref, sk)):
            diff = abs(mpmath.mpf(x) - r)
            # relative to the coefficient's scale S_k = sum of |terms|: the
            # error measure no floating-point evaluation can beat under cancellation
            scaled = float(diff / max(scale, mpmath.mpf(1e-300)))
            worst_scaled = max(worst_scaled, scaled)
            worst_plain = max(worst_plain, float(diff / max(abs(r), mpmath.mpf(1e-300))))
            assert scaled <= REL_TOL, f"{eq} {lang} t^{k}: {x!r} vs {mpmath.nstr(r, 20)} (scaled rel {scaled:.3g})"
            if abs(r) >= scale / 16:   # no heavy cancellation: plain relative error holds too
                assert diff <= REL_TOL * abs(r), f"{eq} {lang} t^{k}: {x!r} vs {mpmath.nstr(r, 20)}"
    print(f"{eq} {lang}: max error {worst_scaled:.3g} relative to S_k, {worst_plain:.3g} relative to |c_k|, {N_SETS} sets")


@pytest.mark.parametrize("eq", EQUATIONS)
def test_all_languages_agree_bit_for_bit(eq, harnesses):
    rng = random.Random(f"{eq}-bits")
    sets = [SAMPLERS[eq](rng) for _ in range(50)]
    results = {}
    for lang in LANGS:
        g, h = harnesses(eq, lang)
        results[lang] = h.evaluate([[s[n] for n in g.function.params] for s in sets])
    for lang in LANGS[1:]:
        assert results[lang] == results["c"], f"{lang} differs from c"


@pytest.mark.parametrize("eq", EQUATIONS)
def test_shared_code_is_smaller_than_naive(eq, generated):
    g = generated(eq, "c")
    assert g.function.multiplications < g.function.naive_multiplications
    naive = generated(eq, "c", shared=False)
    # the plain expansion as printed costs exactly what the header claims
    assert naive.function.multiplications == g.function.naive_multiplications
    print(f"{eq}: {g.function.multiplications} multiplications shared vs {naive.function.multiplications} naive")
