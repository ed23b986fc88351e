"""Seed hunt: random closed scenes of tests/sim_scenes.py run in one runtime,
each checked for the three faults the contact model must not have.

    python3 bench/hunt.py [--lang python] [--family resting,spinning,pile] [--start 0] [--count 100]
                          [--seed 1] [--jobs N] [--crosscheck]

Each family draws `--count` seeds at random (from `--seed`; `--start` adds
an offset so that two hunts draw different seeds): `resting_scene(seed,
boxes=True)` (bodies resting, sliding and dropped on a floor under
gravity), `spinning_scene(seed)` (spinning polygons in a box) and `pile_scene(seed)`
(6 to 16 balls, boxes or both, with friction or without, dropped with random
velocities into a narrow bin: inelastic collapse and pinches), each with
max_events_at_one_time = 1000 so that a loop at one instant fails at once.
A scene fails when it does not finish (stuck, or any other simulator
error), when two bodies overlap by more than the tolerance at an event or a
frame, or when the energy grows by more than 1e-12 relative
(max2code.sim.invariants); with `--crosscheck`, also when the four
runtimes do not write the same bytes for it.  Scenes run `--jobs` at a time
(default: one per core), with a progress line on stderr.  Prints one line
per failing scene (in the order of the draws) and the counts per family and
fault; the exit status is 1 when a scene failed.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import random
import sys
from concurrent.futures import ProcessPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))

from max2code.sim.invariants import check, energy_growth  # noqa: E402
from max2code.sim.replay import read_trace  # noqa: E402
from max2code.sim.scene import parse_scene  # noqa: E402
from max2code.progress import bar  # noqa: E402
from max2code.sim.commands import crosscheck  # noqa: E402
from max2code.sim.simulate import LANGS, SimulateError, run_scene  # noqa: E402
from sim_scenes import pile_scene, resting_scene, spinning_scene  # noqa: E402

FAMILIES = {"resting": lambda seed: resting_scene(seed, boxes=True), "spinning": spinning_scene,
            "pile": pile_scene}
KINDS = ("collision", "support", "stop", "leave", "sleep", "wake", "input", "frame")


def verdict(raw: dict, name: str, lang: str, cross: bool = False) -> str | None:
    """None when the scene finishes with no overlap beyond the tolerance and
    no gain of energy (and, with cross, the same bytes in every runtime);
    else what went wrong, its first word the fault: "stuck" (does not
    finish), "overlap", "energy" or "differ"."""
    raw["max_events_at_one_time"] = 1000
    scene = parse_scene(json.dumps(raw), name)
    try:
        tr = run_scene(scene, lang)
    except SimulateError as exc:
        return f"stuck: does not finish: {str(exc).splitlines()[0]}"
    rp = read_trace("\n".join(tr.lines()), scene, name)
    rep = check(scene, rp, kinds=KINDS)
    if rep.max_overlap > scene.tolerance:
        return f"overlap {rep.max_overlap:.3g} m ({rep.overlap_where})"
    er = energy_growth(scene, rp)
    if er.max_growth > 1e-12:
        return f"energy grows {er.max_growth:.3g} relative ({er.growth_where})"
    if cross:
        traces, problems = crosscheck(scene, LANGS)
        if problems:
            return f"differ: {problems[0]}"
        other = [k for k, t in traces.items() if t.raw != traces[lang].raw]
        if other:
            return f"differ: {', '.join(other)} agree within 1e-9 but do not write {lang}'s bytes"
    return None


def _one(job: tuple[str, int, str, bool]) -> tuple[str, int, str | None]:
    fam, seed, lang, cross = job
    return fam, seed, verdict(FAMILIES[fam](seed), f"{fam}-{seed}.json", lang, cross)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lang", default="python", choices=LANGS)
    ap.add_argument("--family", default="resting,spinning")
    ap.add_argument("--count", type=int, default=100)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="scenes run at once (default: cores)")
    ap.add_argument("--crosscheck", action="store_true", help="also require the same bytes in all four runtimes")
    args = ap.parse_args(argv)
    jobs = []
    for fam in args.family.split(","):
        if fam not in FAMILIES:
            ap.error(f"--family: unknown family '{fam}' (expected {', '.join(FAMILIES)})")
        rng = random.Random(args.seed * 1000003 + args.start)
        jobs += [(fam, rng.randrange(10 ** 6), args.lang, args.crosscheck) for _ in range(args.count)]
    # the simulators are built once, here, before the workers share them
    for lang in (LANGS if args.crosscheck else [args.lang]):
        verdict(pile_scene(1, end_time=0.01), "warm-up.json", lang)
    results = {}
    with ProcessPoolExecutor(max(1, args.jobs)) as pool:
        for i, (fam, seed, why) in enumerate(pool.map(_one, jobs, chunksize=1), 1):
            results[(fam, seed)] = why
            bar(i, len(jobs), f"{fam} {seed}", prefix="hunt")
    failed = False
    for fam in dict.fromkeys(f for f, *_ in jobs):
        faults = collections.Counter()
        n = 0
        for f, seed, *_ in jobs:
            if f != fam:
                continue
            n += 1
            why = results[(f, seed)]
            if why is not None:
                faults[why.split()[0].rstrip(":")] += 1
                print(f"{fam} {seed}: {why}", flush=True)
        detail = ", ".join(f"{k} {v}" for k, v in sorted(faults.items()))
        bad = sum(faults.values())
        print(f"{fam}: {n} scenes, {bad} failed ({args.lang}{', four runtimes compared' if args.crosscheck else ''})"
              + (f": {detail}" if detail else ""), flush=True)
        failed = failed or bad > 0
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
