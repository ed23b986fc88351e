"""Time of impact of circles and convex polygons side by side: max2code's
TOI library (C, docs/toi.md) against parry2d's nonlinear shape cast (f64
and f32) and, when its source is given, Box2D v3's `b2TimeOfImpact`, on the
cases of tests/conformance/toi/toi.jsonl that every peer can take (no
acceleration, no orbit), scored against their mpmath references.

    python3 bench/toi_shapes.py [--families a,b] [--reps N] [--box2d-src DIR]

Per family: ns per query (each case timed alone, the median of 15 batches
of REPS queries; then the median over the family's cases) and right / wrong
/ missed / invented by the conformance rule of docs/toi.md (a contact
between the times the bodies come within 2 tol and are 2 tol inside each
other; overlapped only where the bodies overlap at t = 0).  Peers answer
for their own motion model: parry's rigid motion is ours without
acceleration (the body turns about its centre of rotation while that moves
on its line); Box2D sweeps 60 Hz steps and interpolates each step's
rotation, and stops at its linear slop (5 mm) before contact by design.
The peers' drivers: bench/peers/parry-toi (src/bin/shapes.rs, built with
cargo into build/toi/parry) and bench/peers/box2d/toi_shapes.c.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path[:0] = [str(ROOT), str(ROOT / "runtimes" / "python"), str(ROOT / "bench")]

import toi  # noqa: E402  (bench/toi.py: the peers' builds)
from max2code.conformance import toi_op  # noqa: E402
from max2code.progress import bar  # noqa: E402

CASES = ROOT / "tests" / "conformance" / "toi" / "toi.jsonl"
PEERS = ("ours", "parry f64", "parry f32", "box2d")
VERDICTS = ("right", "wrong", "missed", "invented")


def rigid(case: dict) -> bool:
    """A case every peer can take: no acceleration and no orbit."""
    return all(case[k]["motion"].get(q, 0.0) == 0.0 for k in "ab" for q in ("ax", "ay", "orbit"))


def load(path: Path, families: set[str] | None) -> list[dict]:
    cases = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]
    return [c for c in cases if rigid(c) and (not families or c["family"] in families)]


def peer_line(case: dict) -> str:
    """One case in the peers' input layout (bench/peers/parry-toi/src/bin/shapes.rs)."""
    out = [repr(float(case["horizon"]))]
    for k in "ab":
        b, m = case[k], case[k]["motion"]
        verts = b.get("vertices", []) if b["shape"] == "polygon" else []
        out += ["1" if b["shape"] == "polygon" else "0", str(len(verts))]
        out += [repr(float(m.get(q, 0.0))) for q in ("x", "y", "vx", "vy", "angle", "omega")]
        out.append(repr(float(b.get("radius", 0.0))))
        out += [repr(float(v)) for xy in verts for v in xy]
    return " ".join(out)


def run_peer(exe: Path, cases: list[dict], reps: int) -> dict[str, tuple[list[str], list[float]]]:
    """{driver name: (answers, ns per case)} from one of the peers' programs."""
    text = f"{reps}\n" + "".join(peer_line(c) + "\n" for c in cases)
    proc = subprocess.run([str(exe)], input=text, capture_output=True, text=True, check=True)
    got: dict[str, tuple[list[str], list[float]]] = {}
    for line in proc.stdout.splitlines():
        parts = line.split()
        if parts[0] == "ns":
            got[parts[1]][1].append(float(parts[2]))
        else:
            got.setdefault(parts[0], ([], []))[0].append(parts[1])
    return got


def verdict(case: dict, answer: str) -> str:
    """right / wrong / missed / invented for an answer: a time, "none",
    "overlapped", "refused", or ours as the TOI testee writes it."""
    if answer not in ("none", "overlapped") and not answer.startswith(("hit", "error")):
        answer = "error refused" if answer == "refused" else \
            " ".join(["hit", toi_op.hex_of(float(answer))] + ["0"] * 8)
    v = toi_op.judge(case, answer)
    if v.ok:
        return "right"
    if answer == "none":
        return "missed"
    if answer.startswith("hit") and case.get("t_in") is None:
        return "invented"
    return "wrong"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--families", default="", help="comma-separated families (default: all with rigid cases)")
    ap.add_argument("--reps", type=int, default=200, help="queries per timed batch (default 200)")
    ap.add_argument("--box2d-src", type=Path, help="Box2D v3's source tree: also measure b2TimeOfImpact")
    ap.add_argument("--cases", type=Path, default=CASES)
    ap.add_argument("-q", "--quiet", action="store_true")
    a = ap.parse_args(argv)
    cases = load(a.cases, set(filter(None, a.families.split(","))))
    if not cases:
        print("toi_shapes: no case to run", file=sys.stderr)
        return 2
    steps = 4 if a.box2d_src else 3

    def step(i: int, what: str) -> None:
        if not a.quiet:
            bar(i, steps, what, prefix="toi_shapes")

    step(0, "ours (C)")
    results: dict[str, tuple[list[str], list[float]]] = {}
    ans, ns = toi_op.run_c(dict(enumerate(cases)), reps=a.reps)
    results["ours"] = ([ans[k] for k in range(len(cases))], [ns[k] for k in range(len(cases))])
    step(1, "parry2d build")
    parry = toi.build_parry(not a.quiet).with_name("shapes")
    step(2, "parry2d")
    got = run_peer(parry, cases, a.reps)
    results["parry f64"], results["parry f32"] = got["f64"], got["f32"]
    step(3, "box2d" if a.box2d_src else "done")
    if a.box2d_src:
        exe = toi.build_box2d(a.box2d_src, not a.quiet, driver="toi_shapes.c", name="toi_shapes_box2d")
        results["box2d"] = run_peer(exe, cases, a.reps)["b2"]
        step(4, "done")
    peers = [p for p in PEERS if p in results]
    families = sorted({c["family"] for c in cases}, key=lambda f: [c["family"] for c in cases].index(f))
    print(f"ns per query (median over the family's cases) and right / wrong / missed / invented; "
          f"{len(cases)} cases of {a.cases.name} without acceleration or orbit; {a.reps} queries per batch")
    print("| family | cases | " + " | ".join(f"{p} ns" for p in peers) + " | "
          + " | ".join(f"{p} r/w/m/i" for p in peers) + " |")
    print("|---" * (2 + 2 * len(peers)) + "|")
    for fam in families + ["all"]:
        idx = [k for k, c in enumerate(cases) if fam in ("all", c["family"])]
        cells_ns, cells_v = [], []
        for p in peers:
            answers, times = results[p]
            cells_ns.append(f"{statistics.median(times[k] for k in idx):,.0f}")
            counts = {v: 0 for v in VERDICTS}
            for k in idx:
                counts[verdict(cases[k], answers[k])] += 1
            cells_v.append(" / ".join(str(counts[v]) for v in VERDICTS))
        print(f"| {fam} | {len(idx)} | " + " | ".join(cells_ns) + " | " + " | ".join(cells_v) + " |")
    return 0


if __name__ == "__main__":
    os.environ.setdefault("PYTHONHASHSEED", "0")
    raise SystemExit(main())
