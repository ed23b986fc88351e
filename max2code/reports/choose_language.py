"""`max2code choose-language [--write FILE]`: the table that opens
docs/using-generated-code.md, from figures measured on this machine.

Per target language (the targets module's list): the median ns per
prediction of the generated `circle_circle_toc` (the selected variant's
polynomial over the whole horizon, then the runtime's root solver) and of
`circle_circle_toc_exact` (`--exact`, default options), both on the same
random two-circle motions (orbits, accelerations, horizon 5 s); the
simulator's events per second on examples/billiard-break.json made elastic
(every restitution 1, so the balls keep moving) and without frame events:
the difference in events and in wall time between a run of SIM_SECONDS
simulated seconds and one of SIM_SHORT seconds, so process start and scene
loading cancel; whether `--real=float` exists; and what the
target needs installed and how its code links into a program (the
target's properties)."""
from __future__ import annotations

import argparse
import dataclasses
import os
import random
import subprocess
import sys
import tempfile
import time

from max2code.conformance.exact_cases import _circle_random
from max2code.errors import Max2CodeError
from max2code.generate.pipeline import GenerateRequest, generate_file
from max2code.paths import EXAMPLES, equation
from max2code.progress import bar
from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator, parse_trace
from max2code.targets import LANGUAGES, target
from max2code.toolchain.exact import build_exact_harness, build_poly_harness

BEGIN = "<!-- choose-language:begin (written by max2code choose-language) -->"
END = "<!-- choose-language:end -->"
SCENE = "billiard-break.json"
SIM_SECONDS, SIM_SHORT = 100.0, 1.0


def _events(trace) -> int:
    return sum(trace.stats["events"].get(k, 0) for k in ("collisions", "inputs", "frames", "cells", "horizons"))


def _scenes(folder: str):
    """The example, elastic, for SIM_SHORT and SIM_SECONDS simulated seconds, without frames."""
    import json

    with open(EXAMPLES / SCENE, encoding="utf-8") as fh:
        raw = json.load(fh)
    out = []
    for seconds in (SIM_SHORT, SIM_SECONDS):
        path = os.path.join(folder, f"scene-{seconds:g}.json")
        with open(path, "w", encoding="utf-8") as fh:
            bodies = [dict(b, restitution=1.0) for b in raw["bodies"]]
            json.dump(dict(raw, end_time=seconds, frame_rate=0, bodies=bodies), fh)
        out.append(load_scene(path))
    return out


def _rows(names: list[str], n: int, seed: int) -> list[dict]:
    rng = random.Random(seed)
    return [_circle_random(rng) for _ in range(n)]


def measure(langs, n: int = 400, reps: int = 20, seed: int = 13, progress: bool = True) -> list[dict]:
    out = []
    steps, step = 3 * len(langs), 0
    with tempfile.TemporaryDirectory(prefix="choose-language-") as tmp:
        short, long = _scenes(tmp)
        for lang in langs:
            tgt = target(lang)
            if progress:
                bar(step, steps, f"{lang}: generate and build", prefix="choose-language")
            req = GenerateRequest(path=str(equation("circle-circle")), lang=lang, out_name="generated")
            plain = generate_file(req)
            g = generate_file(dataclasses.replace(req, exact=True))
            names = g.exact.params
            motions = _rows(names, n, seed)
            horizon = 5.0
            r = reps if tgt.compiled else 1
            poly = build_poly_harness(lang, plain.text, plain.function.params, plain.selection.name, True,
                                      plain.selection.max_degree, os.path.join(tmp, f"{lang}-toc"))
            exact = build_exact_harness(lang, g.text, g.exact, os.path.join(tmp, f"{lang}-exact"))
            step += 1
            if progress:
                bar(step, steps, f"{lang}: time the entries", prefix="choose-language")
            _, ns_toc = poly.run([[m[k] for k in g.function.params] + [horizon] for m in motions], reps=r)
            _, ns_exact = exact.run([[m[k] for k in names] + [horizon, 1.0, 1.0, 0.0, 0.0] for m in motions], reps=r)
            step += 1
            if progress:
                bar(step, steps, f"{lang}: simulator", prefix="choose-language")
            sim = build_simulator(lang, long.effects, long.taylor_order)      # generated and built once, not timed
            runs = []
            for scene in (short, long):
                flat = compile_scene(scene)
                t0 = time.perf_counter()
                proc = subprocess.run(sim.run_cmd, input=flat, capture_output=True, text=True, cwd=sim.workdir)
                seconds = time.perf_counter() - t0
                if proc.returncode != 0:
                    raise Max2CodeError(f"max2code choose-language: error: the {lang} simulator failed: "
                                        f"{proc.stderr[-500:]}")
                runs.append((_events(parse_trace(proc.stdout, scene, sim)), seconds))
            events, seconds = runs[1][0] - runs[0][0], runs[1][1] - runs[0][1]
            step += 1
            out.append({"lang": lang, "ns_toc": ns_toc, "ns_exact": ns_exact, "events_per_s": events / seconds,
                        "events": events, "single": tgt.single_type, "requires": tgt.requires, "links": tgt.links})
    if progress:
        bar(steps, steps, "done", prefix="choose-language")
    return out


def _n(x: float) -> str:
    return f"{x:,.0f}"


def table(rows: list[dict], command: str) -> str:
    head = (f"Measured by `{command}` ({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}): two "
            f"circles, median over {{n}} random motions with orbits and accelerations, horizon 5 s; simulator: "
            f"examples/{SCENE} made elastic, {SIM_SECONDS:g} s without frames ({{events}} events; the difference "
            f"from a {SIM_SHORT:g} s run, so start-up cancels).")
    lines = ["| language | ns per prediction (`NAME_toc`) | with `--exact` (`NAME_toc_exact`) | simulator events/s "
             "| single precision (`--real=float`) | must be installed | how it links into a program |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['lang']} | {_n(r['ns_toc'])} | {_n(r['ns_exact'])} | {_n(r['events_per_s'])} | "
                     f"{('yes (' + r['single'] + ')') if r['single'] else 'no'} | {r['requires']} | {r['links']} |")
    return head + "\n\n" + "\n".join(lines) + "\n"


def write(path: str, text: str) -> None:
    with open(path, encoding="utf-8") as fh:
        doc = fh.read()
    a, b = doc.find(BEGIN), doc.find(END)
    if a < 0 or b < a:
        raise Max2CodeError(f"{path}: error: expected the markers {BEGIN} and {END}")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(doc[:a + len(BEGIN)] + "\n" + text + doc[b:])


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="max2code choose-language", description=__doc__.split("\n\n")[0])
    ap.add_argument("--write", metavar="FILE", help="replace the table between the choose-language markers of FILE "
                                                     "(docs/using-generated-code.md)")
    ap.add_argument("--motions", type=int, default=400, help="random motions timed (default 400)")
    ap.add_argument("--reps", type=int, default=20, help="passes over them in the compiled languages (default 20)")
    ap.add_argument("--quiet", "-q", action="store_true")
    args = ap.parse_args(argv)
    rows = measure(list(LANGUAGES), args.motions, args.reps, progress=not args.quiet)
    command = "max2code choose-language" + (" --write " + os.path.basename(args.write) if args.write else "")
    text = table(rows, command).replace("{n}", str(args.motions)).replace("{events}", str(rows[0]["events"]))
    sys.stdout.write(text)
    if args.write:
        write(args.write, text)
    return 0
