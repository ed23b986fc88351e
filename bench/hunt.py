"""Seed hunt: random closed scenes of tests/sim_scenes.py run in one runtime,
each checked for the three faults the contact model must not have.

    python3 bench/hunt.py [--lang python] [--family resting,spinning,pile] [--start 0] [--count 100]
                          [--seed 1]

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
(max2code.sim.invariants).  Prints one line per failing scene and the
counts per family; the exit status is 1 when a scene failed.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))

from max2code.sim.invariants import check, energy_growth  # noqa: E402
from max2code.sim.replay import read_trace  # noqa: E402
from max2code.sim.scene import parse_scene  # noqa: E402
from max2code.sim.simulate import LANGS, SimulateError, run_scene  # noqa: E402
from sim_scenes import pile_scene, resting_scene, spinning_scene  # noqa: E402

FAMILIES = {"resting": lambda seed: resting_scene(seed, boxes=True), "spinning": spinning_scene,
            "pile": pile_scene}
KINDS = ("collision", "support", "stop", "leave", "sleep", "wake", "input", "frame")


def verdict(raw: dict, name: str, lang: str) -> str | None:
    """None when the scene finishes with no overlap beyond the tolerance and
    no gain of energy; else what went wrong."""
    raw["max_events_at_one_time"] = 1000
    scene = parse_scene(json.dumps(raw), name)
    try:
        tr = run_scene(scene, lang)
    except SimulateError as exc:
        return f"does not finish: {str(exc).splitlines()[0]}"
    rp = read_trace("\n".join(tr.lines()), scene, name)
    rep = check(scene, rp, kinds=KINDS)
    if rep.max_overlap > scene.tolerance:
        return f"overlap {rep.max_overlap:.3g} m ({rep.overlap_where})"
    er = energy_growth(scene, rp)
    if er.max_growth > 1e-12:
        return f"energy grows {er.max_growth:.3g} relative ({er.growth_where})"
    return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lang", default="python", choices=LANGS)
    ap.add_argument("--family", default="resting,spinning")
    ap.add_argument("--count", type=int, default=100)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    failed = False
    for fam in args.family.split(","):
        if fam not in FAMILIES:
            ap.error(f"--family: unknown family '{fam}' (expected {', '.join(FAMILIES)})")
        rng = random.Random(args.seed * 1000003 + args.start)
        seeds = [rng.randrange(10 ** 6) for _ in range(args.count)]
        bad = 0
        for seed in seeds:
            why = verdict(FAMILIES[fam](seed), f"{fam}-{seed}.json", args.lang)
            if why is not None:
                bad += 1
                print(f"{fam} {seed}: {why}", flush=True)
        print(f"{fam}: {len(seeds)} scenes, {bad} failed ({args.lang})", flush=True)
        failed = failed or bad > 0
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
