"""Conformance of the TOI library: op "toi" (cases:
tests/conformance/toi/toi.jsonl, made by toi_cases.py, references by
toi_ref.py on the exact motion; docs/toi.md, docs/conformance.md).

Each runtime answers through its library: C through
runtimes/c/tools/m2c_toi_testee.c (linked with the library, max2code/toolchain/toi.py),
Rust through max2code_rt::toi::testee_main (max2code/toolchain/toi.py builds it with
the generated Rust), Modula-2 through runtimes/m2/ToiTestee.mod over the module Toi
(max2code/toolchain/toi.py links it with the simulator's modules), Python through max2code_rt.toi in this process.  The raw answer holds every
bit of the result (time, features, point, normal), so `--lang all` checks
that the runtimes agree on all of them.

Judging, with the case's tolerance tol (m) and its reference: D(0) below
-2 tol must answer overlapped, and overlapped stands only when D(0) < 0; a
contact at t passes when the bodies have come within 2 tol by then (t_in <=
t) and not yet 2 tol inside each other (t <= t_deep); none passes when they
never get 2 tol inside each other within the horizon.
"""
from __future__ import annotations

import subprocess
from pathlib import Path

from max2code.conformance.ops import Verdict, float_of, hex_of
from max2code.paths import RUNTIMES

MOTION = ("x", "y", "vx", "vy", "ax", "ay", "angle", "omega", "orbit", "orbit_phase")
SLACK = 1e-12           # s, relative: the references' times are exact to far below this


def _body_fields(b: dict) -> list[str]:
    if b["shape"] == "circle":
        out = ["0", hex_of(float(b["radius"]))]
    else:
        out = [str(len(b["vertices"]))] + [hex_of(float(v)) for xy in b["vertices"] for v in xy]
    return out + [hex_of(float(b["motion"].get(k, 0.0))) for k in MOTION]


def wire(case: dict, seq: int) -> str:
    """The testee line of a case: toi SEQ HORIZON TOL BODY_A BODY_B (docs/conformance.md)."""
    return " ".join(["toi", str(seq), hex_of(float(case["horizon"])), hex_of(float(case["tol"]))]
                    + _body_fields(case["a"]) + _body_fields(case["b"]))


def c_testee() -> Path:
    from max2code.toolchain import toi
    return toi.c_program(RUNTIMES / "c" / "tools" / "m2c_toi_testee.c", "m2c_toi_testee")


def run_rust(cases: dict[int, dict]) -> dict[int, str]:
    """The Rust library's answers of the cases by seq."""
    from max2code.toolchain import toi
    exe = toi.rust_testee()
    text = "".join(wire(c, s) + "\n" for s, c in cases.items())
    proc = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f"{exe} exited with {proc.returncode}: {proc.stderr[-500:]}")
    answers = {}
    for line in proc.stdout.splitlines():
        seq, _, ans = line.partition(" ")
        answers[int(seq)] = ans.strip()
    return answers


def run_m2(cases: dict[int, dict]) -> dict[int, str]:
    """The Modula-2 library's answers of the cases by seq."""
    from max2code.toolchain import toi
    exe = toi.m2_testee()
    text = "".join(wire(c, s) + "\n" for s, c in cases.items())
    proc = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f"{exe} exited with {proc.returncode}: {proc.stderr[-500:]}")
    answers = {}
    for line in proc.stdout.splitlines():
        seq, _, ans = line.partition(" ")
        answers[int(seq)] = ans.strip()
    return answers


def run_c(cases: dict[int, dict], reps: int = 0) -> tuple[dict[int, str], dict[int, float]]:
    """The C library's answers (and with reps > 0 its ns per query) of the cases by seq."""
    exe = c_testee()
    text = "".join(wire(c, s) + "\n" for s, c in cases.items())
    proc = subprocess.run([str(exe), str(reps)], input=text, capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f"{exe} exited with {proc.returncode}: {proc.stderr[-500:]}")
    answers, ns = {}, {}
    for line in proc.stdout.splitlines():
        if line.startswith("ns "):
            _, seq, v = line.split()
            ns[int(seq)] = float(v)
            continue
        seq, _, ans = line.partition(" ")
        answers[int(seq)] = ans.strip()
    return answers, ns


def python_answer(case: dict) -> str:
    from max2code.toolchain import toi
    from max2code_rt import toi as rt

    lib = toi.python_toi(tol=float(case["tol"]))

    def shape(b):
        return rt.circle(b["radius"]) if b["shape"] == "circle" else rt.polygon(b["vertices"])

    def motion(b):
        return rt.Motion(**{k: b["motion"].get(k, 0.0) for k in MOTION})

    try:
        sa, sb = shape(case["a"]), shape(case["b"])
    except ValueError:
        return "error malformed"
    r = lib.toi(sa, motion(case["a"]), sb, motion(case["b"]), float(case["horizon"]))
    if r.status == rt.HIT:
        return " ".join(["hit", hex_of(r.t), str(r.feature), str(int(r.first)), str(r.i), str(r.j),
                         hex_of(r.px), hex_of(r.py), hex_of(r.nx), hex_of(r.ny)])
    return {rt.NONE: "none", rt.OVERLAPPED: "overlapped"}.get(r.status, "error refused")


class ToiOp:
    """op "toi": the first contact of two bodies through the TOI library."""

    name = "toi"
    testee_langs = ("c", "m2", "python", "rust")

    def degree(self, case: dict):
        return None

    def wire(self, case: dict, seq: int) -> str:
        return wire(case, seq)

    def batch(self, lang: str, cases: dict[int, dict]) -> dict[int, str]:
        if lang == "c":
            return run_c(cases)[0]
        if lang == "python":
            return {s: python_answer(c) for s, c in cases.items()}
        if lang == "rust":
            return run_rust(cases)
        if lang == "m2":
            return run_m2(cases)
        return {s: f"error: no TOI library testee for {lang}" for s in cases}

    def judge(self, case: dict, answer: str) -> Verdict:
        return judge(case, answer)


def judge(case: dict, answer: str) -> Verdict:
    tol, d0 = float(case["tol"]), case["d0"]
    t_in, t_deep, t_star = case.get("t_in"), case.get("t_deep"), case.get("t_star")
    if answer.startswith("error"):
        return Verdict(False, "-", why=answer)
    if answer == "overlapped":
        ok = d0 < 0.0
        return Verdict(ok, answer, why="" if ok else f"answered overlapped, but D(0) = {d0!r} m")
    if d0 < -2.0 * tol:
        return Verdict(False, answer, why=f"the bodies overlap at t = 0 by {-d0!r} m: expected overlapped")
    if answer == "none":
        ok = t_deep is None
        return Verdict(ok, "none", why="" if ok else f"missed the contact at {t_star!r}")
    parts = answer.split()
    if len(parts) != 10 or parts[0] != "hit":
        return Verdict(False, answer, why="unreadable answer")
    t = float_of(parts[1])
    rel = None if t_star is None else abs(t - t_star) / max(abs(t_star), 1e-300)
    slack = SLACK * (1.0 + abs(t))
    if t_in is None or t < t_in - slack:
        return Verdict(False, repr(t), relerr=rel, why="invented a contact: the bodies are farther apart than 2 tol"
                       if t_in is None else f"contact before the bodies come within 2 tol (at {t_in!r})")
    if t_deep is not None and t > t_deep + slack:
        return Verdict(False, repr(t), relerr=rel, why=f"late: the bodies are 2 tol inside each other at {t_deep!r}")
    return Verdict(True, repr(t), relerr=rel, wellcond=t_deep is not None)


def summary(reports, cases: list[dict]) -> str:
    """Per runtime over the toi cases: right and wrong, missed and invented,
    the largest time error against the exact first contact."""
    toi = {str(c.get("id")): c for c in cases if c.get("op") == "toi"}
    if not toi:
        return ""
    rows = ["TOI library (op toi): right / wrong against the mpmath references; missed, invented; "
            "largest |t - t*| / t* over the contacts"]
    for rep in reports:
        res = [r for r in rep.results if r.case_id in toi]
        missed = sum(1 for r in res if not r.verdict.ok and r.verdict.shown == "none")
        invented = sum(1 for r in res if not r.verdict.ok and "invented" in r.verdict.why)
        errs = [r.verdict.relerr for r in res if r.verdict.ok and r.verdict.relerr is not None]
        worst = f"{max(errs):.1e}" if errs else "-"
        right = sum(1 for r in res if r.verdict.ok)
        rows.append(f"  {rep.lang:>7s}: {len(res)} cases, {right} right, {len(res) - right} wrong "
                    f"({missed} missed, {invented} invented); largest relative time error {worst}")
    return "\n".join(rows)
