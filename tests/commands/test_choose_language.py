"""`max2code choose-language [EQ.mxm]`: a user's equation, interleaved rounds
within a time budget, median and spread per language, and what each
language gives besides speed."""
from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT
from max2code.reports import choose_language

ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))


@pytest.mark.slow
def test_a_users_equation_in_rounds_within_the_budget(tmp_path):
    eq = os.path.join(ROOT, "tests", "data", "user-equations", "point-floor-quintic.mxm")
    doc = tmp_path / "doc.md"
    doc.write_text(f"before\n{choose_language.BEGIN}\nold\n{choose_language.END}\nafter\n")
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", eq, "--langs", "python,c", "--seconds", "3",
                        "--motions", "20", "--write", str(doc)], capture_output=True, text=True, cwd=ROOT, env=ENV,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    out = r.stdout
    assert "point-floor-quintic.mxm" in out
    rounds = int(re.search(r"median over (\d+) interleaved rounds", out).group(1))
    assert rounds >= choose_language.MIN_ROUNDS
    assert re.search(r"\d+ rounds in [0-9.]+ s", r.stderr)          # the progress line's last state
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in out.splitlines() if line.startswith("| python") or line.startswith("| c ")}
    assert set(rows) == {"python", "c"}
    for lang, cells in rows.items():
        # NAME_toc and NAME_toc_exact (the quintic's polynomial is its exact gap): median (smallest-largest)
        for cell in cells[:2]:
            med, lo, hi = (float(x.replace(",", "")) for x in re.fullmatch(r"([\d,]+) \(([\d,]+)-([\d,]+)\)", cell).groups())
            assert 0 < lo <= med <= hi
        assert float(cells[2]) > 0                                      # build seconds
    assert rows["python"][3].startswith("no") and rows["c"][3] == "yes (float)"
    assert rows["python"][4].startswith("no") and rows["c"][4].startswith("yes: `#line`")
    assert rows["c"][5] == "yes"
    text = doc.read_text()
    assert text.startswith("before\n") and text.endswith("after\n") and "old" not in text and "| c |" in text


def test_facts_and_spread():
    assert choose_language.facts("m2")["reentrant"].startswith("NAME_toc yes; NAME_toc_exact no")
    assert choose_language.facts("rust")["single"] == "yes (f32)"
    assert choose_language._ns([300.0, 310.0, 500.0]) == "310 (300-500)"
    assert choose_language._ns([]) == "-"


def test_unknown_language_and_missing_file():
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", "--langs", "cobol"], capture_output=True,
                       text=True, cwd=ROOT, env=ENV)
    assert r.returncode == 1 and "unknown cobol" in r.stderr
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", "nowhere.mxm"], capture_output=True,
                       text=True, cwd=ROOT, env=ENV)
    assert r.returncode == 1 and "nowhere.mxm: error: no such file" in r.stderr
