"""Build and run a small program per language around generated exact-motion
code (templates/<lang>/exact_harness.j2): rows of parameters, horizon and
options in, `status t` out, and optionally the median ns per call."""
from __future__ import annotations

import subprocess
from dataclasses import dataclass

from max2code.toolchain import toolchain
from max2code.toolchain.harness import compile_harness, write_harness

MAX_ROWS = 20000      # rows the Modula-2 harness holds (a static array)


@dataclass
class ExactHarness:
    lang: str
    workdir: str
    cmd: list[str]
    nparams: int

    def run(self, rows: list[list[float]], reps: int = 0, timeout: float = 1800) -> tuple[list[tuple[int, float]], float | None]:
        """Each row: parameters, horizon, window_angle, refine, zero_tol, solver.
        Returns (status, t) per row and the median ns per call (reps > 0)."""
        if toolchain(self.lang).harness_rows_fixed and len(rows) > MAX_ROWS:
            raise ValueError(f"the {self.lang} harness holds at most {MAX_ROWS} rows")
        text = f"{reps}\n" + "\n".join(" ".join(repr(float(v)) for v in r) for r in rows) + "\n"
        proc = subprocess.run(self.cmd, input=text, capture_output=True, text=True, timeout=timeout, cwd=self.workdir)
        if proc.returncode != 0:
            raise RuntimeError(f"{self.lang} exact harness failed: {proc.stderr[-2000:]}")
        answers, ns = [], None
        for line in proc.stdout.splitlines():
            a, _, b = line.partition(" ")
            if a == "ns":
                ns = float(b)
            else:
                answers.append((int(a), float(b)))
        if len(answers) != len(rows):
            raise RuntimeError(f"{self.lang} exact harness answered {len(answers)} of {len(rows)} rows")
        return answers, ns


def build_exact_harness(lang: str, generated_text: str, section, workdir: str) -> ExactHarness:
    """Write the generated file (made with exact=True) and the harness into
    `workdir`, and compile them (warnings are errors).  Rows: parameters,
    horizon, window_angle, refine, zero_tol, solver (0 ours, 1 GSL)."""
    return _build(lang, generated_text, workdir, "exact_harness.j2", len(section.params),
                  toc=f"{section.name}_toc_exact")


def build_poly_harness(lang: str, generated_text: str, params, coef: str, selection: bool, max_degree: int,
                       workdir: str) -> ExactHarness:
    """The same for one polynomial over the whole horizon: `coef` (the
    selection entry when `selection`, else a plain coefficient function of
    degree `max_degree`), then the runtime's solver on (0, T].  Rows:
    parameters, horizon."""
    return _build(lang, generated_text, workdir, "poly_harness.j2", len(params), coef=coef, selection=selection,
                  max_degree=max_degree)


def _build(lang: str, generated_text: str, workdir: str, template: str, nparams: int, **ctx) -> ExactHarness:
    tc = toolchain(lang)
    src, exe = write_harness(lang, generated_text, workdir, template, nparams=nparams, max_rows=MAX_ROWS, **ctx)
    compile_harness(tc.exact_harness_build(src, exe, workdir), workdir, timeout=900)
    cmd = tc.harness_run(src, exe)
    return ExactHarness(lang, workdir, cmd, nparams)
