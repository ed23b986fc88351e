"""Long runs (the simulator's invariants): at every collision and every frame of
runs with more than 10,000 such events, no two bodies overlap beyond the
scene's tolerance, and with restitution 1 the kinetic plus potential energy
stays within 1e-9 relative; a second run writes the same trace.  The C
runtime runs them (the cross-check test shows the four write the same bytes)."""
from __future__ import annotations

import json
import math
import os
import random

import pytest

from max2code.sim.invariants import check
from max2code.sim.replay import read_trace
from max2code.sim.scene import parse_scene
from max2code.sim.simulate import run_scene
from sim_scenes import box, random_scene  # noqa: E402

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def disks(n: int, seed: int, end_time: float) -> dict:
    """n equal disks on a jittered lattice in a box, random velocities, restitution 1."""
    rng = random.Random(seed)
    side = math.ceil(math.sqrt(n))
    gap = 0.1
    bodies = box(side * gap, side * gap)
    for k in range(n):
        x, y = (k % side + 0.5) * gap, (k // side + 0.5) * gap
        bodies.append({"name": f"d{k}", "shape": "circle", "radius": 0.03, "mass": 1.0,
                       "position": [x + rng.uniform(-0.01, 0.01), y + rng.uniform(-0.01, 0.01)],
                       "velocity": [rng.uniform(-1, 1), rng.uniform(-1, 1)]})
    return {"name": f"{n} disks", "end_time": end_time, "frame_rate": 100, "bodies": bodies}


CASES = {
    # no scripted inputs: an input adds energy, and the energy test needs a closed system
    "spinning-polygons-and-circles-under-gravity": lambda: {k: v for k, v in dict(
        random_scene(3, gravity=True, spin=True, restitution_one=True, bodies=16, end_time=30.0),
        frame_rate=200).items() if k != "inputs"},
    "disks": lambda: disks(64, 1, 12.0),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_long_run_invariants(case):
    raw = CASES[case]()
    scene = parse_scene(json.dumps(raw), f"{case}.json")
    tr = run_scene(scene, "c")
    rp = read_trace("\n".join(tr.lines()), scene, f"{case}.jsonl")
    rep = check(scene, rp, kinds=("collision", "input", "frame"))
    print(f"{case}: {tr.stats['events']}; {rep}")
    assert rep.events >= 10_000, rep
    assert rep.max_overlap <= scene.tolerance, rep
    assert rep.max_energy_drift <= 1e-9, rep
    again = run_scene(scene, "c")
    assert again.raw == tr.raw
