"""`max2code accuracy`: what accuracy costs in time.

One sweep over the knobs of exact-motion contact prediction (docs/exact-motion.md)
for two circles, in every language: the paper's own single polynomial, our
single polynomial (order 4 and 8), windowed polynomials without refinement
(several window angles), the exact-motion driver (several angles, orders,
the GSL solver, single precision).  For each: the error of the first contact
against the exact motion (mpmath reference, exact_ref.py), contacts missed
and invented, and ns per prediction (in-process clocks, median of passes).
Writes a Markdown table and a plot (PNG and SVG).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import platform
import random
import statistics
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from max2code.conformance import exact_cases, exact_ref
from max2code.conformance.exact_cases import _aim, _circle_random
from max2code.conformance.exact_ref import reference
from max2code.errors import ArgumentParser
from max2code.generate.mxm import read_mxm
from max2code.generate.pipeline import GenerateRequest, derive, generate, generate_file
from max2code.progress import bar

from max2code.paths import BUILD, EQUATIONS, ROOT, equation
from max2code.targets import LANGUAGES
from max2code.toolchain.exact import build_exact_harness, build_poly_harness
# the compiled languages first (the table's order)
LANGS = tuple(sorted(LANGUAGES, key=lambda lang: not LANGUAGES[lang].compiled))
LETTERS = "abcdefmnopqghijklrsuvwxz"
README_BEGIN = "<!-- accuracy:begin (written by max2code accuracy --readme) -->"
README_END = "<!-- accuracy:end -->"


@dataclass(frozen=True)
class Config:
    name: str
    kind: str               # paper | single | plain (windows, no refinement) | exact
    order: int = 4
    angle: float = 0.5
    real: str = "double"
    gsl: bool = False
    langs: tuple[str, ...] = LANGS
    note: str = ""

    @property
    def family(self) -> str:
        if self.kind == "exact" and (self.real == "float" or self.gsl):
            return "exact, float" if self.real == "float" else "exact, GSL"
        if self.kind == "plain" and self.real == "float":
            return "windows, float"
        return {"paper": "paper form", "single": "one polynomial", "plain": "windows, no refinement",
                "exact": "exact (refined)"}[self.kind]


NATIVE = tuple(lang for lang in LANGS if LANGUAGES[lang].compiled)
CONFIGS = (
    Config("paper", "paper", note="the paper's figure 7: cos series of the whole angle, S(X) = O(pi/2 - X), one polynomial"),
    Config("single o4", "single", 4, note="our phase expansion, order 4, one polynomial over the horizon"),
    Config("single o8", "single", 8, note="order 8 (degree 16), one polynomial"),
    Config("plain o4 a1", "plain", 4, 1.0),
    Config("plain o4 a0.5", "plain", 4, 0.5),
    Config("plain o4 a0.25", "plain", 4, 0.25),
    Config("plain o4 a0.1", "plain", 4, 0.1),
    Config("plain o8 a1", "plain", 8, 1.0),
    Config("plain o8 a0.5", "plain", 8, 0.5),
    Config("exact o4 a2", "exact", 4, 2.0),
    Config("exact o4 a1", "exact", 4, 1.0, note="the defaults"),
    Config("exact o4 a0.5", "exact", 4, 0.5),
    Config("exact o4 a0.25", "exact", 4, 0.25),
    Config("exact o8 a2", "exact", 8, 2.0),
    Config("exact o8 a1", "exact", 8, 1.0),
    Config("exact o4 a1 GSL", "exact", 4, 1.0, gsl=True, langs=("c", "m2"), note="GSL's companion-matrix solver"),
    Config("exact o4 a1 float", "exact", 4, 1.0, real="float", langs=NATIVE, note="generated code in float/f32/SHORTREAL"),
    Config("plain o4 a0.25 float", "plain", 4, 0.25, real="float", langs=NATIVE),
)
QUICK = ("paper", "single o4", "plain o4 a0.25", "exact o4 a1")


# ---------------------------------------------------------------- cases
def make_cases(n: int, seed: int, progress: bool = True) -> list[dict]:
    """Two-circle motions aimed to meet (70 %), orbits up to 5 rad/s, horizons
    1 to 10 s, with mpmath references of the exact motion."""
    src = Path(exact_ref.__file__).read_bytes() + Path(exact_cases.__file__).read_bytes()
    key = hashlib.sha256(src + f"{n} {seed}".encode()).hexdigest()[:16]
    cache = BUILD / "accuracy" / f"cases-{key}.json"
    if cache.exists():
        return json.loads(cache.read_text())
    rng = random.Random(seed)
    out = []
    for i in range(n):
        if progress:
            bar(i, n, "reference contact times (mpmath)", prefix="accuracy")
        T = rng.choice([1.0, 2.0, 5.0, 10.0])
        p = _circle_random(rng, 5.0)
        if rng.random() < 0.7:
            p = _aim(rng, p, "circle-circle", T, 1.5)
        ref = reference("circle-circle", p, T)
        if ref.expect == "overlapped" or ref.overlapped_ok:
            continue            # the sweep measures contact times: bodies inside each other at t = 0 have none
        out.append({"params": {k: p[k] for k in LETTERS}, "horizon": T, "expect": ref.expect, "accept": ref.accept,
                    "none_ok": ref.none_ok})
    if progress:
        bar(n, n, "reference contact times (mpmath)", prefix="accuracy")
    cache.parent.mkdir(parents=True, exist_ok=True)
    cache.write_text(json.dumps(out))
    return out


# ---------------------------------------------------------------- harnesses
def _generate(kind: str, lang: str, order: int, real: str):
    req = GenerateRequest(path=str(equation("circle-circle")), lang=lang, out_name="generated",
                          options={"order": str(order)}, exact=kind in ("plain", "exact"), real=real)
    if kind == "paper":
        mod = read_mxm(str(EQUATIONS / "paper" / "circle-circle.mxm"))
        mod = dataclasses.replace(mod, blocks=(), terms=None, terms_span=None, equation="paper_circle_circle")
        return generate(derive(mod), dataclasses.replace(req, path=mod.path, options={}, variants=False))
    return generate_file(req)


def build(kind: str, lang: str, order: int, real: str, workdir: str):
    """A harness for `kind` (paper and single: one polynomial; plain and exact:
    the exact-motion driver) and the parameter names in its order."""
    g = _generate(kind, lang, order, real)
    if kind == "paper":
        return build_poly_harness(lang, g.text, g.function.params, g.function.name, False, g.function.degree,
                                  workdir), g.function.params
    if kind == "single":
        sel = max(v.degree for v in g.variants)
        return build_poly_harness(lang, g.text, g.function.params, f"{g.derivation.module.equation}_coefficients",
                                  True, sel, workdir), g.function.params
    return build_exact_harness(lang, g.text, g.exact, workdir), g.exact.params


# ---------------------------------------------------------------- sweep
@dataclass
class Result:
    config: Config
    lang: str
    ns: float
    median: float | None
    worst: float | None
    missed: int
    invented: int
    contacts: int
    errors: list = field(default_factory=list, repr=False)


def score(config: Config, lang: str, cases: list[dict], answers, ns: float) -> Result:
    errs, missed, invented, contacts = [], 0, 0, 0
    for c, (st, t) in zip(cases, answers):
        if c["expect"] is not None:
            contacts += 1
        if st != 1:
            if c["expect"] is not None and not c["none_ok"]:
                missed += 1
            continue
        if c["expect"] is None:
            if not any(lo <= t <= hi for lo, hi in c["accept"]):
                invented += 1
            continue
        errs.append(abs(t - c["expect"]) / c["expect"] if c["expect"] else abs(t))
    med = statistics.median(errs) if errs else None
    return Result(config, lang, ns, med, max(errs) if errs else None, missed, invented, contacts, errs)


def sweep(configs, langs, cases, reps: int, py_reps: int, progress: bool = True) -> list[Result]:
    keys = sorted({(("exact" if c.kind in ("plain", "exact") else c.kind), lang, c.order, c.real)
                   for c in configs for lang in langs if lang in c.langs},
                  key=lambda k: (LANGS.index(k[1]), k[0], k[2], k[3]))
    steps = len(keys) + sum(1 for c in configs for lang in langs if lang in c.langs)
    done = 0
    results: list[Result] = []
    with tempfile.TemporaryDirectory(prefix="max2code-accuracy-") as tmp:
        harness = {}
        for key in keys:
            if progress:
                bar(done, steps, f"build {key[1]} {key[0]} order {key[2]} {key[3]}", prefix="accuracy")
            kind, lang, order, real = key
            harness[key] = build(kind, lang, order, real, os.path.join(tmp, "-".join(map(str, key))))
            done += 1
        for c in configs:
            for lang in langs:
                if lang not in c.langs:
                    continue
                if progress:
                    bar(done, steps, f"run {lang} {c.name}", prefix="accuracy")
                h, names = harness[(("exact" if c.kind in ("plain", "exact") else c.kind), lang, c.order, c.real)]
                if c.kind in ("paper", "single"):
                    rows = [[float(k["params"][n]) for n in names] + [float(k["horizon"])] for k in cases]
                else:
                    rows = [[float(k["params"][n]) for n in names] +
                            [float(k["horizon"]), c.angle, 1.0 if c.kind == "exact" else 0.0, 0.0, 1.0 if c.gsl else 0.0]
                            for k in cases]
                answers, ns = h.run(rows, reps=reps if LANGUAGES[lang].compiled else py_reps)
                results.append(score(c, lang, cases, answers, ns))
                done += 1
    if progress:
        bar(steps, steps, "done", prefix="accuracy")
    return results


# ---------------------------------------------------------------- output
def _e(x: float | None) -> str:
    if x is None:
        return "-"
    return "0" if x == 0 else f"{x:.1e}"


def _ns(x: float) -> str:
    return f"{x:,.0f}" if x >= 100 else f"{x:.1f}"


def table(results: list[Result]) -> str:
    rows = ["| configuration | language | ns per prediction | median rel. error | max rel. error | missed | invented |",
            "|---|---|---|---|---|---|---|"]
    for r in results:
        rows.append(f"| {r.config.name} | {r.lang} | {_ns(r.ns)} | {_e(r.median)} | {_e(r.worst)} | {r.missed} | "
                    f"{r.invented} |")
    return "\n".join(rows)


def headline(results: list[Result]) -> str:
    """Per language: the exact-motion defaults against the paper's form."""
    by = {(r.config.name, r.lang): r for r in results}
    rows = ["| language | exact motion (defaults): ns | max rel. error | missed / invented | paper's single polynomial: ns "
            "| median rel. error | missed / invented |", "|---|---|---|---|---|---|---|"]
    for lang in LANGS:
        e, p = by.get(("exact o4 a1", lang)), by.get(("paper", lang))
        if not e or not p:
            continue
        rows.append(f"| {lang} | {_ns(e.ns)} | {_e(e.worst)} | {e.missed} / {e.invented} | {_ns(p.ns)} | "
                    f"{_e(p.median)} | {p.missed} / {p.invented} |")
    return "\n".join(rows)


def plot(results: list[Result], out_base: Path) -> list[Path]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    plt.rcParams["svg.hashsalt"] = "max2code-accuracy"
    floor = 1e-17
    markers = {"c": "o", "rust": "s", "m2": "^", "python": "D"}
    families = sorted({r.config.family for r in results})
    colours = {f: plt.get_cmap("tab10")(i) for i, f in enumerate(families)}
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for ax, what in zip(axes, ("median", "worst")):
        for r in results:
            y = getattr(r, what)
            if y is None:
                continue
            ax.scatter(r.ns, max(y, floor), marker=markers[r.lang], color=colours[r.config.family], s=36,
                       edgecolors="black" if r.missed or r.invented else "none", linewidths=1.2)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("ns per prediction (log)")
        ax.set_ylabel(("median" if what == "median" else "largest") + " relative error of the first contact (log)")
        ax.grid(True, which="major", alpha=0.3)
        ax.axhline(1e-12, color="grey", lw=0.8, ls="--")
    handles = [plt.Line2D([], [], marker="o", ls="", color=colours[f], label=f) for f in families]
    handles += [plt.Line2D([], [], marker=m, ls="", color="grey", label=l) for l, m in markers.items()]
    handles += [plt.Line2D([], [], marker="o", ls="", markerfacecolor="white", markeredgecolor="black",
                           label="black rim: missed or invented contacts")]
    fig.legend(handles=handles, fontsize=8, loc="lower center", ncol=6, frameon=False)
    fig.suptitle("Two circles, exact motion: error of the first contact against ns per prediction "
                 f"(errors of 0 drawn at {floor:g}; dashed: 1e-12)", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    paths = [out_base.with_suffix(".png"), out_base.with_suffix(".svg")]
    fig.savefig(paths[0], dpi=110, metadata={"Software": None})
    fig.savefig(paths[1], metadata={"Date": None, "Creator": None})
    plt.close(fig)
    return paths


def markdown(results, cases, command: str, images: list[Path], reps: int, py_reps: int) -> str:
    contacts = sum(1 for c in cases if c["expect"] is not None)
    notes = "\n".join(f"- **{c.name}**: {c.note}" for c in dict.fromkeys(r.config for r in results) if c.note)
    return f"""# What accuracy costs in time

Made by `{command}` (every number below comes from that run; nothing is typed).
Machine: {platform.machine()}, {os.cpu_count()} cores, {platform.python_implementation()} {platform.python_version()};
timings are in-process (C, Rust, Modula-2: `-O2`; Python: CPython), the median of
{reps} passes over all cases ({py_reps} for Python), so they include the
generated code, the driver and the root solver, and are noisy on a busy machine.

**Cases**: {len(cases)} two-circle motions (the paper's 24 letters as real
motion: orbits up to 5 rad/s, accelerations, horizons 1 to 10 s, 70 % aimed to
meet), {contacts} with a contact.  **Error**: |t - t_exact| / t_exact of the
first contact against an mpmath reference of the exact motion
(`max2code/conformance/exact_ref.py`); **missed**: a contact answered as none;
**invented**: a contact where the exact motion has none (both beyond the
reference's rounding band).  Configurations: `o` = Taylor order, `a` = window
angle in radians, `plain` = windows without refinement, `exact` = margins,
subdivision and the polish on the exact gap (docs/exact-motion.md).

{notes}

## Headline: the defaults against the paper's form

{headline(results)}

## All configurations

{table(results)}

![error against time]({images[0].name})

(Also as [SVG]({images[1].name}).)
"""


def update_readme(results, command: str, readme: Path) -> bool:
    text = readme.read_text()
    if README_BEGIN not in text or README_END not in text:
        return False
    head, rest = text.split(README_BEGIN, 1)
    _, tail = rest.split(README_END, 1)
    block = (f"{README_BEGIN}\nExact motion against the paper's single polynomial (two circles; "
             f"`{command}`, details in [docs/accuracy.md](docs/accuracy.md)):\n\n{headline(results)}\n{README_END}")
    readme.write_text(head + block + tail)
    return True


def main(argv: list[str] | None = None) -> int:
    ap = ArgumentParser(prog="max2code accuracy", description=(
        "Sweep the exact-motion knobs (Taylor order, window angle, refinement, solver, float) in every "
        "language against the paper's single polynomial: error against the exact motion and ns per "
        "prediction, as a Markdown table and a plot (PNG, SVG)."))
    ap.add_argument("--langs", default=",".join(LANGS), help="comma-separated from c, rust, m2, python (default: all)")
    ap.add_argument("--cases", type=int, default=300, help="number of two-circle motions (default 300)")
    ap.add_argument("--seed", type=int, default=2028)
    ap.add_argument("--reps", type=int, default=11, help="timed passes per configuration (default 11)")
    ap.add_argument("--python-reps", type=int, default=3, help="timed passes for Python (default 3)")
    ap.add_argument("--quick", action="store_true", help="only " + ", ".join(QUICK))
    ap.add_argument("--configs", help="comma-separated configuration names (default: all)")
    ap.add_argument("-o", "--output", default=str(ROOT / "docs" / "accuracy.md"),
                    help="the Markdown report; the plot goes next to it (.png, .svg)")
    ap.add_argument("--readme", action="store_true", help="also rewrite the headline block in README.md")
    ap.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    args = ap.parse_args(argv)
    langs = [l.strip() for l in args.langs.split(",") if l.strip()]
    for l in langs:
        if l not in LANGS:
            ap.error(f"unknown language {l!r}")
    names = QUICK if args.quick else (tuple(x.strip() for x in args.configs.split(",")) if args.configs else None)
    configs = [c for c in CONFIGS if names is None or c.name in names]
    if names is not None and len(configs) != len(set(names)):
        ap.error(f"unknown configuration in {names}; known: {', '.join(c.name for c in CONFIGS)}")
    cases = make_cases(args.cases, args.seed, progress=not args.quiet)
    results = sweep(configs, langs, cases, args.reps, args.python_reps, progress=not args.quiet)
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    images = plot(results, out.with_suffix(""))
    command = "max2code accuracy" + (" " + " ".join(argv if argv is not None else sys.argv[2:])).rstrip()
    out.write_text(markdown(results, cases, command.strip(), images, args.reps, args.python_reps))
    print(headline(results))
    print(f"wrote {out}, {images[0]}, {images[1]}")
    if args.readme and not update_readme(results, command.strip(), ROOT / "README.md"):
        print("README.md has no accuracy block; not changed", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
