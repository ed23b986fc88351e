"""The C simulator's own number conversions, against the C library's: its
trace writer's %.17g (m2c_sim_format_number) against printf, and its scene
reader's decimals (m2c_sim_parse_number, strtod only for what it does not
take) against strtod, bit for bit, on random doubles of every magnitude
written shortest and with 15-17 digits and on random digit strings
(`sim --check-format N`, `sim --check-parse N`; runtimes/c/tools/m2c_sim_main.c)."""
from __future__ import annotations

import re
import subprocess

import pytest

from max2code.sim.simulate import build_simulator

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

N = 400_000


def _sim() -> list[str]:
    return build_simulator("c", (), 4).run_cmd


def test_format_writes_what_printf_writes():
    r = subprocess.run([*_sim(), "--check-format", str(N)], capture_output=True, text=True, timeout=600)
    m = re.search(r"(\d+) of (\d+) numbers differ", r.stdout)
    assert m and r.returncode == 0, r.stdout + r.stderr
    assert m.group(1) == "0" and int(m.group(2)) == N


def test_parse_reads_what_strtod_reads():
    r = subprocess.run([*_sim(), "--check-parse", str(N)], capture_output=True, text=True, timeout=600)
    m = re.search(r"(\d+) of (\d+) decimals \((\d+) read without strtod\) differ", r.stdout)
    assert m and r.returncode == 0, r.stdout + r.stderr
    bad, total, fast = map(int, m.groups())
    assert bad == 0 and total == N
    # both paths are exercised: the reader's own and strtod's
    assert N // 4 < fast < N
