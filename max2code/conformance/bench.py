"""Root-solver benchmark: `python -m max2code.conformance.bench` (or
`python bench/roots.py`).

Prints the median time per solve (ns) for degrees 2, 3, 4, 6, 8 for each
runtime (C, Rust, Modula-2, Python) against GSL's companion-matrix solver
(from C and from Modula-2) and numpy.roots, on the same polynomials: a fixed
seed mixes polynomials built from random roots (some in (0, 1], some not,
some complex pairs) and polynomials with Gaussian coefficients, all asked for
the smallest root in (0, 1].  Native runtimes are built with -O2 and timed
in-process with a monotonic clock around a pass over all polynomials of a
degree; the median is over passes.  Python and numpy.roots are timed in CPU time
(time_python says why).  With `--rounds N` every column is measured N times,
the columns taking turns, and each figure is the smallest of its N medians:
on a host whose speed swings between phases for seconds or minutes at a
time, a single run catches some columns in a slow phase and others in a
fast one, while the minimum over interleaved rounds compares them all in
the fast phase.  Figures, not tests.
"""
from __future__ import annotations

import argparse
import random
import statistics
import subprocess
import time

from max2code.conformance import runner as R
from max2code.toolchain.c import make_c
from max2code.toolchain.m2 import make_m2
from max2code.toolchain.rust import cargo
from max2code.progress import bar

DEGREES = (2, 3, 4, 6, 8)


def polynomials(per_degree: int, seed: int = 7) -> dict[int, list[list[float]]]:
    rng = random.Random(seed)
    out: dict[int, list[list[float]]] = {}
    for deg in DEGREES:
        polys = []
        for k in range(per_degree):
            if k % 2 == 0:
                c = [rng.gauss(0.0, 1.0) for _ in range(deg + 1)]
            else:
                c = [rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0])]
                left = deg
                while left > 0:
                    if left >= 2 and rng.random() < 0.3:
                        re, im = rng.uniform(-1.0, 2.0), rng.uniform(0.05, 1.0)
                        q = [re * re + im * im, -2.0 * re, 1.0]
                        left -= 2
                    else:
                        q = [-rng.uniform(-1.0, 2.5), 1.0]
                        left -= 1
                    nc = [0.0] * (len(c) + len(q) - 1)
                    for i, a in enumerate(c):
                        for j, b in enumerate(q):
                            nc[i + j] += a * b
                    c = nc
            assert len(c) == deg + 1
            polys.append(c)
        out[deg] = polys
    return out


def wire(polys: dict[int, list[list[float]]]) -> str:
    lines = []
    seq = 0
    for deg, ps in polys.items():
        for c in ps:
            lines.append(R.RootsOp().wire({"coeffs": c, "lo": 0.0, "hi": 1.0}, seq))
            seq += 1
    return "\n".join(lines) + "\n"


def parse(out: str) -> dict[int, float]:
    res = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2:
            res[int(parts[0])] = float(parts[1])
    return res


def native(cmd: list[str], text: str) -> dict[int, float]:
    r = subprocess.run(cmd, input=text, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=True)
    return parse(r.stdout)


def time_python(fn, polys: list[list[float]], reps: int) -> float:
    """Median CPU ns per call over passes.  CPU time, not wall time: a Python
    pass takes milliseconds, longer than a scheduler slice, so on a shared
    machine its wall time counts the other processes' turns too (at a load
    average of 9 on 2 cores, 4-6x).  The native passes take microseconds and
    their median over passes is not affected so."""
    times = []
    for r in range(reps + 1):
        t0 = time.process_time_ns()
        for c in polys:
            fn(c)
        dt = (time.process_time_ns() - t0) / len(polys)
        if r:
            times.append(dt)
    return statistics.median(times)


def numpy_smallest(c: list[float]):
    import numpy as np
    roots = np.roots(c[::-1])
    best = None
    for z in roots:
        if abs(z.imag) <= 1e-7 * max(1.0, abs(z.real)) and 0.0 < z.real <= 1.0:
            if best is None or z.real < best:
                best = float(z.real)
    return best


def _fig(v: float) -> str:
    return f"{v:,.0f}" if v >= 1000 else f"{v:.1f}"


def print_markdown(cols: dict[str, dict[int, float]], names: list[str], rounds: int = 1) -> None:
    """The README's table: one row per degree, ns per solve, and the load average."""
    print("| degree | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for deg in DEGREES:
        print(f"| {deg} | " + " | ".join(_fig(cols[n].get(deg, float("nan"))) for n in names) + " |")
    notes = [f"the smallest of {rounds} interleaved rounds' medians"] if rounds > 1 else []
    try:
        import os
        notes.append(f"load average {os.getloadavg()[0]:.1f} at the end of the run")
    except OSError:
        pass
    if notes:
        print(f"\n({'; '.join(notes)})")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--per-degree", type=int, default=1000, help="polynomials per degree (default 1000)")
    ap.add_argument("--reps", type=int, default=41, help="timed passes for native runtimes (default 41)")
    ap.add_argument("--py-reps", type=int, default=5, help="timed passes for Python and numpy (default 5)")
    ap.add_argument("--rounds", type=int, default=1,
                    help="measure every column this many times, taking turns, and report the smallest "
                         "median of each (default 1)")
    ap.add_argument("--markdown", action="store_true",
                    help="print the table as Markdown (the README's table) with the load average")
    args = ap.parse_args(argv)
    if args.rounds < 1 or args.reps < 1 or args.py_reps < 1 or args.per_degree < 1:
        ap.error("--rounds, --reps, --py-reps and --per-degree must be at least 1")
    polys = polynomials(args.per_degree)
    text = wire(polys)
    builds = ["build C", "build Rust", "build Modula-2"]
    reps = str(args.reps)
    from max2code_rt.roots import smallest_root

    def python_col(fn):
        return lambda: {deg: time_python(fn, polys[deg], args.py_reps) for deg in DEGREES}

    columns = {
        "C": lambda: native([str(R.BUILD / "c" / "m2c_bench"), "m2c", reps], text),
        "GSL (C)": lambda: native([str(R.BUILD / "c" / "m2c_bench"), "gsl", reps], text),
        "Rust": lambda: native([str(R.BUILD / "rust" / "release" / "max2code_rt_bench"), reps], text),
        "Modula-2": lambda: native([str(R.BUILD / "m2" / "roots_bench")], f"bench m2 {reps}\n" + text),
        "GSL (M2)": lambda: native([str(R.BUILD / "m2" / "roots_bench")], f"bench gsl {reps}\n" + text),
        "Python": python_col(lambda c: smallest_root(c, 0.0, 1.0)),
        "numpy.roots": python_col(numpy_smallest),
    }
    total = len(builds) + args.rounds * len(columns)

    def progress(i: int, what: str) -> None:
        bar(i, total, what, "bench/roots.py")

    progress(0, builds[0])
    R.build_testee("c")
    make_c(R.BUILD / "c" / "m2c_bench")
    progress(1, builds[1])
    cargo("build", "--release", "--quiet", "--bin", "max2code_rt_bench")
    progress(2, builds[2])
    make_m2(R.BUILD / "m2" / "roots_bench")
    cols: dict[str, dict[int, float]] = {name: {} for name in columns}
    step = len(builds)
    for r in range(args.rounds):
        for name, measure in columns.items():
            progress(step, f"{name}" + (f", round {r + 1}" if args.rounds > 1 else ""))
            step += 1
            for deg, ns in measure().items():
                cols[name][deg] = min(ns, cols[name].get(deg, ns))
    progress(total, "done")
    names = list(cols)
    if args.markdown:
        print_markdown(cols, names, args.rounds)
        return 0
    what = f"smallest of {args.rounds} rounds' median" if args.rounds > 1 else "median"
    print(f"{what} ns per solve, smallest root in (0, 1], {args.per_degree} polynomials per degree")
    print("degree " + "".join(f"{n:>13s}" for n in names))
    for deg in DEGREES:
        print(f"{deg:6d} " + "".join(f"{cols[n].get(deg, float('nan')):13.1f}" for n in names))
    found = {}
    for deg in DEGREES:
        found[deg] = sum(1 for c in polys[deg] if smallest_root(c, 0.0, 1.0) is not None)
    print("polynomials with a root in (0, 1]: " + ", ".join(f"d{d} {found[d]}/{len(polys[d])}" for d in DEGREES))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
