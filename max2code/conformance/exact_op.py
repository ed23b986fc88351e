"""Conformance of the exact-motion contact time: op "toc" with
"motion": "exact" (cases: tests/conformance/toc_exact.jsonl, made by
exact_cases.py, references by exact_ref.py).

Each language answers through a harness compiled around its generated code
(`max2code --exact`, templates/<lang>/exact_harness.j2): the generated
NAME_toc_exact with the runtime's driver, default options unless the case
gives "options" (window_angle, refine, zero_tol).  An answer passes when it
lies in one of the case's "accept" intervals, or is "none" and the case
says none_ok (or has no contact).  Regular cases (the contact is decided to
1e-12 / 4 by double arithmetic) accept only [t (1 - 1e-12), t (1 + 1e-12)].
"""
from __future__ import annotations

import tempfile

from max2code.conformance.equations import USER_EQUATIONS, equation_file, known_equations
from max2code.conformance.ops import Verdict

LETTERS = {"circle-circle": "abcdefmnopqghijklrsuvwxz", "point-line": "abcdefghijkl"}
DEFAULTS = {"window_angle": 1.0, "refine": True, "zero_tol": 0.0}


def malformed(case: dict) -> str:
    if case.get("equation") not in LETTERS and case.get("equation") not in USER_EQUATIONS:
        return (f"unknown equation {case.get('equation')!r} (known: {known_equations()}; "
                "max2code conformance --equation FILE.mxm names another)")
    if not isinstance(case.get("params"), dict):
        return "params must be an object of letter: number"
    missing = [k for k in LETTERS.get(case["equation"], "") if k not in case["params"]]
    if missing:
        return f"missing parameters {', '.join(missing)}"
    h = case.get("horizon")
    if not isinstance(h, (int, float)) or not h > 0:
        return "horizon must be a positive number"
    opts = case.get("options", {})
    if not isinstance(opts, dict) or set(opts) - set(DEFAULTS):
        return f"options may hold {', '.join(DEFAULTS)}"
    return ""


def row(case: dict, names) -> list[float]:
    o = dict(DEFAULTS, **case.get("options", {}))
    return ([float(case["params"][n]) for n in names] +
            [float(case["horizon"]), float(o["window_angle"]), 1.0 if o["refine"] else 0.0, float(o["zero_tol"]), 0.0])


def batch(lang: str, cases: dict[int, dict]) -> dict[int, str]:
    # imported here: the runner loads this module, and roots-only runs need no generator
    from max2code.generate.pipeline import GenerateRequest, generate_file
    from max2code.toolchain.exact import build_exact_harness

    answers: dict[int, str] = {}
    by_eq: dict[str, list[int]] = {}
    for seq, case in cases.items():
        why = malformed(case)
        if why:
            answers[seq] = f"error: malformed toc case: {why}"
        else:
            by_eq.setdefault(case["equation"], []).append(seq)
    for equation, seqs in sorted(by_eq.items()):
        g = generate_file(GenerateRequest(path=str(equation_file(equation)), lang=lang,
                                          out_name="generated", exact=True))
        missing = {s: [n for n in g.exact.params if n not in cases[s]["params"]] for s in seqs}
        for s in [s for s in seqs if missing[s]]:
            answers[s] = f"error: malformed toc case: missing parameters {', '.join(missing[s])}"
        seqs = [s for s in seqs if not missing[s]]
        if not seqs:
            continue
        with tempfile.TemporaryDirectory(prefix=f"exact-{lang}-") as tmp:
            h = build_exact_harness(lang, g.text, g.exact, tmp)
            got, _ = h.run([row(cases[s], g.exact.params) for s in seqs])
        for s, (status, t) in zip(seqs, got):
            answers[s] = {1: repr(t), 0: "none", 2: "overlapped"}.get(status, "unsupported")
    return answers


def judge(case: dict, answer: str):
    expect = case.get("expect")
    if answer.startswith("error"):
        return Verdict(False, "-", why=answer[len("error: "):])
    if answer == "unsupported":
        return Verdict(False, answer, why="the entry refused the parameters")
    if answer == "overlapped" or expect == "overlapped":
        # "overlapped": the gap is below minus the rounding band at t = 0; overlapped_ok: the gap is
        # negative at t = 0 but within the reference's band, where either answer stands
        ok = answer == "overlapped" and (expect == "overlapped" or bool(case.get("overlapped_ok")))
        why = "" if ok else ("the bodies overlap at t = 0: expected overlapped" if expect == "overlapped" else
                             "answered overlapped, but the bodies do not overlap at t = 0")
        return Verdict(ok, answer, why=why)
    if answer == "none":
        ok = expect is None or bool(case.get("none_ok"))
        return Verdict(ok, "none", why="" if ok else f"missed the contact at {expect!r}")
    t = float(answer)
    inside = any(lo <= t <= hi for lo, hi in case.get("accept", []))
    rel = None
    if expect is not None:
        rel = abs(t - expect) / abs(expect) if expect != 0 else abs(t)
    if not inside:
        why = "invented a contact" if expect is None and not case.get("accept") else \
            f"outside the accepted times (expected {expect!r})"
        return Verdict(False, answer, relerr=rel, why=why)
    return Verdict(True, answer, relerr=rel, wellcond=bool(case.get("regular")))


def summary(reports, cases: list[dict]) -> str:
    """Per runtime, over the exact-motion cases: the largest relative error
    on regular contacts, and how many contacts were missed or invented."""
    exact = {str(c.get("id")): c for c in cases if c.get("op") == "toc" and c.get("motion") == "exact"}
    if not exact:
        return ""
    rows = ["exact-motion contact times (op toc, motion exact): max relative error on regular contacts; "
            "missed / invented contacts; failures"]
    for rep in reports:
        res = [r for r in rep.results if r.case_id in exact]
        regular = [r.verdict.relerr for r in res if r.verdict.ok and r.verdict.wellcond and r.verdict.relerr is not None]
        missed = sum(1 for r in res if not r.verdict.ok and r.verdict.shown == "none")
        invented = sum(1 for r in res if not r.verdict.ok and r.verdict.shown not in ("none", "-")
                       and exact[r.case_id].get("expect") is None)
        worst = f"{max(regular):.1e}" if regular else "-"
        rows.append(f"  {rep.lang:>7s}: {len(res)} cases, max relative error {worst} over {len(regular)} regular contacts; "
                    f"{missed} missed, {invented} invented; {sum(1 for r in res if not r.verdict.ok)} failed")
    return "\n".join(rows)
