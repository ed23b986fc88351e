"""`max2code simulate` and `max2code crosscheck` (docs/simulator.md)."""
from __future__ import annotations

import argparse
import functools
import sys

from max2code.errors import ArgumentParser, Max2CodeError
from max2code.record import Record
from max2code.sim.scene import DEFAULT_MAX_EVENTS, SceneError, check_scene, load_scene
from max2code.sim.scene_c import read_scene
from max2code.sim.simulate import CONVERTERS, LANGS, RunStopped, SimulateError, Trace, run_scene, stream_scene, stop_line
from max2code.textio import check_output, open_output


class SimCliError(Max2CodeError):
    pass


def _load(path: str, check: bool = True):
    try:
        return load_scene(path, check=check)
    except SceneError as exc:
        raise SimCliError(str(exc)) from None


def _run(scene, lang: str, progress: bool) -> Trace:
    try:
        return run_scene(scene, lang, progress=progress)
    except SimulateError as exc:
        raise SimCliError(str(exc)) from None


def simulate_main(argv: list[str]) -> int:
    p = ArgumentParser(prog="max2code simulate",
                       description="Run a JSON scene in one runtime and write its trace: one JSON line per "
                                   "event, then the final state and the statistics.  The trace is written as "
                                   "the simulator runs (memory does not grow with the number of events).")
    p.add_argument("scene", help="scene file (JSON, docs/simulator.md)")
    p.add_argument("--lang", choices=LANGS, default="c", help="which runtime's simulator (default c)")
    p.add_argument("-o", "--output", default="-", help="write the trace here ('-': standard output, the default)")
    p.add_argument("--no-frames", action="store_true", help="leave the frame events out of the trace")
    p.add_argument("--max-events", type=_count, metavar="N",
                   help="stop with an error after N events (collisions, inputs, frames); default: the scene's "
                        f"max_events ({DEFAULT_MAX_EVENTS:,})")
    p.add_argument("--converter", choices=CONVERTERS, default="auto",
                   help="convert the flat trace to JSON in C (built with gcc on first use) or in Python (the "
                        "same bytes, slower); default auto: C when gcc builds it, else Python with a note on stderr")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary on stderr")
    args = p.parse_args(argv)
    check_output(args.output)
    # the common case read, checked and compiled in C; else in Python, the last checks while the simulator
    # reads the scene
    # (--max-events is written into the flat scene, which the simulator counts its handled events against:
    # such a run is read in Python)
    scene = read_scene(args.scene) if args.max_events is None else None
    check = None
    if scene is None:
        scene = _load(args.scene, check=False)
        if args.max_events is not None:
            scene.max_events = args.max_events
        check = functools.partial(check_scene, scene)
    limit = scene.max_events
    try:
        with open_output(args.output) as out:
            raw = getattr(out, "buffer", None)       # all of the trace as bytes, when the stream has a buffer
            write, write_bytes = out.write, None
            if raw is not None:
                out.flush()
                write_bytes = raw.write
                write = lambda text: write_bytes(text.encode("utf-8"))      # noqa: E731
            try:
                stats = stream_scene(scene, args.lang, write, frames=not args.no_frames, max_events=limit,
                                     progress=not args.quiet and sys.stderr.isatty(), converter=args.converter,
                                     warn=lambda line: print(line, file=sys.stderr), check=check,
                                     write_bytes=write_bytes)
            except RunStopped as exc:
                if exc.t is None:
                    raise           # nothing was simulated (a scene the simulator refused): no trace
                # the events up to the stop stay in the trace (a file is kept), closed by one line saying why
                write(stop_line(exc))
                stopped = exc
            else:
                stopped = None
    except (SimulateError, SceneError) as exc:
        raise SimCliError(str(exc)) from None
    if stopped is not None:
        where = "" if args.output == "-" else f"; the trace up to then is in {args.output}"
        raise SimCliError(f"{stopped}{where}")
    if not args.quiet:
        ev = stats["events"]
        used = ", ".join(f"{k} {v}" for k, v in stats["predictions"].items())
        counts = ", ".join(f"{k} {v}" for k, v in ev.items())     # every counter of the trace, by name
        print(f"max2code simulate: {scene.path} in {args.lang}: {counts}; effects: "
              f"{', '.join(scene.effects) or 'none'}; predictions per variant: {used}", file=sys.stderr)
    return 0


def _count(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text!r}")
    return v


class Difference(Record):
    _fields = ("index", "what")

    def __init__(self, index: int, what: str):
        self.index = index      # event index, or -1 for the final state
        self.what = what


def compare(a: Trace, b: Trace, rel: float = 1e-9) -> Difference | None:
    """The first place where two traces disagree: kinds, bodies, features,
    times within `rel` relative; then the final states."""
    for k, (x, y) in enumerate(zip(a.events, b.events)):
        if x["kind"] != y["kind"] or x.get("bodies") != y.get("bodies") or x.get("feature") != y.get("feature"):
            return Difference(k, f"event {k}: {a.lang} has {_short(x)}, {b.lang} has {_short(y)}")
        dt = abs(x["t"] - y["t"])
        if dt > rel * max(abs(x["t"]), abs(y["t"])):
            return Difference(k, f"event {k} ({_short(x)}): times differ by {dt:.3g} s "
                                 f"({dt / max(abs(x['t']), abs(y['t'])):.3g} relative)")
    if len(a.events) != len(b.events):
        k = min(len(a.events), len(b.events))
        extra, who = (a.events[k], a.lang) if len(a.events) > k else (b.events[k], b.lang)
        return Difference(k, f"event {k}: only {who} has it: {_short(extra)}")
    for fa, fb in zip(a.final["bodies"], b.final["bodies"]):
        for key in ("position", "velocity"):
            for u, v in zip(fa[key], fb[key]):
                if abs(u - v) > rel * max(1.0, abs(u), abs(v)):
                    return Difference(-1, f"final {key} of {fa['body']}: {u!r} in {a.lang}, {v!r} in {b.lang}")
    return None


def _short(e: dict) -> str:
    s = f"{e['kind']} at t={e['t']!r}"
    if "bodies" in e:
        s += " of " + "+".join(e["bodies"])
    if "feature" in e:
        s += f" ({e['feature']})"
    return s


def crosscheck(scene, langs=LANGS, progress: bool = False) -> tuple[dict[str, Trace], list[str]]:
    """Run the scene in every language; returns the traces and the
    disagreements with the first language (empty: all agree)."""
    traces = {lang: _run(scene, lang, progress) for lang in langs}
    ref = traces[langs[0]]
    problems = []
    for lang in langs[1:]:
        d = compare(ref, traces[lang])
        if d is not None:
            problems.append(f"{ref.lang} vs {lang}: {d.what}")
    return traces, problems


def crosscheck_main(argv: list[str]) -> int:
    p = ArgumentParser(prog="max2code crosscheck",
                                description="Run a scene in all four runtimes and report agreement, or the first "
                                            "event where they differ and by how much.")
    p.add_argument("scenes", nargs="+", help="scene files (JSON)")
    p.add_argument("--langs", default=",".join(LANGS), help=f"comma-separated runtimes (default {','.join(LANGS)})")
    args = p.parse_args(argv)
    langs = tuple(x for x in args.langs.split(",") if x)
    for lang in langs:
        if lang not in LANGS:
            raise SimCliError(f"--langs: unknown runtime '{lang}' (expected {', '.join(LANGS)})")
    status = 0
    for path in args.scenes:
        scene = _load(path)
        traces, problems = crosscheck(scene, langs)
        ref = traces[langs[0]]
        same_bytes = all(t.raw == ref.raw for t in traces.values())
        n = len(ref.events)
        if problems:
            status = 1
            for pr in problems:
                print(f"{path}: DIFFER: {pr}")
        else:
            worst = 0.0
            for t in traces.values():
                for x, y in zip(ref.events, t.events):
                    if x["t"] != y["t"]:
                        worst = max(worst, abs(x["t"] - y["t"]) / max(abs(x["t"]), abs(y["t"])))
            print(f"{path}: {' '.join(langs)} agree on {n} events"
                  + (" (identical bytes)" if same_bytes else f" (largest time difference {worst:.3g} relative)"))
    return status
