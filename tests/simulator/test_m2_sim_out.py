"""The Modula-2 simulator's trace writer (runtimes/m2/SimOut) writes every
double as C's printf("%.17g") does: SimOutCheck compares the two on random
bit patterns, trace-like magnitudes, short decimals and their neighbours,
powers of ten, zeros, infinities and NaN, and fails on any difference."""
from __future__ import annotations

import os
from pathlib import Path
import re
import shutil
import subprocess

import pytest

from max2code.toolchain.m2 import SIM_FLAGS

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
M2 = os.path.join(ROOT, "runtimes", "m2")

pytestmark = [pytest.mark.slow,      # builds or runs the native runtimes (scripts/test --fast leaves it out)
              pytest.mark.skipif(shutil.which("gm2") is None, reason="gm2 not installed")]


def test_sim_out_writes_what_printf_writes(tmp_path):
    incs = [f"-I{M2}", f"-I{os.path.join(M2, 'src')}"]
    obj = str(tmp_path / "SimOut.o")
    exe = str(tmp_path / "sim_out_check")
    for cmd in (["gm2", *SIM_FLAGS, *incs, "-c", os.path.join(M2, "SimOut.mod"), "-o", obj],
                ["gm2", *SIM_FLAGS, f"-I{tmp_path}", *incs, os.path.join(M2, "SimOutCheck.mod"), obj, "-o", exe,
                 "-lm"]):
        r = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True)
        assert r.returncode == 0, r.stdout + r.stderr
    r = subprocess.run([exe], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout
    m = re.search(r"(\d+) numbers checked, (\d+) by the fast path, (\d+) mismatches", r.stdout)
    assert m, r.stdout
    checked, fast, bad = map(int, m.groups())
    assert bad == 0 and checked > 10 ** 6
    # both paths are exercised: the fast one and the snprintf fallback
    assert 0 < fast < checked
