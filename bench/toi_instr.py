"""Instructions per query of max2code's TOI library (C, docs/toi.md) on the
conformance cases (tests/conformance/toi/toi.jsonl), counted by valgrind's
callgrind: one case a run of the C testee, only inside `m2c_toi`
(`--toggle-collect=m2c_toi`), with `LD_BIND_NOW=1` so that the dynamic
linker's first-call binding of libm and the generated entries is not
counted.  Instruction counts do not depend on the machine's load.

    python3 bench/toi_instr.py [--families a,b] [--json OUT]

Prints per family the cases, the median and the mean instructions per query.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path[:0] = [str(ROOT), str(ROOT / "runtimes" / "python")]

from max2code.conformance import toi_op  # noqa: E402

CASES = ROOT / "tests" / "conformance" / "toi" / "toi.jsonl"


def count(exe: Path, case: dict, workdir: str) -> int:
    """Instructions callgrind counts inside m2c_toi for one query of case."""
    out = os.path.join(workdir, "callgrind.out")
    env = dict(os.environ, LD_BIND_NOW="1")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--toggle-collect=m2c_toi",
                    str(exe)], input=toi_op.wire(case, 0) + "\n", text=True, capture_output=True, check=True,
                   env=env, cwd=workdir)
    with open(out) as f:
        for line in f:
            m = re.match(r"(?:summary|totals):\s*(\d+)", line)
            if m:
                return int(m.group(1))
    raise RuntimeError("callgrind wrote no total")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--families", default="", help="comma-separated families (default: all)")
    ap.add_argument("--cases", type=Path, default=CASES)
    ap.add_argument("--json", type=Path, help="also write {case id: instructions} here")
    a = ap.parse_args(argv)
    want = set(filter(None, a.families.split(",")))
    cases = [json.loads(line) for line in a.cases.read_text(encoding="utf-8").splitlines() if line.strip()]
    cases = [c for c in cases if not want or c["family"] in want]
    exe = toi_op.c_testee()
    got: dict[str, int] = {}
    with tempfile.TemporaryDirectory(prefix="toi-instr-") as tmp:
        for c in cases:
            got[c["id"]] = count(exe, c, tmp)
    if a.json:
        a.json.write_text(json.dumps(got, indent=1) + "\n", encoding="utf-8")
    families = list(dict.fromkeys(c["family"] for c in cases))
    print("| family | cases | median | mean |")
    print("|---|---|---|---|")
    for fam in families:
        n = [got[c["id"]] for c in cases if c["family"] == fam]
        print(f"| {fam} | {len(n)} | {statistics.median(n):,.0f} | {statistics.mean(n):,.0f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
