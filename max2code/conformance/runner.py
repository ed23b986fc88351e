"""Conformance runner: `python -m max2code.conformance.runner --lang LANG [--cases F]`
(also `max2code conformance ...`).

Cases are JSON lines under tests/conformance/ (`{"id", "op", ...}`); each op
is a handler in OPS that turns a case into one wire line for the testee and
judges the testee's answer.  A case whose op has no handler is a failure (not
a crash), so a new op (e.g. "toc") is one more entry in OPS.

Each runtime has a testee program speaking the line protocol of docs/roots.md
("Conformance suite"): doubles cross the process boundary as the 16 hex digits
of their IEEE-754 bits, so nothing is lost in printing or parsing.

tests/conformance/expected_failures/<lang>.txt lists case ids expected to fail
("ID  reason" per line); a listed case that passes is a failure, so the list
can only shrink.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from max2code.conformance.exact_op import summary as exact_summary
from max2code.conformance.ops import RootsOp, Verdict, float_of, hex_of, num  # noqa: F401  (the runner's API)
from max2code.conformance.equations import use_equation
from max2code.conformance.toc import TocOp
from max2code.conformance.toi_op import ToiOp, summary as toi_summary
from max2code.errors import ArgumentParser, Max2CodeError
from max2code.paths import BUILD, CASES as CASES_DIR, EXPECTED_FAILURES as XFAIL_DIR  # noqa: F401  (BUILD: the runner's API)
from max2code.targets import LANGUAGES, gsl_baselines
from max2code.toolchain import toolchain
from max2code.toolchain.rust import rust_env  # noqa: F401  (the runner's API)
from max2code.textio import read_text

ALL_LANGS = tuple(LANGUAGES)
BASELINES = gsl_baselines()


def _ops() -> dict[str, object]:
    return {"roots": RootsOp(), "toc": TocOp(), "toi": ToiOp()}


OPS: dict[str, object] = _ops()


# ------------------------------------------------------------------ testees
def build_testee(lang: str) -> list[str]:
    """Build the testee of `lang` (a language or a GSL baseline) if needed and return its command."""
    if lang in LANGUAGES:
        return toolchain(lang).testee()
    for name, t in LANGUAGES.items():
        if t.gsl_baseline == lang:
            return toolchain(name).testee(baseline=True)
    raise ValueError(f"unknown language {lang!r}")


# ------------------------------------------------------------------- runner
@dataclass
class Result:
    case_id: str
    degree: int | None
    verdict: Verdict
    raw: str | None          # the testee's raw answer (bits) for agreement checks
    status: str = ""         # pass, FAIL, xfail, XPASS


@dataclass
class Report:
    lang: str
    results: list[Result] = field(default_factory=list)
    seconds: float = 0.0
    error: str = ""

    def count(self, status: str) -> int:
        return sum(1 for r in self.results if r.status == status)

    @property
    def ok(self) -> bool:
        return not self.error and self.count("FAIL") == 0 and self.count("XPASS") == 0

    def max_relerr_by_degree(self, well_only: bool = False) -> dict[int, float]:
        out: dict[int, float] = {}
        for r in self.results:
            if r.degree is None or (well_only and not r.verdict.wellcond):
                continue
            e = r.verdict.relerr
            cur = out.get(r.degree, 0.0)
            if e is not None and e > cur:
                cur = e
            out[r.degree] = cur
        return out


class CaseFileError(Max2CodeError):
    """A case file that is not JSON lines of objects."""


def load_cases(paths: list[Path]) -> list[dict]:
    """The cases of the files, in order; one-line errors name FILE:LINE.  A
    file without any case is an error: running nothing is not a pass."""
    cases = []
    for p in paths:
        before = len(cases)
        for n, line in enumerate(read_text(str(p)).split("\n"), 1):
            if not line.strip():
                continue
            try:
                case = json.loads(line)
            except (json.JSONDecodeError, RecursionError) as exc:
                msg = exc.msg if isinstance(exc, json.JSONDecodeError) else "nested too deeply"
                col = f":{exc.colno}" if isinstance(exc, json.JSONDecodeError) else ""
                raise CaseFileError(f"{p}:{n}{col}: error: not JSON ({msg}): expected one case object per line") from None
            if not isinstance(case, dict):
                raise CaseFileError(f"{p}:{n}: error: expected a case object {{\"id\", \"op\", ...}}, "
                                    f"got {type(case).__name__}")
            if not isinstance(case.get("op"), str):
                raise CaseFileError(f"{p}:{n}: error: the case has no \"op\" string (one of {', '.join(sorted(OPS))})")
            if "id" in case and not isinstance(case["id"], str):
                raise CaseFileError(f"{p}:{n}: error: \"id\" must be a string")
            case.setdefault("id", f"{p.name}:{n}")
            cases.append(case)
        if len(cases) == before:
            raise CaseFileError(f"{p}: error: no cases in the file (expected JSON lines {{\"id\", \"op\", ...}})")
    return cases


def default_case_files() -> list[Path]:
    return sorted(CASES_DIR.glob("*.jsonl"))


def load_xfail(lang: str) -> dict[str, str]:
    p = XFAIL_DIR / f"{lang}.txt"
    out: dict[str, str] = {}
    if p.exists():
        for line in p.read_text(encoding="utf-8").splitlines():
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cid, _, reason = line.partition(" ")
            out[cid] = reason.strip()
    return out


TESTEE = "testee"     # the report's name for a testee of the user's own (--testee)


def run_lang(lang: str, cases: list[dict], testee: list[str] | None = None) -> Report:
    """Run the cases against runtime `lang`, or with `testee` against that
    command (every case over the wire, toc cases too: docs/conformance.md)."""
    rep = Report(lang)
    t0 = time.monotonic()
    try:
        cmd = testee or build_testee(lang)
    except (Max2CodeError, OSError) as exc:
        rep.error = str(exc)
        return rep
    # ops that name their testee languages are skipped for other runtimes (the GSL baselines)
    if testee is None:
        cases = [c for c in cases
                 if not (c.get("op") in OPS and lang not in getattr(OPS[c["op"]], "testee_langs", (lang,)))]
    lines, index = [], {}
    batched: dict[str, dict[int, dict]] = {}
    for seq, case in enumerate(cases):
        op = OPS.get(case.get("op"))
        if op is None:
            continue
        if hasattr(op, "batch") and testee is None:   # answered by the op's own testee (generated code)
            batched.setdefault(op.name, {})[seq] = case
            continue
        try:
            lines.append(op.wire(case, seq))
            index[seq] = case
        except (KeyError, TypeError, ValueError) as exc:
            case["_bad"] = f"malformed case: {exc}"
    try:
        proc = subprocess.run(cmd, input="".join(line + "\n" for line in lines), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, timeout=600)
    except (OSError, subprocess.TimeoutExpired) as exc:
        rep.error = f"testee {cmd[0]} failed: {exc}"
        rep.results = [Result(str(c.get("id")), None, Verdict(False, "-", why="no answer from testee"), None, "FAIL")
                       for c in cases]
        return rep
    answers: dict[int, str] = {}
    for line in proc.stdout.splitlines():
        seq, _, ans = line.strip().partition(" ")
        if seq.isdigit() and int(seq) < len(cases):
            op = OPS.get(cases[int(seq)].get("op"))
            answers[int(seq)] = op.read(ans.strip()) if hasattr(op, "read") else ans.strip()
    if proc.returncode != 0:
        rep.error = f"testee exited with {proc.returncode}: {proc.stderr.strip()[:500]}"
    for name, group in batched.items():
        try:
            answers.update(OPS[name].batch(lang, group))
        except Exception as exc:  # a build or run failure of the op's testee: every case of it fails
            rep.error = f"{name} testee failed: {str(exc)[:500]}"
    xfail = load_xfail(lang)
    for seq, case in enumerate(cases):
        cid = str(case.get("id"))
        op = OPS.get(case.get("op"))
        if op is None:
            res = Result(cid, None, Verdict(False, "-", why=f"unknown op {case.get('op')!r}"), None)
        elif "_bad" in case:
            res = Result(cid, None, Verdict(False, "-", why=case["_bad"]), None)
        elif seq not in answers:
            res = Result(cid, op.degree(case), Verdict(False, "-", why="no answer from testee"), None)
        else:
            res = Result(cid, op.degree(case), op.judge(case, answers[seq]), answers[seq])
        if cid in xfail:
            res.status = "XPASS" if res.verdict.ok else "xfail"
        else:
            res.status = "pass" if res.verdict.ok else "FAIL"
        rep.results.append(res)
    rep.seconds = time.monotonic() - t0
    return rep


def print_report(rep: Report, quiet: bool, out=None) -> None:
    out = out or sys.stdout
    if rep.error:
        print(f"[{rep.lang}] ERROR {rep.error}", file=out)
    for r in rep.results:
        if quiet and r.status in ("pass", "xfail"):
            continue
        why = f"  ({r.verdict.why})" if r.verdict.why else ""
        if r.status == "XPASS":
            why = "  (listed in expected_failures but passes: remove it)"
        err = f"  relerr={r.verdict.relerr:.2e}" if r.verdict.relerr is not None else ""
        print(f"[{rep.lang}] {r.status:5s} {r.case_id}: t={r.verdict.shown}{err}{why}", file=out)
    print(f"[{rep.lang}] {len(rep.results)} cases: {rep.count('pass')} passed, "
          f"{rep.count('FAIL')} failed, {rep.count('xfail')} expected failures, "
          f"{rep.count('XPASS')} unexpected passes ({rep.seconds:.1f} s)", file=out)


def accuracy_table(reports: list[Report]) -> str:
    """Max relative error per degree: over all matched roots, and over simple
    well-conditioned roots only (tolerance at the 1e-12 relative floor)."""
    alls = [rep.max_relerr_by_degree() for rep in reports]
    wells = [rep.max_relerr_by_degree(well_only=True) for rep in reports]
    degs = sorted({d for m in alls for d in m})
    names = "".join(f"{rep.lang:>10s}" for rep in reports)
    rows = ["max relative error vs mpmath, by degree: all roots | simple well-conditioned roots",
            "degree " + names + "  |" + names]

    def cell(e):
        return f"{'-' if e is None else f'{e:.1e}':>10s}"

    for d in degs:
        rows.append(f"{d:6d} " + "".join(cell(m.get(d)) for m in alls) + "  |"
                    + "".join(cell(m.get(d)) for m in wells))
    return "\n".join(rows)


def agreement(reports: list[Report]) -> list[str]:
    """Case ids on which the runtimes' raw answers differ."""
    by_id: dict[str, list] = {}
    for rep in reports:
        raw = {r.case_id: r.raw for r in rep.results}
        for cid in set(raw) | set(by_id):
            by_id.setdefault(cid, []).append(raw.get(cid))
    return [cid for cid, answers in by_id.items()
            if len(answers) != len(reports) or None in answers and any(a is not None for a in answers)
            or len(set(answers)) > 1]


def main(argv: list[str] | None = None) -> int:
    import shlex

    ap = ArgumentParser(prog="max2code conformance",
                        description="Run the conformance cases against a runtime's testee, a user's equation's "
                                    "generated code (--equation) or a program of the user's own (--testee).")
    ap.add_argument("--lang", choices=ALL_LANGS + BASELINES + ("all",),
                    help="runtime to test; 'all' runs python, c, rust and m2 and checks they agree bit for bit; "
                         "'gsl' and 'gsl-m2' are the GSL companion-matrix baselines (C, Modula-2)")
    ap.add_argument("--testee", metavar="COMMAND",
                    help="run this program instead of a runtime (a shell-quoted command line); it reads the cases "
                         "as wire lines on standard input and answers on standard output (docs/conformance.md)")
    ap.add_argument("--equation", metavar="FILE.mxm",
                    help="a .mxm file of your own: toc cases naming it (its file name without .mxm, or its "
                         "'equation' name) are answered by its generated code; without --cases, the cases of "
                         "'max2code cases FILE.mxm -n 24 --seed 1'")
    ap.add_argument("--cases", action="append", type=Path,
                    help="a .jsonl case file (repeatable; default: every tests/conformance/*.jsonl)")
    ap.add_argument("--quiet", "-q", action="store_true", help="print only failures and the summary")
    ap.add_argument("--list-failures", action="store_true",
                    help="print the failing cases in the expected_failures format (ID reason) and exit 0")
    args = ap.parse_args(argv)
    if (args.lang is None) == (args.testee is None):
        raise Max2CodeError("max2code conformance: error: give --lang LANG or --testee 'COMMAND ...' (one of them)")
    testee = None
    if args.testee is not None:
        testee = shlex.split(args.testee)
        if not testee:
            raise Max2CodeError("max2code conformance: error: --testee: expected a command")
        if not args.cases and not args.equation:
            raise Max2CodeError("max2code conformance: error: --testee needs --cases FILE.jsonl (or --equation FILE.mxm)")
    if args.equation is not None:
        if not os.path.isfile(args.equation):
            raise Max2CodeError(f"--equation {args.equation}: error: no such file")
        names = use_equation(args.equation)
    if args.cases:
        files = args.cases
    elif args.equation is not None:
        files = []
    else:
        files = default_case_files()
        if not files:
            raise Max2CodeError(f"max2code conformance: error: no case files (*.jsonl) in {CASES_DIR}")
    if files:
        cases = load_cases(files)
    else:
        from max2code.conformance.user_cases import cases_for     # here: it loads the generator

        cases = cases_for(args.equation)
        if not args.quiet:
            print(f"max2code conformance: {len(cases)} cases for {names[0]} "
                  f"(max2code cases {args.equation} -n 24 --seed 1)")
    if not cases:
        raise Max2CodeError(f"{files[0] if len(files) == 1 else ', '.join(map(str, files))}: error: "
                            "expected conformance cases (JSON lines), found none")
    langs = [TESTEE] if testee else list(ALL_LANGS) if args.lang == "all" else [args.lang]
    reports = []
    for lang in langs:
        rep = run_lang(lang, cases, testee)
        if args.list_failures:
            for r in rep.results:
                if r.status in ("FAIL", "xfail"):
                    print(f"{r.case_id} {lang}: {r.verdict.why}; answered {r.verdict.shown}")
            continue
        print_report(rep, args.quiet)
        reports.append(rep)
    if args.list_failures:
        return 0
    if any(r.degree is not None for rep in reports for r in rep.results):
        print(accuracy_table(reports))
    for text in (exact_summary(reports, cases), toi_summary(reports, cases)):
        if text:
            print(text)
    ok = all(rep.ok for rep in reports)
    if len(reports) > 1:
        diff = agreement(reports)
        if diff:
            ok = False
            print(f"bit-for-bit agreement: NO, {len(diff)} cases differ: {', '.join(diff[:10])}"
                  + (" ..." if len(diff) > 10 else ""))
            for cid in diff[:10]:
                row = [f"{rep.lang}={next((r.verdict.shown for r in rep.results if r.case_id == cid), '-')}"
                       for rep in reports]
                print(f"  {cid}: " + " ".join(row))
        else:
            print(f"bit-for-bit agreement: yes, {', '.join(langs)} agree on all {len(cases)} cases")
    print("conformance: " + ("OK" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
