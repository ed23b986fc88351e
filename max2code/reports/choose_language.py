"""`max2code choose-language [EQ.mxm] [--seconds S] [--write FILE]`: what each
target language gives for an equation, measured on this machine.

For the equation (default the bundled two circles): the code is generated
and compiled per language (the build time is measured: generation of the
file and compilation of its harnesses); then rounds, the languages taking
turns in a rotating order, each round one harness run per language and
entry: the ns per prediction of `NAME_toc` (the selected variant's
polynomial over the whole horizon, then the runtime's root solver) and of
`NAME_toc_exact` (`--exact`, default options) on the same random motions
(drawn as `max2code cases` draws parameters).  Rounds go on until the time
budget is spent (at least MIN_ROUNDS); the table gives the median over the
rounds and their spread (smallest to largest), since one pass on a shared
machine is noise.  Besides speed it states what each language offers:
single precision (`--real=float`), `#line` debugging into the .mxm,
reentrancy of the entries, what must be installed and how the code links.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import random
import statistics
import sys
import tempfile
import time

from max2code.errors import Max2CodeError
from max2code.paths import equation as bundled_equation
from max2code.progress import bar
from max2code.targets import LANGUAGES, target

BEGIN = "<!-- choose-language:begin (written by max2code choose-language) -->"
END = "<!-- choose-language:end -->"
HORIZON = 5.0
MIN_ROUNDS = 3
PASSES = 3            # passes over the motions per harness run (the run reports their median)

# entries that keep state between calls in module variables (docs/exact-motion.md): Modula-2's driver
NOT_REENTRANT = {"m2": "NAME_toc yes; NAME_toc_exact no (the driver's state is in module variables)"}


@dataclasses.dataclass
class Lang:
    name: str
    build_s: float
    poly: object               # toolchain.exact.ExactHarness of NAME_toc (or the plain polynomial)
    exact: object | None       # ... of NAME_toc_exact, None when the equation has none
    toc: list = dataclasses.field(default_factory=list)       # ns per prediction, one per round
    toc_exact: list = dataclasses.field(default_factory=list)


def _motions(path: str, n: int, seed: int) -> tuple[list[dict], bool, str]:
    """n parameter draws for the equation, whether it has NAME_toc_exact, and why not."""
    from max2code.conformance.user_cases import _draw, load_equation

    eq = load_equation(path)
    rng = random.Random(seed)
    exact = eq.exact is not None or eq.windowed
    return [_draw(eq, rng) for _ in range(n)], exact, "" if exact else eq.why_not_exact


def build(path: str, langs: list[str], workdir: str, exact: bool, progress: bool) -> list[Lang]:
    """Generate the equation's code for every language (one after the other:
    Python), then compile the harnesses two at a time (the runtimes' own
    builds first, one at a time, so that no two makes share a folder).  A
    language's build time: its generation plus its compilations."""
    from concurrent.futures import ThreadPoolExecutor

    from max2code.generate.pipeline import GenerateRequest, generate_file
    from max2code.toolchain import toolchain
    from max2code.toolchain.exact import build_exact_harness, build_poly_harness

    seconds = {lang: 0.0 for lang in langs}
    jobs = []
    for i, lang in enumerate(langs):
        if progress:
            bar(i, 2 * len(langs), f"{lang}: generate", prefix="choose-language")
        t0 = time.perf_counter()
        req = GenerateRequest(path=path, lang=lang, out_name="generated")
        plain = generate_file(req)
        fn, sel = plain.function, plain.selection
        coef, selected, degree = (sel.name, True, sel.max_degree) if sel is not None else (fn.name, False, fn.degree)
        jobs.append((lang, "toc", build_poly_harness, (lang, plain.text, fn.params, coef, selected, degree,
                                                        os.path.join(workdir, f"{lang}-toc"))))
        if exact:
            g = generate_file(dataclasses.replace(req, exact=True))
            jobs.append((lang, "exact", build_exact_harness, (lang, g.text, g.exact, os.path.join(workdir, f"{lang}-exact"))))
        toolchain(lang).exact_harness_build("harness", "harness", workdir)      # the runtime, built if needed
        seconds[lang] += time.perf_counter() - t0

    def run(job):
        t0 = time.perf_counter()
        h = job[2](*job[3])
        return job, h, time.perf_counter() - t0

    built: dict[tuple[str, str], object] = {}
    with ThreadPoolExecutor(max_workers=2) as pool:
        for k, (job, h, secs) in enumerate(pool.map(run, jobs)):
            built[job[0], job[1]] = h
            seconds[job[0]] += secs
            if progress:
                bar(len(langs) + (k + 1) * len(langs) // len(jobs), 2 * len(langs), f"{job[0]}: {job[1]} harness built",
                    prefix="choose-language")
    return [Lang(lang, seconds[lang], built[lang, "toc"], built.get((lang, "exact"))) for lang in langs]


def measure(path: str, langs: list[str], seconds: float = 60.0, motions: int = 200, seed: int = 13,
            progress: bool = True) -> tuple[list[Lang], dict]:
    """Build every language, then interleaved rounds until `seconds` (from the start) are spent."""
    start = time.perf_counter()
    rows, exact, why = _motions(path, motions, seed)
    info = {"rounds": 0, "motions": motions, "exact": exact, "why_not_exact": why}
    with tempfile.TemporaryDirectory(prefix="choose-language-") as tmp:
        out = build(path, langs, tmp, exact, progress)
        params = list(rows[0])
        toc_rows = [[m[k] for k in params] + [HORIZON] for m in rows]
        exact_rows = [[m[k] for k in params] + [HORIZON, 1.0, 1.0, 0.0, 0.0] for m in rows]
        r = 0
        while True:
            elapsed = time.perf_counter() - start
            if r >= MIN_ROUNDS and elapsed >= seconds:
                break
            order = out[r % len(out):] + out[:r % len(out)]     # a rotating order: no language always first
            for lg in order:
                if progress:
                    left = max(0.0, seconds - elapsed)
                    print(f"\rchoose-language: round {r + 1}: {lg.name:<6s} ({elapsed:5.1f} s, {left:4.1f} s of the "
                          f"budget left)        ", end="", file=sys.stderr, flush=True)
                _, ns = lg.poly.run(toc_rows, reps=PASSES)
                lg.toc.append(ns)
                if lg.exact is not None:
                    _, ns = lg.exact.run(exact_rows, reps=PASSES)
                    lg.toc_exact.append(ns)
            r += 1
        if progress:
            print(f"\rchoose-language: {r} rounds in {time.perf_counter() - start:.1f} s" + " " * 40, file=sys.stderr)
    info["rounds"] = r
    return out, info


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
    head = (f"Measured by `{command}` ({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}): {name}, "
            f"{info['motions']} random motions (parameters drawn as `max2code cases` draws them), horizon "
            f"{HORIZON:g} s; ns per prediction, median over {info['rounds']} interleaved rounds (smallest-largest "
            f"in brackets); build: generating the code and compiling its harnesses."
            + ("" if info["exact"] else f"  No `NAME_toc_exact`: {info['why_not_exact']}."))
    lines = ["| language | ns per prediction (`NAME_toc`) | with `--exact` (`NAME_toc_exact`) | build s "
             "| single precision (`--real=float`) | `#line` debugging | reentrant | must be installed "
             "| how it links into a program |",
             "|---|---|---|---|---|---|---|---|---|"]
    for lg in langs:
        f = facts(lg.name)
        lines.append(f"| {lg.name} | {_ns(lg.toc)} | {_ns(lg.toc_exact)} | {lg.build_s:.1f} | {f['single']} | "
                     f"{f['line']} | {f['reentrant']} | {f['requires']} | {f['links']} |")
    return head + "\n\n" + "\n".join(lines) + "\n"


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
    ap = argparse.ArgumentParser(prog="max2code choose-language", description=__doc__.split("\n\n")[0])
    ap.add_argument("file", nargs="?", help="the .mxm file (default: the bundled circle-circle)")
    ap.add_argument("--seconds", type=_positive(float), default=60.0,
                    help="time budget, builds included (default 60); at least 3 rounds are run")
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
    rows, info = measure(path, langs, args.seconds, args.motions, progress=not args.quiet)
    name = os.path.basename(path)
    command = "max2code choose-language" + (f" {name}" if args.file else "") + \
        (" --write " + os.path.basename(args.write) if args.write else "")
    text = table(rows, info, "the bundled two circles (circle-circle.mxm)" if not args.file else name, command)
    sys.stdout.write(text)
    if args.write:
        write(args.write, text)
    return 0
