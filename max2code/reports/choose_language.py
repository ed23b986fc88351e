"""`max2code choose-language [EQ.mxm] [--seconds S] [--write FILE]`: what each
target language gives for an equation, measured on this machine.

For the equation (default the bundled two circles): the code is generated
and compiled per language into harnesses, which are kept (BUILD/reuse/,
max2code/toolchain/cache.py) and reused by later runs with the same inputs;
the build time reported is what making them took.  Then rounds, the
languages taking turns in a rotating order, each round one harness run per
language and entry: the ns per prediction of `NAME_toc` (the selected
variant's polynomial over the whole horizon, then the runtime's root
solver) and of `NAME_toc_exact` (`--exact`, default options) on the same
random motions (drawn as `max2code cases` draws parameters); the table gives
the median over the rounds and their spread (smallest to largest), since
one pass on a shared machine is noise.

The budget (`--seconds`) covers everything, and a share of it is kept for
timing: builds get the budget less that share (`timing_reserve`), a
language whose build would not fit in what builds have left is not built,
and said so before the time is spent, the cheapest languages first, so
that successive runs add the next ones; a build still going when the builds'
time ends is stopped, and so is a harness run still going at the deadline;
rounds go on while the next one, by its runs' last durations, ends in time.  The run
reports its accounting (preparing, builds, timing, total).  Besides speed
the table states what each language offers: single precision
(`--real=float`), `#line` debugging into the .mxm, reentrancy of the
entries, what must be installed and how the code links.
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import random
import shutil
import statistics
import subprocess
import sys
import time

from max2code.errors import Max2CodeError
from max2code.paths import equation as bundled_equation
from max2code.targets import LANGUAGES, target

BEGIN = "<!-- choose-language:begin (written by max2code choose-language) -->"
END = "<!-- choose-language:end -->"
HORIZON = 5.0
MIN_ROUNDS = 3
PASSES = 3            # passes over the motions per harness run (the run reports their median)

# entries that keep state between calls in module variables (docs/exact-motion.md): Modula-2's driver
NOT_REENTRANT = {"m2": "NAME_toc yes; NAME_toc_exact no (the driver's state is in module variables)"}


# seconds a language's generation and builds take when this machine has not made them yet (unloaded: the
# Modula-2 build alone is about 50 s); once made, the measured time is used, and the programs are reused
FIRST_SECONDS = {"python": 20.0, "c": 30.0, "rust": 60.0, "m2": 90.0}
TIMING_SHARE = 0.25   # of the budget kept for timing rounds when a language is to be built ...
TIMING_MIN_S = 10.0   # ... at least so many seconds (never more than half the budget)


def timing_reserve(seconds: float) -> float:
    """Seconds of a `seconds` budget that builds leave for timing rounds."""
    return min(0.5 * seconds, max(TIMING_MIN_S, TIMING_SHARE * seconds))


def planned_seconds(lang: str, last: dict | None) -> float:
    """What making `lang` is planned to take: its last time here when it
    finished, else FIRST_SECONDS (never made here, or stopped when last
    tried: the runtime's and the generator's builds are incremental, so
    what a stopped build made is kept and the next one goes on from it)."""
    if last is not None and last["finished"]:
        return last["seconds"]
    return FIRST_SECONDS.get(lang, 30.0)


@dataclasses.dataclass
class Lang:
    name: str
    build_s: float | None      # seconds its generation and builds took when made (None: not made)
    poly: object = None        # toolchain.exact.ExactHarness of NAME_toc (or the plain polynomial)
    exact: object = None       # ... of NAME_toc_exact, None when the equation has none
    reused: bool = False       # built by an earlier run
    spent_s: float = 0.0       # seconds this run spent generating and building it
    note: str = ""             # why it is not timed
    toc: list = dataclasses.field(default_factory=list)       # ns per prediction, one per round
    toc_exact: list = dataclasses.field(default_factory=list)


def _motions(path: str, n: int, seed: int) -> tuple[list[dict], bool, str]:
    """n parameter draws for the equation, whether it has NAME_toc_exact, and why not."""
    from max2code.conformance.user_cases import _draw, load_equation

    eq = load_equation(path)
    rng = random.Random(seed)
    exact = eq.exact is not None or eq.windowed
    return [_draw(eq, rng) for _ in range(n)], exact, "" if exact else eq.why_not_exact


def _within(deadline: float, fn, *args):
    """fn(*args) in a child process (its own process group, so that the
    compilers and Maxima it starts go with it), stopped at `deadline`
    (time.perf_counter()).  Returns (finished, its result or error text,
    seconds)."""
    import multiprocessing
    import signal

    ctx = multiprocessing.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)

    def child():
        os.setpgid(0, 0)
        try:
            send.send((True, fn(*args)))
        except BaseException as exc:            # noqa: BLE001 - every failure goes to the parent as text
            send.send((False, str(exc) or type(exc).__name__))

    t0 = time.perf_counter()
    proc = ctx.Process(target=child, daemon=True)
    proc.start()
    with contextlib.suppress(OSError):
        os.setpgid(proc.pid, proc.pid)          # the child does the same: whichever runs first
    send.close()
    answer = None
    if recv.poll(max(0.0, deadline - time.perf_counter())):
        try:
            answer = recv.recv()
        except EOFError:
            answer = (False, "the child process ended without an answer")
    if answer is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.kill()
    proc.join()
    seconds = time.perf_counter() - t0
    if answer is None:
        return False, None, seconds
    ok, value = answer
    return ok, value, seconds


def _make(path: str, lang: str, exact: bool, key: str) -> dict:
    """Generate the equation's code for `lang` and compile its harnesses into
    the reuse folder of `key` (run in a child process); the entry."""
    from max2code.generate.pipeline import GenerateRequest, generate_file
    from max2code.toolchain import cache, toolchain
    from max2code.toolchain.exact import build_exact_harness, build_poly_harness

    t0 = time.perf_counter()
    with cache.building(key) as d:
        toolchain(lang).exact_harness_build("harness", "harness", str(d))      # the runtime, built if needed
        req = GenerateRequest(path=path, lang=lang, out_name="generated")
        plain = generate_file(req)
        fn, sel = plain.function, plain.selection
        coef, selected, degree = (sel.name, True, sel.max_degree) if sel is not None else (fn.name, False, fn.degree)
        h = build_poly_harness(lang, plain.text, fn.params, coef, selected, degree, str(d / "toc"))
        entry = {"toc": [h.workdir, h.cmd, h.nparams], "exact": None}
        if exact:
            g = generate_file(dataclasses.replace(req, exact=True))
            x = build_exact_harness(lang, g.text, g.exact, str(d / "exact"))
            entry["exact"] = [x.workdir, x.cmd, x.nparams]
        entry["seconds"] = time.perf_counter() - t0
        cache.save(key, entry)
    return entry


def _harnesses(lang: str, entry: dict):
    from max2code.toolchain.exact import ExactHarness

    poly = ExactHarness(lang, *entry["toc"])
    exact = ExactHarness(lang, *entry["exact"]) if entry.get("exact") else None
    return poly, exact


def prepare(path: str, langs: list[str], motions: int, seed: int, deadline: float, say,
            build_deadline: float | None = None) -> tuple[list[Lang], dict]:
    """The motions and every language's harnesses, reused when an earlier run
    made them from the same inputs, else made by `build_deadline` (default
    `deadline`), the cheapest first: a language whose making would not fit in
    what is left (planned_seconds) is not made, and said so before any time is
    spent on it; one that is still being made at `build_deadline` is stopped."""
    from max2code.toolchain import cache, toolchain

    info: dict = {"motions_s": 0.0}
    key = cache.equation_key(path, motions=motions, seed=seed, what="motions")
    got = cache.load(key)
    if got is not None:
        rows, exact, why = got["rows"], got["exact"], got["why"]
    else:
        ok, value, secs = _within(deadline, _motions, path, motions, seed)
        info["motions_s"] = secs
        if not ok:
            raise Max2CodeError(f"max2code choose-language: error: {path}: " + (
                value if value is not None else "reading the equation and drawing its motions did not finish "
                f"within the budget ({secs:.1f} s); give more --seconds"))
        rows, exact, why = value
        if key is not None:
            with cache.building(key):
                cache.save(key, {"rows": rows, "exact": exact, "why": why})
    info.update(rows=rows, exact=exact, why_not_exact=why)
    taken = cache.seconds_taken()
    out = {lang: Lang(lang, None) for lang in langs}
    keys = {lang: cache.equation_key(path, lang=lang, exact=exact, what="harnesses",
                                  tools=toolchain(lang).tool_versions()) for lang in langs}
    todo = []
    for lang in langs:
        entry = cache.load(keys[lang])
        if entry is not None:
            lg = out[lang]
            lg.build_s, lg.reused = entry["seconds"], True
            lg.poly, lg.exact = _harnesses(lang, entry)
        else:
            last = taken.get(lang)
            todo.append((planned_seconds(lang, last), lang, last))
    build_deadline = deadline if build_deadline is None else build_deadline
    for expect, lang, last in sorted(todo, key=lambda x: x[0]):
        lg = out[lang]
        left = build_deadline - time.perf_counter()
        how = ("as when last made here" if last and last["finished"] else
               f"going on from a build stopped at {last['seconds']:.0f} s here" if last else
               "before it was ever made here")
        if expect > left:
            lg.note = (f"not built: generating and building it takes about {expect:.0f} s ({how}), more than the "
                       f"{max(left, 0.0):.0f} s the budget leaves for builds; a run with --seconds "
                       f"{_enough(expect):.0f} or more builds it once, later runs reuse it")
            say(f"choose-language: {lang}: {lg.note}")
            continue
        say(f"choose-language: {lang}: generating and building (about {expect:.0f} s, {how}; {left:.0f} s left)")
        work_key = keys[lang] or f"scratch-{os.getpid()}-{lang}"      # an equation whose reads cannot be known
        if keys[lang] is None:
            info.setdefault("scratch", []).append(cache.folder(work_key))
        ok, value, secs = _within(build_deadline, _make, path, lang, exact, work_key)
        lg.spent_s = secs
        cache.remember_seconds(lang, secs, ok)
        if ok:
            lg.build_s = value["seconds"]
            lg.poly, lg.exact = _harnesses(lang, value)
        elif value is None:
            lg.note = (f"not built: still building when the budget's time for builds ended ({secs:.0f} s); what "
                       f"it made is kept: the next run goes on from it, and a run with --seconds {_enough(secs):.0f} "
                       "or more finishes it, later runs reuse it")
            say(f"choose-language: {lang}: {lg.note}")
        else:
            raise Max2CodeError(f"max2code choose-language: error: {lang}: {value}")
    return [out[lang] for lang in langs], info


def _enough(build_s: float) -> float:
    """A budget whose time for builds holds a build of `build_s` seconds and motions."""
    seconds = build_s + 10.0
    while seconds - timing_reserve(seconds) < build_s + 5.0:
        seconds += 5.0
    return seconds


def measure(path: str, langs: list[str], seconds: float = 60.0, motions: int = 200, seed: int = 13,
            progress: bool = True, rounds: int | None = None, start: float | None = None) -> tuple[list[Lang], dict]:
    """Make (or reuse) every language's harnesses, then interleaved rounds
    while a round's next run fits in the budget: `seconds` from `start`
    (default now) cover everything, and no step is begun that its last
    duration says would not end in time; a harness run is stopped at the
    deadline (its round is then left out).  `rounds`: at most so many.
    Builds end `timing_reserve(seconds)` before the deadline."""
    start = time.perf_counter() if start is None else start
    deadline = start + seconds

    def say(text):
        if progress:
            print(text, file=sys.stderr, flush=True)

    out, info = prepare(path, langs, motions, seed, deadline, say, deadline - timing_reserve(seconds))
    t_timing = time.perf_counter()
    rows = info.pop("rows")
    params = list(rows[0])
    toc_rows = [[m[k] for k in params] + [HORIZON] for m in rows]
    exact_rows = [[m[k] for k in params] + [HORIZON, 1.0, 1.0, 0.0, 0.0] for m in rows]
    timed = [lg for lg in out if lg.poly is not None]
    last: dict[tuple[str, str], float] = {}         # each harness run's last duration
    r, why_stop = 0, "the budget"
    while timed and (rounds is None or r < rounds):
        order = timed[r % len(timed):] + timed[:r % len(timed)]     # a rotating order: no language always first
        runs = [(lg, "toc", lg.poly, toc_rows) for lg in order] + \
               [(lg, "exact", lg.exact, exact_rows) for lg in order if lg.exact is not None]
        runs.sort(key=lambda x: order.index(x[0]))
        if sum(last.get((lg.name, kind), 0.0) for lg, kind, _, _ in runs) > deadline - time.perf_counter():
            break                       # the next round, by its runs' last durations, would not end in time
        got, complete = [], True
        for lg, kind, h, data in runs:
            left = deadline - time.perf_counter()
            if left <= 0:
                complete = False
                break
            t0 = time.perf_counter()
            try:
                _, ns = h.run(data, reps=PASSES, timeout=left)
            except subprocess.TimeoutExpired:
                complete = False
                break
            last[lg.name, kind] = time.perf_counter() - t0
            got.append((lg, kind, ns))
            if progress:
                el = time.perf_counter() - start
                print(f"\rchoose-language: round {r + 1}: {lg.name:<6s} ({el:5.1f} s, {max(0.0, seconds - el):4.1f} s "
                      "of the budget left)        ", end="", file=sys.stderr, flush=True)
        if not complete:
            break
        for lg, kind, ns in got:
            (lg.toc if kind == "toc" else lg.toc_exact).append(ns)
        r += 1
    else:
        why_stop = "--rounds" if timed else "no language built"
    for d in info.pop("scratch", []):
        shutil.rmtree(d, ignore_errors=True)
    end = time.perf_counter()
    if progress and timed:
        print(f"\rchoose-language: {r} rounds in {end - start:.1f} s" + " " * 40, file=sys.stderr)
    info.update(rounds=r, motions=motions, stopped_by=why_stop, budget=seconds,
                prepare_s=t_timing - start, build_s=sum(lg.spent_s for lg in out), timing_s=end - t_timing,
                total_s=end - start)
    return out, info


def accounting(out: list[Lang], info: dict) -> str:
    """The run's use of its budget, in one sentence."""
    reused = [lg.name for lg in out if lg.reused]
    made = [f"{lg.name} {lg.spent_s:.1f} s" for lg in out if lg.spent_s and lg.build_s is not None]
    stopped = [f"{lg.name} {lg.spent_s:.1f} s" for lg in out if lg.spent_s and lg.build_s is None]
    parts = [f"budget {info['budget']:g} s",
             f"preparing {info['prepare_s']:.1f} s (motions {info['motions_s']:.1f} s; builds "
             + (", ".join(made) if made else "none")
             + (f"; reused {', '.join(reused)}" if reused else "")
             + (f"; stopped at the deadline {', '.join(stopped)}" if stopped else "") + ")",
             f"timing {info['timing_s']:.1f} s ({info['rounds']} rounds)",
             f"total {info['total_s']:.1f} s"]
    over = info["total_s"] - info["budget"]
    return "Accounting: " + "; ".join(parts) + (f"; over the budget by {over:.1f} s" if over > 0.05 else "") + "."


def _ns(values: list) -> str:
    if not values:
        return "-"
    med = statistics.median(values)
    return f"{med:,.0f} ({min(values):,.0f}-{max(values):,.0f})"


def facts(lang: str) -> dict:
    """What the language offers besides speed (from its target's properties)."""
    tgt = target(lang)
    line = "yes: `#line` into the .mxm (compiler errors and debuggers show .mxm lines)" if tgt.line_directive \
        else "no: origin comments name the .mxm line"
    single = f"yes ({tgt.single_type})" if tgt.single_type else "no (double only)"
    return {"single": single, "line": line, "reentrant": NOT_REENTRANT.get(lang, "yes"),
            "requires": tgt.requires, "links": tgt.links}


def table(langs: list[Lang], info: dict, name: str, command: str) -> str:
    few = "" if info["rounds"] >= MIN_ROUNDS or info["stopped_by"] != "the budget" else (
        f"  Only {info['rounds']} rounds fitted in the budget: the medians are of few runs (give more --seconds).")
    head = (f"Measured by `{command}` ({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}): {name}, "
            f"{info['motions']} random motions (parameters drawn as `max2code cases` draws them), horizon "
            f"{HORIZON:g} s; ns per prediction, median over {info['rounds']} interleaved rounds (smallest-largest "
            f"in brackets); build: the seconds generating the code and compiling its harnesses took when they were "
            f"made (reused: by an earlier run with the same inputs)."
            + ("" if info["exact"] else f"  No `NAME_toc_exact`: {info['why_not_exact']}.") + few
            + "\n\n" + accounting(langs, info))
    lines = ["| language | ns per prediction (`NAME_toc`) | with `--exact` (`NAME_toc_exact`) | build s "
             "| single precision (`--real=float`) | `#line` debugging | reentrant | must be installed "
             "| how it links into a program |",
             "|---|---|---|---|---|---|---|---|---|"]
    notes = []
    for lg in langs:
        f = facts(lg.name)
        build = "-" if lg.build_s is None else f"{lg.build_s:.1f}" + (" (reused)" if lg.reused else "")
        lines.append(f"| {lg.name} | {_ns(lg.toc)} | {_ns(lg.toc_exact)} | {build} | {f['single']} | "
                     f"{f['line']} | {f['reentrant']} | {f['requires']} | {f['links']} |")
        if lg.note:
            notes.append(f"- {lg.name}: {lg.note}.")
    return head + "\n\n" + "\n".join(lines) + "\n" + ("\n" + "\n".join(notes) + "\n" if notes else "")


def write(path: str, text: str) -> None:
    with open(path, encoding="utf-8") as fh:
        doc = fh.read()
    a, b = doc.find(BEGIN), doc.find(END)
    if a < 0 or b < a:
        raise Max2CodeError(f"{path}: error: expected the markers {BEGIN} and {END}")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(doc[:a + len(BEGIN)] + "\n" + text + doc[b:])


def _positive(kind):
    def parse(text: str):
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not v > 0:
            raise argparse.ArgumentTypeError(f"must be positive, got {text!r}")
        return v
    return parse


def main(argv: list[str]) -> int:
    start = time.perf_counter()
    ap = argparse.ArgumentParser(prog="max2code choose-language", description=__doc__.split("\n\n")[0])
    ap.add_argument("file", nargs="?", help="the .mxm file (default: the bundled circle-circle)")
    ap.add_argument("--seconds", type=_positive(float), default=60.0,
                    help="time budget, everything included (default 60): harnesses made by an earlier run from "
                         "the same inputs are reused; builds get the budget less a quarter (at least 10 s) kept "
                         "for timing, and a build that does not fit there is left out, and said so")
    ap.add_argument("--rounds", type=_positive(int), help="at most this many rounds (default: while the budget lasts)")
    ap.add_argument("--motions", type=_positive(int), default=200, help="random motions timed per round (default 200)")
    ap.add_argument("--langs", default=",".join(LANGUAGES), metavar="LIST",
                    help=f"languages, comma-separated (default {','.join(LANGUAGES)})")
    ap.add_argument("--write", metavar="FILE", help="replace the table between the choose-language markers of FILE "
                                                     "(docs/using-generated-code.md)")
    ap.add_argument("--quiet", "-q", action="store_true", help="no progress line")
    args = ap.parse_args(argv)
    langs = [x.strip() for x in args.langs.split(",") if x.strip()]
    unknown = [x for x in langs if x not in LANGUAGES]
    if unknown or not langs:
        raise Max2CodeError(f"max2code choose-language: error: --langs: unknown {', '.join(unknown) or 'empty list'} "
                            f"(known: {', '.join(LANGUAGES)})")
    path = args.file or str(bundled_equation("circle-circle"))
    if not os.path.isfile(path):
        raise Max2CodeError(f"{path}: error: no such file")
    rows, info = measure(path, langs, args.seconds, args.motions, progress=not args.quiet, rounds=args.rounds,
                         start=start)
    name = os.path.basename(path)
    command = "max2code choose-language" + (f" {name}" if args.file else "") + \
        (" --write " + os.path.basename(args.write) if args.write else "")
    text = table(rows, info, "the bundled two circles (circle-circle.mxm)" if not args.file else name, command)
    sys.stdout.write(text)
    if not args.quiet:
        print("choose-language: " + accounting(rows, info), file=sys.stderr)
    if args.write:
        write(args.write, text)
    return 0
