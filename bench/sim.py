"""Simulator benchmark: events (and collisions) per second of each runtime's simulator on
gases of equal disks in a box, from 10^2 to 10^5 disks.

    python3 bench/sim.py [--langs c,rust,m2,python] [--sizes 100,1000,10000,100000]
                         [--events 500000] [--fraction 0.25] [--seed 1]

Each scene: N disks of radius 1 cm at random non-overlapping positions in a
square box of four fixed walls, filling `--fraction` of its area, random
velocities (speed 1 m/s), no gravity, restitution 1, no frames.  The end
time is chosen so that a run handles about `--events` events: a short pilot
run of the first runtime measures the event rate, and the end time scales
with it.  Events are the handled ones: every counter of the trace's N lines
(collisions, cell crossings, horizons, inputs, frames, support transitions,
and any kind a runtime adds) but stale queue entries and the pair and
feature prediction counts; a second table gives every counter per collision.  Each runtime also
runs the scene for 1 ns, which is nearly all start (reading the scene, the
first prediction of every pair, the final states): "after" is the rate of
the events past it.  The times are
those of the simulator's process, CPU (user + system: the events and collisions per
second reported) and wall: reading the scene, simulating and writing the whole
trace (into a pipe that this script drains).  Runtimes
whose simulator does not build are skipped with a note.  With `--rounds N`
each runtime runs each scene (and its start) N times, the runtimes taking
turns, and the smallest CPU and wall times are reported: the host's speed
swings between phases for seconds to minutes, and the smallest of
interleaved rounds compares every runtime in the fast phase (bench/roots.py
has the same option).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from max2code.progress import bar  # noqa: E402
from max2code.sim.scene import compile_scene, parse_scene  # noqa: E402
from max2code.sim.simulate import (LANGS, WORK_COUNTERS, SimulateError, build_simulator,  # noqa: E402
                                   handled_events, time_engine)

RADIUS = 0.01       # m
SPEED = 1.0         # m/s
START = 1e-9        # s: a run that is (almost) only its start


def gas(n: int, fraction: float, end_time: float, seed: int) -> dict:
    """n equal disks at random non-overlapping positions in a square box
    (random sequential placement through a grid of cells one diameter wide)."""
    rng = random.Random(seed)
    side = math.sqrt(n * math.pi * RADIUS * RADIUS / fraction)
    cell = 2.0 * RADIUS
    grid: dict[tuple[int, int], list[tuple[float, float]]] = {}
    placed: list[tuple[float, float]] = []
    gap = 2.0 * RADIUS * (1.0 + 1e-6)
    tries = 0
    while len(placed) < n:
        tries += 1
        if tries > 1000 * n:
            raise RuntimeError(f"cannot place {n} disks at area fraction {fraction}")
        x = rng.uniform(RADIUS * 1.001, side - RADIUS * 1.001)
        y = rng.uniform(RADIUS * 1.001, side - RADIUS * 1.001)
        cx, cy = int(x // cell), int(y // cell)
        if any((x - px) ** 2 + (y - py) ** 2 < gap * gap
               for dx in (-1, 0, 1) for dy in (-1, 0, 1) for px, py in grid.get((cx + dx, cy + dy), ())):
            continue
        grid.setdefault((cx, cy), []).append((x, y))
        placed.append((x, y))
    t = 0.1
    walls = []
    for name, cx, cy, hw, hh in (("floor", side / 2, -t / 2, side / 2 + t, t / 2),
                                 ("ceiling", side / 2, side + t / 2, side / 2 + t, t / 2),
                                 ("left", -t / 2, side / 2, t / 2, side / 2),
                                 ("right", side + t / 2, side / 2, t / 2, side / 2)):
        walls.append({"name": name, "shape": "polygon", "fixed": True, "position": [cx, cy],
                      "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]})
    disks = []
    for k, (x, y) in enumerate(placed):
        a = rng.uniform(0.0, 2.0 * math.pi)
        disks.append({"name": f"d{k}", "shape": "circle", "radius": RADIUS, "mass": 1.0,
                      "position": [x, y], "velocity": [SPEED * math.cos(a), SPEED * math.sin(a)]})
    return {"name": f"gas of {n} disks", "end_time": end_time, "bodies": walls + disks}


def run(build, flat: str) -> tuple[float, float, dict[str, int]]:
    """Wall and CPU time (user + system) of one run and its counters (the N
    lines, by name); the trace is drained as it comes."""
    return time_engine(build, flat)


def handled(counts: dict[str, int]) -> int:
    """Events handled: every N counter but stale entries and predictions
    (so a new event kind counts without a change here)."""
    return handled_events(counts)


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="bench/sim.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--langs", default=",".join(LANGS[1:] + LANGS[:1]),
                   help="runtimes to time, in this order (default c,rust,m2,python; unbuilt ones are skipped)")
    p.add_argument("--sizes", default="100,1000,10000,100000", help="numbers of disks")
    p.add_argument("--events", type=float, default=5e5, help="events per run (about; default 5e5)")
    p.add_argument("--fraction", type=float, default=0.25, help="area fraction of the disks (default 0.25)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--rounds", type=int, default=1,
                   help="runs of each scene per runtime, taking turns; the smallest times are reported (default 1)")
    args = p.parse_args(argv)
    if args.rounds < 1:
        p.error("--rounds must be at least 1")
    langs = [x for x in args.langs.split(",") if x]
    for lang in langs:
        if lang not in LANGS:
            p.error(f"unknown runtime '{lang}' (expected {', '.join(LANGS)})")
    sizes = [int(float(x)) for x in args.sizes.split(",") if x]

    # every gas has the same effects (none: no gravity, nothing turns)
    probe = parse_scene(json.dumps(gas(2, args.fraction, 1.0, args.seed)), "gas")
    builds = {}
    for lang in langs:
        try:
            builds[lang] = build_simulator(lang, probe.effects, probe.taylor_order)
        except (NotImplementedError, SimulateError) as exc:
            print(f"bench/sim.py: skipping {lang}: {str(exc).splitlines()[0]}", file=sys.stderr)
    if not builds:
        print("bench/sim.py: no runtime's simulator builds", file=sys.stderr)
        return 1
    order = list(builds)

    steps = len(sizes) * (len(order) * args.rounds + 1)
    step = 0
    rows = []
    for n in sizes:
        bar(step, steps, f"{n} disks: pilot", "bench/sim.py")
        # pilot: a short run of the first runtime measures events per simulated second
        guess = 0.05 * args.events / (n * SPEED / RADIUS)
        scene = parse_scene(json.dumps(gas(n, args.fraction, guess, args.seed)), f"gas-{n}")
        _, _, counts = run(builds[order[0]], compile_scene(scene))
        end = float(f"{guess * args.events / max(handled(counts), 1):.4g}")
        scene = parse_scene(json.dumps(gas(n, args.fraction, end, args.seed)), f"gas-{n}")
        flat = compile_scene(scene)
        # the start alone: reading the scene, the first predictions, the final states
        start = compile_scene(parse_scene(json.dumps(gas(n, args.fraction, START, args.seed)), f"gas-{n}"))
        step += 1
        row = {"bodies": n, "end": end, "times": {}, "counts": None}
        for r in range(args.rounds):
            for lang in order:
                bar(step, steps, f"{n} disks: {lang}" + (f", round {r + 1}" if args.rounds > 1 else ""),
                    "bench/sim.py")
                _, cpu0, counts0 = run(builds[lang], start)
                elapsed, cpu, counts = run(builds[lang], flat)
                if lang in row["times"]:
                    w, c, c0, _ = row["times"][lang]
                    elapsed, cpu, cpu0 = min(elapsed, w), min(cpu, c), min(cpu0, c0)
                row["times"][lang] = (elapsed, cpu, cpu0, handled(counts0))
                if row["counts"] is not None and counts != row["counts"]:
                    print(f"bench/sim.py: {n} disks: {lang} counts {counts}, {order[0]} {row['counts']}",
                          file=sys.stderr)
                row["counts"] = counts
                step += 1
        rows.append(row)
    bar(steps, steps, "done", "bench/sim.py")

    head = f"{'bodies':>8} {'end (s)':>9} {'events':>9} {'collisions':>10} {'cells':>9} {'stale':>9}"
    for lang in order:
        head += (f" {lang + ' cpu s':>11} {lang + ' ev/s':>11} {lang + ' coll/s':>11} {lang + ' wall s':>11}"
                 f" {lang + ' start s':>11} {'after':>9}")
    print(head)
    for row in rows:
        c = row["counts"]
        ev = handled(c)
        line = (f"{row['bodies']:>8} {row['end']:>9.4g} {ev:>9} {c.get('collisions', 0):>10} {c.get('cells', 0):>9} "
                f"{c.get('stale', 0):>9}")
        for lang in order:
            wall, cpu, cpu0, ev0 = row["times"][lang]
            after = (ev - ev0) / (cpu - cpu0) if cpu > cpu0 else float("nan")
            line += (f" {cpu:>11.3f} {ev / max(cpu, 1e-9):>11.4g} {c.get('collisions', 0) / max(cpu, 1e-9):>11.4g}"
                     f" {wall:>11.3f} {cpu0:>11.3f} {after:>9.4g}")
        print(line)
    print("ev/s: events per CPU second (user + system) of the simulator's process; coll/s: collisions per CPU "
          "second (the work: fewer events per collision make each event dearer);\nwall s: its elapsed time, "
          "which a loaded machine stretches; start s: CPU seconds of the same scene run for 1 ns (reading it, "
          "the first predictions, the final states); after: events per CPU second past the start"
          + (f"\n(times: the smallest of {args.rounds} interleaved rounds)" if args.rounds > 1 else ""))
    # every counter of the trace's N lines, by name, per collision
    names = list(dict.fromkeys(k for row in rows for k in row["counts"]))
    print()
    print(f"{'bodies':>8} {'events/collision':>16} " + " ".join(f"{k:>10}" for k in names))
    for row in rows:
        c = row["counts"]
        col = max(c.get("collisions", 0), 1)
        print(f"{row['bodies']:>8} {handled(c) / col:>16.3f} " + " ".join(f"{c.get(k, 0) / col:>10.3f}" for k in names))
    print("per collision: each N counter of the trace over the collisions; events/collision: all events handled "
          f"(every counter but {', '.join(WORK_COUNTERS)}: queue entries dropped, pair and feature predictions)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
