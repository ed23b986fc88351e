"""The figure-making commands run end to end (their figures are not asserted:
speed lives in benchmarks, not in tests)."""
import subprocess
import sys

import pytest

from conftest import ROOT

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def test_bench_variants_builds_and_reports_every_variant():
    out = subprocess.run([sys.executable, "-m", "max2code", "bench-variants", "--sets", "20", "--reps", "1",
                          "--trials", "1", "equations/point-line.mxm"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    rows = [line for line in out.stdout.splitlines() if line.startswith("| point_line")]
    assert len(rows) == 5   # the five point-line variants, each timed in C and Rust
    assert "| c |" in out.stdout and "| rust |" in out.stdout


def test_table_reports_both_columns_of_figure_6():
    out = subprocess.run([sys.executable, "-m", "max2code", "table", "equations/point-line.mxm"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    row = [line for line in out.stdout.splitlines() if line.startswith("| point-line.mxm")][0].split("|")
    assert row[2].strip() == "4" and int(row[-4]) < int(row[-5])   # degree; shared < naive multiplications
