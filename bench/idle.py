"""What idling buys: CPU per second of play of our event-driven engine
driven by a 60 frames-per-second game loop, against pymunk stepping the same
scene at 1/60 and 1/240 s, rapier2d at 1/60 s and Box2D v3 at 1/60 s with 4
sub-steps (when its source is given), for the game's scene and every example
scene (examples/*.json and examples/piles/*.json).

    python3 bench/idle.py [--engines c[,python]] [--fps 60] [--runs 3] [--plot docs/idle]
                          [--box2d-src DIR] [--no-peers] [SCENE.json ...]

Ours: the world opened through max2code.sim.live (the build is done before
the clock starts), then per frame k: advance(k / fps) (every event up to
the frame) and states(t), every body's state in one call (what drawing needs); no
rendering.  pymunk: the scene translated by max2code/reports/engines.py
(build_space: the same bodies, masses, restitution, gravity; friction 0),
per frame 1 or 4 steps and every body's position and angle read.  A scene's
scripted inputs (the game's recording has them) are applied in pymunk at the
first step that reaches their time.  rapier2d and Box2D: the compiled
drivers of max2code/reports/peers.py (built before the clock starts), best of
up to 3 runs, their step calls alone timed (the states are written after
each step, outside the clock).  A scene's own frame_rate is set to 0:
the loop draws the frames, the engine need not hold frame events.

Figures: CPU seconds (time.process_time) per second of play, best of
`--runs` (ours: of which the state reads, through ctypes for the C engine);
and the share of the frame budget (1 / fps) the engine could sleep, 1 -
mean busy frame / budget (the busiest frame's share in brackets).  The load average is printed:
on a shared machine the figures stretch with it.
"""
from __future__ import annotations

import argparse
import glob
import json
import math
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from max2code.errors import Max2CodeError  # noqa: E402
from max2code.sim.live import _runtime  # noqa: E402
from max2code.reports import peers  # noqa: E402
from max2code.reports.engines import build_space  # noqa: E402
from max2code.sim.live import open_world  # noqa: E402
from max2code.sim.scene import ADD_VELOCITY, IMPULSE, SET_VELOCITY, TELEPORT, parse_scene  # noqa: E402

SimError = _runtime().SimError          # what the live engines raise (a stuck scene, a failure)
GAME_SCENE = os.path.join(ROOT, "examples", "game", "recording.json")


def load(path: str):
    """The scene without its own frames (the loop makes them)."""
    with open(path, encoding="utf-8") as fh:
        raw = json.load(fh)
    raw["frame_rate"] = 0
    return parse_scene(json.dumps(raw), path)


def ours(scene, engine: str, fps: float):
    """(CPU s of the whole loop, per-frame CPU s list, CPU s in the state reads) for one run."""
    world = open_world(scene, engine)
    n = math.floor(scene.end_time * fps + 1e-9)
    per = []
    reads = 0.0
    clock = time.process_time
    start = clock()
    for k in range(1, n + 1):
        c0 = clock()
        t = k / fps
        world.advance(t)
        c1 = clock()
        world.states(t)
        c2 = clock()
        reads += c2 - c1
        per.append(c2 - c0)
    total = clock() - start
    if hasattr(world, "close"):
        world.close()
    return total, per, reads


def _apply(space, body, inp) -> None:
    """A scripted input on a pymunk body, as our scene format means it."""
    x, y = inp.velocity
    if inp.mode == SET_VELOCITY:
        body.velocity = (x, y)
    elif inp.mode == ADD_VELOCITY:
        body.velocity = (body.velocity.x + x, body.velocity.y + y)
    elif inp.mode == IMPULSE:
        body.apply_impulse_at_local_point((x, y))
    elif inp.mode == TELEPORT:
        body.position = (x, y)
        space.reindex_shapes_for_body(body)
    else:                                       # REMOVE
        space.remove(body, *body.shapes)


def frames(scene, dt: float, fps: float):
    """pymunk stepped at dt, read every frame: (CPU s, per-frame CPU s list)."""
    world = build_space(scene)
    space, pbodies = world.space, world.bodies
    inputs = sorted(scene.inputs, key=lambda i: i.time)
    n = math.floor(scene.end_time * fps + 1e-9)
    per_frame = max(1, round(1.0 / (fps * dt)))
    per = []
    clock = time.process_time
    start = clock()
    t = 0.0
    nxt = 0
    for _ in range(n):
        c0 = clock()
        for _ in range(per_frame):
            while nxt < len(inputs) and inputs[nxt].time <= t + dt * 0.5:
                _apply(space, pbodies[inputs[nxt].body], inputs[nxt])
                nxt += 1
            space.step(dt)
            t += dt
        for b in pbodies:
            b.position, b.angle       # noqa: B018  (the reads drawing needs; a removed body's too, as ours)
        per.append(clock() - c0)
    return clock() - start, per, None


def best(fn, runs: int):
    out = None
    for _ in range(runs):
        r = fn()
        if out is None or r[0] < out[0]:
            out = r
    return out


def peer_frames(run, fps: float):
    """(CPU s, per-frame CPU s list, None) of a compiled peer's run
    (max2code/reports/peers.py: its 1/60 s steps, grouped per frame)."""
    group = max(1, round(1.0 / (fps * peers.STEP)))
    per = [sum(run.step_cpu[k:k + group]) for k in range(0, len(run.step_cpu), group)]
    return run.cpu, per, None


def measure(paths, engines, fps: float, runs: int, progress=True, built=None):
    built = built or {}
    rows = []
    for path in paths:
        scene = load(path)
        label = os.path.relpath(path, ROOT)
        for engine in engines:
            open_world(scene, engine)           # build before the clock starts
        row = {"scene": label, "end": scene.end_time, "bodies": len(scene.bodies), "runs": {}, "skipped": {}}
        for engine in engines:
            try:
                row["runs"][f"ours {engine}"] = best(lambda: ours(scene, engine, fps), runs)
            except (Max2CodeError, SimError) as exc:      # stuck, or any failure: the table says where it stopped
                row["skipped"][f"ours {engine}"] = "stopped: " + str(exc).splitlines()[0][-160:]
        for dt, name in ((1 / 60, "pymunk 1/60 s"), (1 / 240, "pymunk 1/240 s")):
            row["runs"][name] = best(lambda: frames(scene, dt, fps), runs)
        for engine, binary in built.items():
            name = peers.PEER_TITLES[engine]
            if isinstance(binary, Exception):
                row["skipped"][name] = str(binary)
                continue
            run = peers.run_driver(engine, binary, scene)
            if run.status != "ok":
                row["skipped"][name] = run.status
                continue
            row["runs"][name] = peer_frames(run, fps)
        rows.append(row)
        if progress:
            print(f"idle: {label} done", file=sys.stderr)
    return rows


def table(rows, fps: float) -> list[str]:
    """One row per scene; per run: CPU ms per second of play (ours: of which
    the state reads) and the share of the frame budget left to sleep (mean
    frame; the worst frame's in brackets)."""
    names = list(dict.fromkeys(n for r in rows for n in [*r["runs"], *r["skipped"]]))
    budget = 1.0 / fps
    head = ["scene (bodies, s played)"]
    for n in names:
        head += [f"{n}: CPU ms per s of play" + (" (state reads)" if n.startswith("ours") else ""),
                 f"{n}: could sleep (worst frame)"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [f"{r['scene']} ({r['bodies']}, {r['end']:g})"]
        for n in names:
            if n not in r["runs"]:
                cells += [r["skipped"].get(n, "-"), "-"]
                continue
            total, per, reads = r["runs"][n]
            cpu = f"{total / r['end'] * 1e3:,.2f}"
            if reads is not None:
                cpu += f" ({reads / r['end'] * 1e3:,.2f})"
            mean = total / max(len(per), 1)
            cells += [cpu, f"{(1 - mean / budget) * 100:.1f} % ({(1 - max(per) / budget) * 100:.1f} %)"]
        out.append("| " + " | ".join(cells) + " |")
    return out


def plot(rows, stem: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = list(dict.fromkeys(n for r in rows for n in r["runs"]))
    fig, ax = plt.subplots(figsize=(10, 4.8))
    width = 0.8 / len(names)
    for k, n in enumerate(names):
        ys = [r["runs"][n][0] / r["end"] * 1e3 if n in r["runs"] else math.nan for r in rows]
        ax.bar([i + (k - (len(names) - 1) / 2) * width for i in range(len(rows))], ys, width, label=n)
    ax.set_yscale("log")
    ax.set_xticks(range(len(rows)), [os.path.basename(r["scene"]).removesuffix(".json") for r in rows],
                  rotation=20, ha="right")
    ax.axhline(1e3, color="grey", linestyle=":", linewidth=1)
    ax.text(len(rows) - 0.5, 1e3, "all the CPU (1000 ms per s)", ha="right", va="bottom", fontsize=8)
    ax.set_ylabel("CPU ms per second of play (log)")
    ax.set_title("A 60 fps game loop: our event engine (advance + states per frame) vs frame engines stepping")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)
    fig.savefig(stem + ".svg", metadata={"Date": None})
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--engines", default="c")
    ap.add_argument("--fps", type=float, default=60.0)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--plot", default=os.path.join(ROOT, "docs", "idle"), help="write PLOT.png and PLOT.svg ('' none)")
    ap.add_argument("--box2d-src", metavar="DIR", help="a Box2D v3 source folder: Box2D joins the table")
    ap.add_argument("--no-peers", action="store_true", help="leave out rapier2d (and Box2D)")
    args = ap.parse_args(argv)
    paths = args.scenes or ([GAME_SCENE] + sorted(glob.glob(os.path.join(ROOT, "examples", "*.json")))
                            + sorted(glob.glob(os.path.join(ROOT, "examples", "piles", "*.json"))))
    engines = [e for e in args.engines.split(",") if e]
    load_before = os.getloadavg()
    built = {}
    if not args.no_peers:
        built = {k: v for k, v in peers.prepare(args.box2d_src).items() if k != "pymunk"}
    rows = measure(paths, engines, args.fps, args.runs, built=built)
    load_after = os.getloadavg()
    print(f"`python3 bench/idle.py` ({args.fps:g} frames per second; CPU per second of play, best of "
          f"{args.runs}; load average {load_before[0]:.1f} before, {load_after[0]:.1f} after):\n")
    print("\n".join(table(rows, args.fps)))
    if args.plot:
        plot(rows, args.plot)
        print(f"\nplot: {os.path.relpath(args.plot, ROOT)}.png, .svg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
