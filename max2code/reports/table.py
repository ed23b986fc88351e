"""`max2code table`: the paper's figure 6 remade for our output.

For each equation: lines of .mxm, lines of Maxima output (its 2D display of
the expanded polynomial at 79 columns, as the paper counted, and characters
of the 1D form), lines of generated code per language for the equation
alone (`--no-variants`, as the paper's figure counts one equation), multiplications of
the plain expansion and of our shared-subexpression code, and generation
time with Maxima (cold) and from the cache (warm).
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

from max2code.errors import ArgumentParser
from max2code.generate.maxima import run_maxima
from max2code.generate.mxm import read_mxm
from max2code.paths import equation
from max2code.progress import bar
from max2code.generate.pipeline import GenerateRequest, derive, generate_file
from max2code.targets import LANGUAGES

DEFAULT = [str(equation("circle-circle")), str(equation("point-line"))]


def _progress(i: int, n: int, what: str) -> None:
    bar(i, n, what, prefix="max2code table")


def maxima_display_lines(path: str) -> int:
    """Lines Maxima prints when it displays the expanded polynomial (2D, linel 79)."""
    d = derive(read_mxm(path))
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "display.txt")
        item = f'block([display2d: true, linel: 79], with_stdout("{out}", print(expand(__m2c_p))), 0)'
        run_maxima(list(d.prelude), list(d.statements), {"shown": item}, fallback=d.origin, use_cache=False)
        with open(out, encoding="utf-8") as fh:
            return sum(1 for line in fh if line.strip())


def _cli_seconds(args: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "max2code", *args], check=True, env=env,
                   stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def measure(paths: list[str]) -> list[dict]:
    rows = []
    langs = sorted(LANGUAGES)
    steps = len(paths) * (len(langs) + 3)
    step = 0
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, MAX2CODE_CACHE=cache)
        for path in paths:
            row: dict = {"equation": os.path.basename(path)}
            with open(path, encoding="utf-8") as fh:
                row["mxm_lines"] = sum(1 for _ in fh)
            _progress(step, steps, f"{path}: Maxima display"); step += 1
            row["maxima_lines"] = maxima_display_lines(path)
            _progress(step, steps, f"{path}: cold generation"); step += 1
            row["cold_s"] = _cli_seconds(["--lang=c", path, "-o", os.devnull, "-q", "--no-cache", "--no-variants"], env)
            _cli_seconds(["--lang=c", path, "-o", os.devnull, "-q", "--no-variants"], env)   # fill the cache
            _progress(step, steps, f"{path}: warm generation"); step += 1
            row["warm_s"] = min(_cli_seconds(["--lang=c", path, "-o", os.devnull, "-q", "--no-variants"], env) for _ in range(3))
            for lang in langs:
                _progress(step, steps, f"{path}: {lang}"); step += 1
                g = generate_file(GenerateRequest(path=path, lang=lang, line_directives=False, variants=False))
                row[f"lines_{lang}"] = g.text.count("\n")
                row["maxima_chars"] = len(g.derivation.maxima_text)
                row["degree"] = g.function.degree
                row["mult_naive"] = g.function.naive_multiplications
                row["mult_shared"] = g.function.multiplications
            rows.append(row)
    _progress(steps, steps, "done")
    return rows


def markdown(rows: list[dict]) -> str:
    langs = sorted(LANGUAGES)
    head = ["equation", "degree", ".mxm lines", "Maxima lines (2D)", "Maxima chars (1D)"] + \
           [f"{lang} lines" for lang in langs] + ["mults naive", "mults shared", "cold s", "warm s"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [r["equation"], r["degree"], r["mxm_lines"], r["maxima_lines"], r["maxima_chars"]] + \
                [r[f"lines_{lang}"] for lang in langs] + \
                [r["mult_naive"], r["mult_shared"], f"{r['cold_s']:.2f}", f"{r['warm_s']:.2f}"]
        out.append("| " + " | ".join(str(c) for c in cells) + " |")
    return "\n".join(out) + "\n"


def main(argv: list[str]) -> int:
    ap = ArgumentParser(prog="max2code table", description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="*", default=DEFAULT, help="the .mxm files (default: the bundled equations)")
    ap.add_argument("-o", "--output", help="also write the Markdown table to this file")
    args = ap.parse_args(argv)
    text = markdown(measure(args.files))
    sys.stdout.write(text)
    if args.output:
        with open(args.output, "w", encoding="utf-8") as fh:
            fh.write("Made by `max2code table` (code lines without #line directives; "
                     "generation times are whole CLI runs, cold = Maxima runs, warm = cached).\n\n" + text)
    return 0
