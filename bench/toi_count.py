"""Instructions per query of the generated `circle_circle_toc_exact` (C,
default options) and of the single Taylor polynomial, counted by valgrind's
callgrind on the cases of bench/toi.py (the same draws: seed, motions and
family order).

    python3 bench/toi_count.py [--motions 40] [--seed 31] [--families a,b] [--passes 10]

A count is the harness run with PASSES timed passes less the same run with
none, divided by PASSES and the number of cases, so that reading the input
and the first (answering) pass cancel.  Printed per family: the cases with
no contact (the exact driver's answer) and all cases, each as exact,
polynomial and their ratio.  Instruction counts do not depend on the
machine's load, unlike the ns of bench/toi.py.
"""
from __future__ import annotations

import argparse
import os
import random
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path[:0] = [str(ROOT), str(ROOT / "runtimes" / "python"), str(ROOT / "bench")]

import toi  # noqa: E402


def instructions(cmd: list[str], text: str, workdir: str) -> int:
    """Instructions callgrind counts for one run of cmd on stdin text."""
    out = os.path.join(workdir, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", *cmd], input=text, text=True,
                   capture_output=True, check=True, cwd=workdir)
    with open(out) as f:
        for line in f:
            m = re.match(r"(?:summary|totals):\s*(\d+)", line)
            if m:
                return int(m.group(1))
    raise RuntimeError("callgrind wrote no total")


def per_query(harness, rows: list[list[float]], passes: int) -> float:
    def text(reps):
        return f"{reps}\n" + "\n".join(" ".join(repr(float(v)) for v in r) for r in rows) + "\n"
    full = instructions(harness.cmd, text(passes), harness.workdir)
    base = instructions(harness.cmd, text(0), harness.workdir)
    return (full - base) / passes / len(rows)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--motions", type=int, default=40)
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--families", default=",".join(f for f in toi.FAMILIES if toi.FAMILIES[f][2] == "circles"))
    ap.add_argument("--passes", type=int, default=10)
    a = ap.parse_args(argv)
    families = [f.strip() for f in a.families.split(",") if f.strip()]
    rng = random.Random(a.seed)
    cases = {f: [toi.FAMILIES[f][0](rng) for _ in range(a.motions)] for f in families}
    toi.BUILD.mkdir(parents=True, exist_ok=True)
    print("| family | no-contact cases | exact | polynomial | ratio | all cases | exact | polynomial | ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="toi-count-", dir=toi.BUILD) as tmp:
        ours = toi.Ours(["c"], tmp, False)
        for f in families:
            rows = {}
            for kind in ("exact", "poly"):
                rows[kind] = []
                for c in cases[f]:
                    row = [c["params"][k] for k in toi.LETTERS] + [c["horizon"]]
                    rows[kind].append(row + [1.0, 1.0, 0.0, 0.0] if kind == "exact" else row)
            answers, _ = ours.harness["c", "exact"].run(rows["exact"])
            none = [i for i, (st, _) in enumerate(answers) if st == 0]
            cells = []
            for pick in (none, list(range(len(cases[f])))):
                if not pick:
                    cells += ["0", "-", "-", "-"]
                    continue
                ex = per_query(ours.harness["c", "exact"], [rows["exact"][i] for i in pick], a.passes)
                po = per_query(ours.harness["c", "poly"], [rows["poly"][i] for i in pick], a.passes)
                cells += [str(len(pick)), f"{ex:,.0f}", f"{po:,.0f}", f"{ex / po:.1f}x"]
            print(f"| {f} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
