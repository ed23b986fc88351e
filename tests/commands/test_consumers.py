"""docs/using-generated-code.md, run as written: each language's block
builds a program outside this repository against the runtime installed by
`max2code runtime LANG --install PREFIX` (C through pkg-config, Rust with
-D warnings, Python in a venv holding only max2code-rt, Modula-2 with gm2),
using the max2code of the installed wheel, and the four print the same
contact times."""
from __future__ import annotations

import math
import re
import subprocess

import pytest

from max2code import paths

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

DOC = paths.ROOT / "docs" / "using-generated-code.md"
LANGS = ("c", "rust", "python", "m2")
# circle 1 at (0, 0) at 1 m/s, radius 1; circle 2 at (10, 0.5) at -1 m/s, radius 0.5
EXPECTED = (10.0 - math.sqrt(2.0)) / 2.0


def blocks() -> dict[str, str]:
    return dict(re.findall(r"<!-- consumer: (\w+) -->\n```sh\n(.*?)\n```", DOC.read_text(encoding="utf-8"), re.S))


def test_the_doc_has_a_program_per_language():
    assert sorted(blocks()) == sorted(LANGS)


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    return tmp_path_factory.mktemp("prefix")


@pytest.fixture(scope="module")
def answers():
    return {}


@pytest.mark.parametrize("lang", LANGS)
def test_consumer_program(installed, prefix, answers, tmp_path, lang):
    _, env = installed
    env = dict(env, PREFIX=str(prefix))
    r = subprocess.run(["bash", "-euo", "pipefail", "-c", blocks()[lang]], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-3000:]
    got = dict(re.findall(r"^(circle_circle_toc(?:_exact)?): (\S+)$", r.stdout, re.M))
    assert sorted(got) == ["circle_circle_toc", "circle_circle_toc_exact"], r.stdout
    times = {k: float(v) for k, v in got.items()}
    assert abs(times["circle_circle_toc"] - EXPECTED) < 1e-12
    assert abs(times["circle_circle_toc_exact"] - EXPECTED) < 1e-12
    answers[lang] = times
    if lang == "python":     # the venv holds max2code-rt and nothing else of ours
        freeze = subprocess.run([str(tmp_path / "venv" / "bin" / "pip"), "freeze"], capture_output=True, env=env,
                                text=True, check=True).stdout
        assert [ln.split("@")[0].split("==")[0].strip() for ln in freeze.splitlines()] == ["max2code-rt"], freeze
    if len(answers) == len(LANGS):
        assert len({tuple(sorted(a.items())) for a in answers.values()}) == 1, answers
