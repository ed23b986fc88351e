"""`max2code simulate` against the engine it runs: wall
time, CPU time and peak memory of the command and of the simulator's process
alone, on bench/sim.py's gases of equal disks or on the example scenes.

    python3 bench/simulate_cmd.py [--lang c] [--sizes 10000,100000] [--events 3e5] [--seed 1]
                                  [--converter auto|c|python|both] [--repeat N] [--against DIR] [--examples]

For each size, the end time is scaled (one pilot run) so that the run handles
about `--events` events; the scene is written to a temporary JSON file, the
engine is run on its flat form (trace drained into a pipe), then the command
`max2code simulate --lang LANG SCENE -o TRACE -q --converter CONV` runs in a
fresh Python process (the checkout's modules compiled to bytecode first, as an
install does; the last run's trace file removed before each run).  With `--repeat N` the engine and the commands run in turn N times,
and the least wall time and the least CPU time of each are shown (on a shared
machine the others waited for a core).
`--against DIR` adds the command of another checkout (its own build
folder), run in turn with this one's.  `--examples` times each scene of
examples/ instead (what a game developer
sees on small scenes).  Peak memory is a process's maximum resident set (the
command's: that of the largest of the command and its simulator child),
measured through GNU time when installed (a child forked from this script
would count this script's own memory at the fork).
"""
from __future__ import annotations

import argparse
import glob
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

from max2code.sim.scene import compile_scene, load_scene, parse_scene  # noqa: E402
from max2code.sim.simulate import build_simulator  # noqa: E402


TIME = "/usr/bin/time"       # GNU time: the peak memory of a child forked from a small process


def timed(cmd: list[str], *, stdin=None, stdout=None, cwd=None, env=None) -> tuple[float, float, float, bytes]:
    """Run cmd: wall, CPU (user + system, its children included), peak RSS in
    MB, and the last 64 kB of its output when stdout is a pipe.  Through
    GNU time when there is one: a child forked from this process would
    count this process's memory at the fork as its own."""
    report = None
    if os.path.exists(TIME):
        fd, report = tempfile.mkstemp(prefix="simcmd-time-")
        os.close(fd)
        cmd = [TIME, "-q", "-f", "%M", "-o", report, *cmd]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdin=stdin, stdout=stdout, cwd=cwd, env=env)
    tail = b""
    if stdout is subprocess.PIPE:
        while True:
            chunk = proc.stdout.read(1 << 20)
            if not chunk:
                break
            tail = (tail + chunk)[-65536:]
        proc.stdout.close()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"bench/simulate_cmd.py: failed: {' '.join(cmd)}")
    cpu = usage.ru_utime + usage.ru_stime     # GNU time's own share is a millisecond; it prints only 10 ms steps
    if report is None:
        return wall, cpu, usage.ru_maxrss / 1024.0, tail
    with open(report, encoding="ascii") as fh:
        kb = fh.read().split()[-1]
    os.unlink(report)
    return wall, cpu, int(kb) / 1024.0, tail


def engine(build, flat_path: str) -> tuple[float, float, float, dict[str, int]]:
    """The simulator alone on a flat scene file: wall, CPU, peak MB, its N
    counters; the trace drained from a pipe."""
    with open(flat_path, "rb") as flat:
        wall, cpu, mb, tail = timed(build.run_cmd, stdin=flat, stdout=subprocess.PIPE, cwd=build.workdir)
    counts = {}
    for line in tail.decode("ascii", "replace").splitlines():
        w = line.split()
        if len(w) == 3 and w[0] == "N":
            counts[w[1]] = int(w[2])
    return wall, cpu, mb, counts


def command(scene_path: str, out: str, lang: str, converter: str, root: str = ROOT) -> tuple[float, float, float, int]:
    """Wall, CPU (the command and its simulator), peak RSS in MB of the
    command's largest process, and the trace's size in bytes; the command
    of the checkout `root`."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([root, os.path.join(root, "runtimes", "python")]))
    extra = [] if converter == "auto" else ["--converter", converter]     # auto: the default, and any version's
    # run from the checkout: `python -m` puts the current folder first on the path, before PYTHONPATH, so from
    # another checkout's folder it would import that one's max2code
    if os.path.exists(out):     # freeing the last run's trace (tens of MB) is not this run's work
        os.unlink(out)
    wall, cpu, mb, _ = timed([sys.executable, "-m", "max2code", "simulate", "--lang", lang, scene_path, "-o", out,
                              "-q", *extra], env=env, cwd=root)
    return wall, cpu, mb, os.path.getsize(out)


def compiled(root: str) -> None:
    """The checkout's Python modules compiled to bytecode, as an install
    does (`pip install` compiles them, and a first run writes them): with
    PYTHONDONTWRITEBYTECODE set, as on the project's machine, every command
    would compile them again from source, some 0.1 s."""
    for sub in ("max2code", os.path.join("runtimes", "python", "max2code_rt")):
        subprocess.run([sys.executable, "-m", "compileall", "-q", os.path.join(root, sub)], check=True,
                       stdout=subprocess.DEVNULL, stdin=subprocess.DEVNULL)


def best(results: list[tuple]) -> tuple:
    """The least wall time and the least CPU time of several runs, the
    largest peak, and the rest of the last."""
    return (min(r[0] for r in results), min(r[1] for r in results), max(r[2] for r in results), *results[-1][3:])


def measure(build, flat_path: str, path: str, out: str, lang: str, cmds: list[tuple[str, str, str]], repeat: int):
    """The engine and each command (label, checkout, converter), run in
    turn `repeat` times (so that a change of the machine's load falls on
    all alike); best() of each."""
    runs: dict[str, list] = {}
    for _ in range(repeat):
        runs.setdefault("engine", []).append(engine(build, flat_path))
        for label, root, conv in cmds:
            runs.setdefault(label, []).append(command(path, out, lang, conv, root))
    return best(runs["engine"]), [(label, best(runs[label])) for label, _, _ in cmds]


HEAD = (f"{'scene':>14} {'events':>8} {'conv':>6} {'engine wall':>11} {'cpu':>6} {'MB':>4} "
        f"{'cmd wall':>8} {'cpu':>6} {'MB':>4} {'ratio':>5} {'cpu ratio':>9} {'trace MB':>8}")


def row(name, counts, conv, eng, cmd) -> str:
    return (f"{name:>14} {handled(counts):>8} {conv:>6} {eng[0]:>11.3f} {eng[1]:>6.3f} {eng[2]:>4.0f} "
            f"{cmd[0]:>8.3f} {cmd[1]:>6.3f} {cmd[2]:>4.0f} {cmd[0] / eng[0]:>5.2f} {cmd[1] / eng[1]:>9.2f} "
            f"{cmd[3] / 1e6:>8.1f}")


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="bench/simulate_cmd.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--lang", default="c")
    p.add_argument("--sizes", default="10000,100000")
    p.add_argument("--events", type=float, default=3e5, help="events per run (about; default 3e5)")
    p.add_argument("--fraction", type=float, default=0.25)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--converter", default="auto", choices=("auto", "c", "python", "both"),
                   help="the command's trace converter (both: c, then python)")
    p.add_argument("--repeat", type=int, default=1,
                   help="runs of each, in turn; the least wall and the least CPU shown (default 1)")
    p.add_argument("--against", metavar="CHECKOUT",
                   help="also time the command of another checkout of max2code (e.g. an older commit), in turn "
                        "with this one's")
    p.add_argument("--examples", action="store_true", help="time the example scenes instead of gases")
    args = p.parse_args(argv)
    convs = ("c", "python") if args.converter == "both" else (args.converter,)
    cmds = [(conv, ROOT, conv) for conv in convs]
    if args.against:
        cmds.append(("other", os.path.abspath(args.against), "auto"))
    for root in sorted({root for _, root, _ in cmds}):
        compiled(root)
    print(HEAD)
    with tempfile.TemporaryDirectory(prefix="simcmd-") as tmp:
        out, flat_path = os.path.join(tmp, "trace.jsonl"), os.path.join(tmp, "scene.flat")
        if args.examples:
            for path in sorted(glob.glob(os.path.join(ROOT, "examples", "*.json"))):
                scene = load_scene(path)
                build = build_simulator(args.lang, scene.effects, scene.taylor_order)
                with open(flat_path, "w", encoding="ascii") as fh:
                    fh.write(compile_scene(scene))
                eng, got = measure(build, flat_path, path, out, args.lang, cmds, args.repeat)
                for label, cmd in got:
                    print(row(os.path.basename(path)[:-5][:14], eng[3], label, eng, cmd))
        else:
            probe = parse_scene(json.dumps(gas(2, args.fraction, 1.0, args.seed)), "gas")
            build = build_simulator(args.lang, probe.effects, probe.taylor_order)
            for n in (int(float(x)) for x in args.sizes.split(",") if x):
                guess = 0.05 * args.events / (n * 1.0 / 0.01)
                scene = parse_scene(json.dumps(gas(n, args.fraction, guess, args.seed)), "gas")
                _, _, counts = run(build, compile_scene(scene))
                end = float(f"{guess * args.events / max(handled(counts), 1):.4g}")
                raw = gas(n, args.fraction, end, args.seed)
                path = os.path.join(tmp, f"gas-{n}.json")
                with open(path, "w", encoding="utf-8") as fh:
                    json.dump(raw, fh)
                with open(flat_path, "w", encoding="ascii") as fh:
                    fh.write(compile_scene(parse_scene(json.dumps(raw), path)))
                eng, got = measure(build, flat_path, path, out, args.lang, cmds, args.repeat)
                for label, cmd in got:
                    print(row(f"gas {n}", eng[3], label, eng, cmd))
    print("engine: the simulator's process on the flat scene, its trace drained into a pipe; cmd: `max2code "
          "simulate -o TRACE -q --converter CONV` in a fresh process (other: the --against checkout's command) (scene check, build cache look-up, run, JSON "
          "trace; its CPU includes the simulator's); ratio: cmd wall / engine wall; cpu ratio: cmd CPU / engine "
          f"CPU; MB: peak resident memory (the command's: of its largest process); load average at the end: "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
