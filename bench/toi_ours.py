"""ns per query of max2code's TOI library (docs/toi.md) on the conformance
cases of op "toi" (tests/conformance/toi/toi.jsonl), with right / wrong
against their mpmath references.

    python3 bench/toi_ours.py [--lang c|python] [--family both-spinning] [--reps N]

`measure(lang, cases) -> float` (the median ns per query over the cases)
is what bench/toi.py calls beside the other engines; `answers(lang, cases)`
gives each case's answer for scoring.  C times each case with its testee
(the median of 15 batches of REPS queries, the shapes made once, as a
Box2D user keeps them); Python times the library's call in this process."""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path[:0] = [str(ROOT), str(ROOT / "runtimes" / "python")]

from max2code.conformance import toi_op  # noqa: E402

CASES = ROOT / "tests" / "conformance" / "toi" / "toi.jsonl"
DEFAULT_FAMILY = "both-spinning"      # two spinning boxes


def load(path: Path = CASES, family: str | None = DEFAULT_FAMILY) -> list[dict]:
    cases = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]
    return [c for c in cases if family in (None, "all") or c.get("family") == family]


def per_case_ns(lang: str, cases: list[dict], reps: int = 2000) -> list[float]:
    """ns per query of each case."""
    if lang == "c":
        _, ns = toi_op.run_c(dict(enumerate(cases)), reps=reps)
        return [ns[k] for k in range(len(cases))]
    if lang == "python":
        out = []
        for c in cases:
            n = max(1, reps // 100)
            samples = []
            for _ in range(5):
                t0 = time.perf_counter_ns()
                for _ in range(n):
                    toi_op.python_answer(c)
                samples.append((time.perf_counter_ns() - t0) / n)
            out.append(statistics.median(samples))
        return out
    raise ValueError(f"no TOI library benchmark for {lang}")


def measure(lang: str, cases: list[dict], reps: int = 2000) -> float:
    """The median over the cases of ns per query."""
    return statistics.median(per_case_ns(lang, cases, reps))


def answers(lang: str, cases: list[dict]) -> list[str]:
    seqs = dict(enumerate(cases))
    got = toi_op.ToiOp().batch(lang, seqs)
    return [got.get(k, "error: no answer") for k in range(len(cases))]


def score(lang: str, cases: list[dict]) -> tuple[int, int, list[str]]:
    """(right, wrong, why of each wrong) against the references."""
    right, bad = 0, []
    for c, a in zip(cases, answers(lang, cases)):
        v = toi_op.judge(c, a)
        if v.ok:
            right += 1
        else:
            bad.append(f"{c['id']}: {v.why}")
    return right, len(bad), bad


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lang", default="c", choices=("c", "python"))
    ap.add_argument("--family", default=DEFAULT_FAMILY, help="a case family, or 'all'")
    ap.add_argument("--reps", type=int, default=2000)
    ap.add_argument("--cases", default=str(CASES))
    args = ap.parse_args(argv)
    cases = load(Path(args.cases), args.family)
    if not cases:
        print(f"no cases of family {args.family!r} in {args.cases}", file=sys.stderr)
        return 2
    ns = per_case_ns(args.lang, cases, args.reps)
    right, wrong, why = score(args.lang, cases)
    q = statistics.quantiles(ns, n=10) if len(ns) > 1 else ns * 9
    print(f"{args.lang} TOI library, family {args.family} ({len(cases)} cases): median {statistics.median(ns):.0f} ns "
          f"per query (p10 {q[0]:.0f}, p90 {q[-1]:.0f}); {right} right, {wrong} wrong against mpmath")
    for w in why:
        print("  wrong: " + w)
    return 0 if wrong == 0 else 1


if __name__ == "__main__":
    os.environ.setdefault("PYTHONHASHSEED", "0")
    raise SystemExit(main())
