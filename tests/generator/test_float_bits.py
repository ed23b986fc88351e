"""--real=float gives the same bits in every language that offers it (C
float, Rust f32, Modula-2 SHORTREAL): the bundled equations, generated in
single precision, compiled by the project's harness and run on the same
inputs, print the same coefficients."""
import os
from pathlib import Path
import random

import pytest

from max2code.generate.pipeline import GenerateRequest, generate_file
from max2code.toolchain.harness import build_harness
from max2code.targets import LANGUAGES

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
FLOAT_LANGS = sorted(n for n, t in LANGUAGES.items() if t.single_type is not None)


def _inputs(nparams: int, n: int = 400) -> list[list[float]]:
    rnd = random.Random(20261207)
    rows = []
    for k in range(n):
        row = [rnd.uniform(-4.0, 4.0) * 10.0 ** rnd.randint(-3, 2) for _ in range(nparams)]
        if k % 7 == 0:      # exact zeros select the variants
            row = [0.0 if rnd.random() < 0.4 else x for x in row]
        rows.append(row)
    return rows


@pytest.mark.parametrize("eq", ["circle-circle", "point-edge", "point-line"])
def test_float_variants_agree_bit_for_bit(tmp_path, eq):
    assert {"c", "m2", "rust"} <= set(FLOAT_LANGS)
    outputs = {}
    for lang in FLOAT_LANGS:
        g = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", f"{eq}.mxm"), lang=lang,
                                          out_name="generated", real="float"))
        h = build_harness(lang, g, str(tmp_path / lang), mode="entry")
        outputs[lang] = h.evaluate(_inputs(len(g.function.params)))
    ref = FLOAT_LANGS[0]
    calls = sum(len(r) for r in outputs[ref])
    assert calls > 400
    for lang in FLOAT_LANGS[1:]:
        diff = [(i, a, b) for i, (a, b) in enumerate(zip(outputs[ref], outputs[lang])) if a != b]
        assert not diff, f"{lang} differs from {ref} in {len(diff)} of {len(outputs[ref])} rows, first {diff[0]}"
