"""`max2code bench-variants`: what the variants buy (a benchmark, not a test).

For each equation: per variant, its degree, multiplications and ns per
coefficient evaluation in C and Rust; then, on a workload where each body
has no orbit with probability 1/2 (and everything else random), ns per
call of the selection entry against always calling the full variant.
"""
from __future__ import annotations

import os
import random
import subprocess
import tempfile

from max2code.errors import ArgumentParser, Max2CodeError
from max2code.generate.pipeline import GenerateRequest, generate_file
from max2code.paths import equation
from max2code.progress import bar
from max2code.generate.render import environment
from max2code.targets import target as get_target
from max2code.toolchain import toolchain

# optimised builds; each toolchain adds how to link its runtime (generated files call its solver)
BUILD = {
    "c": lambda tc, src, exe: ["gcc", "-std=c11", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Werror",
                               src, "-o", exe, *tc.runtime_flags(), "-lm"],
    "rust": lambda tc, src, exe: ["rustc", "--edition", "2021", "-C", "opt-level=3", "-D", "warnings",
                                  *tc.runtime_flags(), src, "-o", exe],
}
SOURCE = {"c": "bench.c", "rust": "bench.rs"}


def _params(g, rng, zeros=()):
    """A random parameter set (radii positive) with `zeros` set to 0."""
    radii = {p.name for p in g.derivation.module.parameters if p.effect == "radius"}
    return [0.0 if n in zeros else rng.uniform(0.1, 2.0) if n in radii else rng.uniform(-3.0, 3.0)
            for n in g.function.params]


def run(path: str, n: int, reps: int, trials: int, progress) -> list[dict]:
    rows: dict[str, dict] = {}
    mixed_rows = {}
    for lang in ("c", "rust"):
        g = generate_file(GenerateRequest(path=path, lang=lang, out_name="generated"))
        eq = g.derivation.module.equation
        vs = list(g.variants)
        full_index = next(i for i, v in enumerate(vs) if v.name == g.function.name)
        rng = random.Random(2026)
        lines = [f"{len(vs)} {n}"]
        for v in vs:
            lines += [" ".join(repr(x) for x in _params(g, rng, v.zeros)) for _ in range(n)]
        orbit_radius = [p.name for p in g.derivation.module.parameters if p.effect == "orbit_radius"]
        for _ in range(n):   # each body without orbit with probability 1/2
            lines.append(" ".join(repr(x) for x in _params(g, rng, [r for r in orbit_radius if rng.random() < 0.5])))
        with tempfile.TemporaryDirectory() as tmp:
            tgt = get_target(lang)
            with open(os.path.join(tmp, "generated" + tgt.extension), "w") as fh:
                fh.write(g.text)
            src = os.path.join(tmp, SOURCE[lang])
            with open(src, "w") as fh:
                fh.write(environment().get_template(f"{lang}/bench.j2").render(
                    generated="generated" + tgt.extension, functions=[v.name for v in vs], nparams=len(g.function.params),
                    max_terms=max(v.degree for v in vs) + 1, entry=f"{eq}_coefficients", full_index=full_index,
                    reps=reps, trials=trials))
            exe = os.path.join(tmp, "bench")
            progress(f"{eq}: compiling the {lang} benchmark")
            proc = subprocess.run(BUILD[lang](toolchain(lang), src, exe), capture_output=True, text=True)
            if proc.returncode != 0:
                raise Max2CodeError(f"max2code bench: the {lang} benchmark did not compile:\n{proc.stderr[-3000:]}")
            progress(f"{eq}: timing {len(vs) + 2} functions in {lang}")
            out = subprocess.run([exe], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True).stdout
        times = {int(a): float(b) for a, b in (line.split() for line in out.splitlines())}
        for i, v in enumerate(vs):
            row = rows.setdefault(v.name, {"equation": eq, "variant": v.name, "degree": v.degree,
                                           "multiplications": v.function.multiplications})
            row[f"ns_{lang}"] = times[i]
        mixed_rows.setdefault(eq, {})[lang] = (times[len(vs)], times[len(vs) + 1])
    return list(rows.values()), mixed_rows


def main(argv: list[str]) -> int:
    ap = ArgumentParser(prog="max2code bench-variants", description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="*", default=[str(equation("circle-circle")), str(equation("point-line"))])
    ap.add_argument("--sets", type=int, default=2000, help="parameter sets per variant (default 2000)")
    ap.add_argument("--reps", type=int, default=50, help="passes over the sets per trial (default 50)")
    ap.add_argument("--trials", type=int, default=5, help="trials; the median is reported (default 5)")
    args = ap.parse_args(argv)

    steps = [0, 4 * len(args.files)]   # compile and time, in two languages, per file

    def progress(msg):
        bar(steps[0], steps[1], msg, prefix="max2code bench")
        steps[0] += 1

    results = [(path, *run(path, args.sets, args.reps, args.trials, progress)) for path in args.files]
    bar(steps[1], steps[1], "done", prefix="max2code bench")
    for path, rows, mixed in results:
        print(f"\n{os.path.basename(path)}: ns per coefficient evaluation (median of {args.trials} trials)\n")
        print("| variant | degree | multiplications | C ns | Rust ns |")
        print("|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['variant']} | {r['degree']} | {r['multiplications']} | {r['ns_c']:.1f} | {r['ns_rust']:.1f} |")
        for eq, by_lang in mixed.items():
            print(f"\nworkload: each body without orbit with probability 1/2 ({args.sets} sets)\n")
            print("| language | selection entry ns | always full ns | speed-up |")
            print("|---|---|---|---|")
            for lang, (entry, full) in by_lang.items():
                print(f"| {lang} | {entry:.1f} | {full:.1f} | {full / entry:.2f}x |")
    return 0
