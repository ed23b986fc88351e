"""`max2code accuracy` end to end on a small sweep (C and Python, a dozen
motions): it writes the table and both plots, and its numbers say what the
issue expects of them (exact motion exact, the paper's form far off)."""
import re

import pytest

from max2code.reports import accuracy

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def test_accuracy_quick_sweep(tmp_path, capsys):
    out = tmp_path / "acc.md"
    assert accuracy.main(["--langs", "c,python", "--cases", "12", "--quick", "--reps", "3", "--python-reps", "1",
                          "-o", str(out), "-q"]) == 0
    text = out.read_text()
    assert (tmp_path / "acc.png").stat().st_size > 1000 and (tmp_path / "acc.svg").stat().st_size > 1000
    assert "Made by `max2code accuracy --langs c,python --cases 12" in text
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 7 and cells[1] in ("c", "python") and cells[0] in accuracy.QUICK:
            rows[(cells[0], cells[1])] = cells
    assert len(rows) == 2 * len(accuracy.QUICK)
    for lang in ("c", "python"):
        exact = rows[("exact o4 a1", lang)]
        assert exact[4] == "0" or float(exact[4]) <= 1e-12, exact
        assert exact[5:] == ["0", "0"], exact
        paper = rows[("paper", lang)]
        assert float(paper[3]) > 1e-6, paper
        assert re.fullmatch(r"[0-9,.]+", exact[2]) and re.fullmatch(r"[0-9,.]+", paper[2])
    assert "| c |" in capsys.readouterr().out
