"""#line directives: a compile error planted in a .mxm term block is
reported by gcc and gm2 at the .mxm line (and column)."""
import os
import re
import subprocess
from pathlib import Path

import pytest

from max2code.generate.pipeline import GenerateRequest, generate_file

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
DATA = str(ROOT / "tests" / "data" / "planted-error.mxm")
PLANTED_LINE = {"c": 10, "m2": 20}   # the `term 1` blocks in planted-error.mxm


def _source(tmp_path, planted: bool) -> str:
    text = open(DATA).read()
    if not planted:
        text = text.replace("PLANTED", "")
    path = tmp_path / "planted-error.mxm"
    path.write_text(text)
    return str(path)


def _gen(path, lang, out_name, lines=True):
    return generate_file(GenerateRequest(path=path, lang=lang, out_name=out_name, line_directives=lines)).text


def _compile_c(tmp_path, text):
    src = tmp_path / "quad.c"
    src.write_text(text)
    return subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-c", str(src), "-o", str(tmp_path / "quad.o")],
                          capture_output=True, text=True)


def _compile_m2(tmp_path, text):
    (tmp_path / "quad.mxd").write_text(text)
    main = tmp_path / "usequad.mod"
    main.write_text('MODULE usequad ;\n\n#include "quad.mxd"\n\nVAR k: ARRAY [0..2] OF REAL ;\nBEGIN\n  quad (1.0, 2.0, 3.0, k)\nEND usequad.\n')
    return subprocess.run(["gm2", "-fiso", "-fcpp", "-Wall", "-Werror", f"-I{tmp_path}", "-c", str(main), "-o", str(tmp_path / "usequad.o")],
                          capture_output=True, text=True, cwd=tmp_path)


COMPILE = {"c": _compile_c, "m2": _compile_m2}
OUT = {"c": "quad.c", "m2": "quad.mxd"}


@pytest.mark.parametrize("lang", ["c", "m2"])
def test_planted_error_is_reported_at_the_mxm_line(tmp_path, lang):
    path = _source(tmp_path, planted=True)
    proc = COMPILE[lang](tmp_path, _gen(path, lang, OUT[lang]))
    assert proc.returncode != 0
    lines = [int(m) for m in re.findall(r"planted-error\.mxm:(\d+):\d+: error", proc.stderr)]
    assert lines, proc.stderr
    assert lines[0] == PLANTED_LINE[lang], proc.stderr
    if lang == "c":   # gcc also gives the column of PLANTED in the .mxm
        col = open(path).read().splitlines()[PLANTED_LINE[lang] - 1].index("PLANTED") + 1
        assert re.search(rf"planted-error\.mxm:{PLANTED_LINE[lang]}:{col}: error", proc.stderr), proc.stderr


@pytest.mark.parametrize("lang", ["c", "m2"])
def test_fragment_without_the_planted_error_compiles_cleanly(tmp_path, lang):
    path = _source(tmp_path, planted=False)
    for lines in (True, False):
        proc = COMPILE[lang](tmp_path, _gen(path, lang, OUT[lang], lines))
        assert proc.returncode == 0, proc.stderr


def test_no_line_switch_removes_directives(tmp_path):
    path = _source(tmp_path, planted=False)
    assert "#line" in _gen(path, "c", "quad.c")
    assert "#line" not in _gen(path, "c", "quad.c", lines=False)
