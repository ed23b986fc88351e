"""`max2code simulate` against the engine it runs (issue 12, item 3): wall
time, CPU time and peak memory of the command and of the simulator's process
alone, on bench/sim.py's gases of equal disks.

    python3 bench/simulate_cmd.py [--lang c] [--sizes 1000,10000,100000] [--events 3e5] [--seed 1]

For each size, the end time is scaled (one pilot run) so that the run handles
about `--events` events; the scene is written to a temporary JSON file, the
engine is run on its flat form (trace drained into a pipe), then the command
`max2code simulate --lang LANG SCENE -o TRACE -q` runs in a fresh Python
process.  Peak memory is the process's maximum resident set (the command's
includes its simulator child's only through `ru_maxrss` of the children).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "bench"))

from sim import gas, handled, run  # noqa: E402  (bench/sim.py)

from max2code.sim.scene import compile_scene, parse_scene  # noqa: E402
from max2code.sim.simulate import build_simulator  # noqa: E402


def command(scene_path: str, out: str, lang: str) -> tuple[float, float, float, int]:
    """Wall, CPU (this command and its children), peak RSS in MB of the
    command, and the trace's size in bytes."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "max2code", "simulate", "--lang", lang, scene_path, "-o", out,
                             "-q"], env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"bench/simulate_cmd.py: max2code simulate failed on {scene_path}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0, os.path.getsize(out)


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="bench/simulate_cmd.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--lang", default="c")
    p.add_argument("--sizes", default="1000,10000,100000")
    p.add_argument("--events", type=float, default=3e5, help="events per run (about; default 3e5)")
    p.add_argument("--fraction", type=float, default=0.25)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args(argv)
    probe = parse_scene(json.dumps(gas(2, args.fraction, 1.0, args.seed)), "gas")
    build = build_simulator(args.lang, probe.effects, probe.taylor_order)
    print(f"{'bodies':>8} {'events':>9} {'collisions':>10} {'engine wall':>11} {'engine cpu':>10} "
          f"{'cmd wall':>9} {'cmd cpu':>8} {'ratio':>6} {'cmd MB':>7} {'trace MB':>9}")
    with tempfile.TemporaryDirectory(prefix="simcmd-") as tmp:
        for n in (int(float(x)) for x in args.sizes.split(",") if x):
            guess = 0.05 * args.events / (n * 1.0 / 0.01)
            scene = parse_scene(json.dumps(gas(n, args.fraction, guess, args.seed)), "gas")
            _, _, counts = run(build, compile_scene(scene))
            end = float(f"{guess * args.events / max(handled(counts), 1):.4g}")
            raw = gas(n, args.fraction, end, args.seed)
            path = os.path.join(tmp, f"gas-{n}.json")
            with open(path, "w", encoding="utf-8") as fh:
                json.dump(raw, fh)
            scene = parse_scene(json.dumps(raw), path)
            wall_e, cpu_e, counts = run(build, compile_scene(scene))
            wall_c, cpu_c, mb, size = command(path, os.path.join(tmp, "trace.jsonl"), args.lang)
            print(f"{n:>8} {handled(counts):>9} {counts.get('collisions', 0):>10} {wall_e:>11.3f} {cpu_e:>10.3f} "
                  f"{wall_c:>9.3f} {cpu_c:>8.3f} {wall_c / wall_e:>6.2f} {mb:>7.0f} {size / 1e6:>9.1f}")
    print("engine: the simulator's process on the flat scene, its trace drained into a pipe; cmd: `max2code "
          "simulate -o TRACE -q` in a fresh process (scene check, build cache look-up, run, JSON trace); "
          "ratio: cmd wall / engine wall; cmd MB: peak resident memory of the command's largest process")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
