"""Compile generated coefficient code into a small program per language
(templates/<lang>/harness.j2) that reads parameter sets on stdin and prints
the coefficients exactly; used by the tests and the benchmarks.  Also the
two steps every harness shares (exact.py's too): writing the generated file
and the harness source into a workdir, and running the build commands."""
from __future__ import annotations

import os
import subprocess
from dataclasses import dataclass

from max2code.errors import Max2CodeError
from max2code.generate.lower import FunctionIR
from max2code.generate.render import environment
from max2code.targets import LANGUAGES
from max2code.toolchain import toolchain


class HarnessBuildError(Max2CodeError):
    """The generated code did not compile; the message holds the compiler's output."""


@dataclass
class Harness:
    lang: str
    workdir: str
    run_cmd: list[str]
    nparams: int

    def evaluate(self, param_sets: list[list[float]], timeout: float = 300) -> list[list[float]]:
        text = "\n".join(" ".join(repr(float(x)) for x in ps) for ps in param_sets) + "\n"
        proc = subprocess.run(self.run_cmd, input=text, capture_output=True, text=True,
                              timeout=timeout, cwd=self.workdir)
        if proc.returncode != 0:
            raise RuntimeError(f"{self.lang} harness failed: {proc.stderr[-2000:]}")
        return [[float(w) for w in line.split()] for line in proc.stdout.splitlines()]


def build_harness(lang: str, generated_text: str, fn: FunctionIR, workdir: str, entry: str | None = None,
                  max_degree: int | None = None, toc: str | None = None) -> Harness:
    """Write the generated file and the harness into `workdir` and compile them.
    With `entry` (a selection function's name) the harness calls it and prints
    the selected degree, then that many + 1 coefficients (-1 when unsupported).
    With `toc` (a time-of-contact entry's name) each input line is the
    parameters then lo and hi, and the harness prints `status t`."""
    tc = toolchain(lang)
    src, exe = write_harness(lang, generated_text, workdir, "harness.j2", name=entry or fn.name,
                             nparams=len(fn.params), nterms=(max_degree if entry else fn.degree) + 1,
                             entry=bool(entry), toc=toc)
    compile_harness(tc.harness_build(src, exe, [workdir]), workdir, timeout=600)
    return Harness(lang, workdir, tc.harness_run(src, exe), len(fn.params))


def write_harness(lang: str, generated_text: str, workdir: str, template: str, **ctx) -> tuple[str, str]:
    """Write the generated file and the harness made from LANG's `template`
    (given `generated`, the generated file's name, and `ctx`) into `workdir`;
    return the harness source's and executable's paths."""
    os.makedirs(workdir, exist_ok=True)
    gen = "generated" + LANGUAGES[lang].extension
    with open(os.path.join(workdir, gen), "w", encoding="utf-8") as fh:
        fh.write(generated_text)
    src = os.path.join(workdir, toolchain(lang).harness_source)
    text = environment().get_template(f"{lang}/{template}").render(generated=gen, **ctx)
    with open(src, "w", encoding="utf-8") as fh:
        fh.write(text)
    return src, os.path.join(workdir, "harness")


def compile_harness(commands: list[list[str]], workdir: str, timeout: float) -> None:
    """Run the build commands in `workdir`; HarnessBuildError with the tool's output on failure."""
    for cmd in commands:
        proc = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True, cwd=workdir,
                              timeout=timeout)
        if proc.returncode != 0:
            raise HarnessBuildError(f"{' '.join(cmd)}\n{proc.stdout}{proc.stderr}")
