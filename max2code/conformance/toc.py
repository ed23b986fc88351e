"""The conformance op "toc": time of contact through the generated entry
functions (`NAME_toc`), with their variant selection and the runtime's
solver.

Case: {"id", "op": "toc", "equation": "circle-circle" | "point-line" | a user's,
       "params": {letter: value}, "horizon": T, "expect": t | null, "tol": abs}
or, as `max2code cases` writes them (user_cases.py), "accept" intervals and
"none_ok" instead of "tol".  A user's equation is known by the file's stem
or its `equation` name once registered with use_equation (`max2code
conformance --equation FILE`).
The answer is the smallest t in (0, T] at which the equation's polynomial
(the bundled .mxm at its default Taylor order) is zero.  References come
from motion_ref (polynomial arithmetic at 60 digits, independent of Maxima
and of max2code) and mpmath.polyroots; `tol` bounds the error a double
evaluation of the coefficients can cause (condition of the root) plus 1e-12
relative.
"""
from __future__ import annotations

import json
import os
import random
import re
import sys
import tempfile
from pathlib import Path

import mpmath

from max2code.conformance import exact_op
from max2code.conformance.equations import equation_file, known_equations
from max2code.conformance.motion_ref import EQUATIONS, scale
from max2code.conformance.ops import Verdict, float_of, hex_of, num

from max2code.paths import CASES
from max2code.targets import LANGUAGES
ORDER = 4
EPS = 2.0 ** -52
CASE_FILE = CASES / "toc.jsonl"

# a user's equations, by the names a case may give them (the file's stem and its `equation` name)
def reference(equation: str, params: dict, horizon: float):
    """(t or None, tolerance, reason-to-skip or None) for one case."""
    with mpmath.workdps(60):
        coef = EQUATIONS[equation](params, ORDER)
        sk = scale(equation, params, ORDER)
        while len(coef) > 1 and coef[-1] == 0:
            coef, sk = coef[:-1], sk[:-1]
        if len(coef) < 2:
            return None, 0.0, "constant polynomial"
        roots = mpmath.polyroots(list(reversed(coef)), maxsteps=400, extraprec=400)
        real = sorted(mpmath.re(r) for r in roots if abs(mpmath.im(r)) <= mpmath.mpf(10) ** -30 * max(1, abs(r)))
        near = [r for r in roots if abs(mpmath.im(r)) < 1e-6 * max(1, abs(r)) and -1e-6 < mpmath.re(r) <= horizon * (1 + 1e-6)]
        inside = [r for r in real if 0 < r <= horizon]
        deriv = [k * c for k, c in enumerate(coef)][1:]

        def tol_at(r):
            p1 = abs(mpmath.polyval(list(reversed(deriv)), r))
            noise = 64 * EPS * sum(s * abs(r) ** k for k, s in enumerate(sk))
            return float(1e-12 * abs(r) + noise / p1) if p1 else float("inf")

        if len(near) > len(inside) and not inside:
            return None, 0.0, "a near-real root close to the window: ambiguous"
        if not inside:
            return None, 0.0, None
        r = inside[0]
        tol = tol_at(r)
        if tol > 1e-6 * max(1.0, float(abs(r))) or r < 1e-9 or horizon - r < 1e-9:
            return None, 0.0, "ill-conditioned or at a window edge"
        return float(r), tol, None


def _sample(equation: str, rng: random.Random) -> dict:
    if equation == "point-line":
        p = {}
        for pos, vel, acc, rad, w, ph in (("a", "b", "c", "d", "e", "f"), ("g", "h", "i", "j", "k", "l")):
            p.update({pos: rng.uniform(-3, 3), vel: rng.uniform(-3, 3), acc: rng.uniform(-2, 2),
                      rad: rng.uniform(0, 1), w: rng.uniform(-2, 2), ph: rng.uniform(-3.1, 3.1)})
        off = {"d": ["d"], "c": ["c"], "j": ["j"], "i": ["i"]}
    else:
        a, m = rng.uniform(-10, 10), rng.uniform(-10, 10)
        p = {"a": a, "b": rng.uniform(-3, 3), "c": rng.uniform(-1, 1), "d": rng.uniform(0, 1), "e": rng.uniform(-1, 1),
             "f": rng.uniform(-3.1, 3.1), "m": m, "n": rng.uniform(-3, 3), "o": rng.uniform(-1, 1),
             "p": rng.uniform(-1, 1), "q": rng.uniform(-3.1, 3.1),
             "g": a + rng.uniform(-6, 6), "h": rng.uniform(-3, 3), "i": rng.uniform(-1, 1), "j": rng.uniform(0, 1),
             "k": rng.uniform(-1, 1), "l": rng.uniform(-3.1, 3.1), "r": m + rng.uniform(-6, 6),
             "s": rng.uniform(-3, 3), "u": rng.uniform(-1, 1), "v": rng.uniform(-1, 1), "w": rng.uniform(-3.1, 3.1),
             "x": rng.uniform(0.1, 1.5), "z": rng.uniform(0.1, 1.5)}
        off = {"d": ["d"], "c": ["c", "o"], "x": ["x"], "j": ["j"], "i": ["i", "u"], "z": ["z"]}
    for names in off.values():
        if rng.random() < 0.4:
            for n in names:
                p[n] = 0.0
    return p


def generate(n_per_equation: int = 150, seed: int = 2026) -> list[dict]:
    """Random cases with references; ambiguous ones are skipped (counted on stderr)."""
    rng = random.Random(seed)
    cases, skipped = [], 0
    for equation in ("circle-circle", "point-line"):
        made = 0
        while made < n_per_equation:
            params = _sample(equation, rng)
            horizon = rng.choice([0.5, 2.0, 5.0])
            t, tol, why = reference(equation, params, horizon)
            if why:
                skipped += 1
                continue
            cases.append({"id": f"toc-{equation}-{made:03d}", "op": "toc", "equation": equation,
                          "params": params, "horizon": horizon, "expect": t, "tol": tol})
            made += 1
    print(f"toc cases: {len(cases)} written, {skipped} ambiguous draws skipped", file=sys.stderr)
    return cases


def _malformed(case: dict) -> str:
    if not isinstance(case.get("equation"), str) or equation_file(case["equation"]) is None:
        return (f"unknown equation {case.get('equation')!r} (known: {known_equations()}; "
                "max2code conformance --equation FILE.mxm names another)")
    if not isinstance(case.get("params"), dict):
        return "params must be an object of letter: number"
    h = case.get("horizon")
    if not isinstance(h, (int, float)) or not h > 0:
        return "horizon must be a positive number"
    return ""


class TocOp:
    """op "toc": answered by a harness compiled from the generated code of the
    case's equation (templates/<lang>/harness.j2, toc mode)."""

    name = "toc"
    testee_langs = tuple(LANGUAGES)

    def degree(self, case: dict):
        return None

    def batch(self, lang: str, cases: dict[int, dict]) -> dict[int, str]:
        # imported here: the runner loads this module, and roots-only runs need no generator
        from max2code.generate.pipeline import GenerateRequest, generate_file
        from max2code.toolchain.exact import build_poly_harness
        from max2code.toolchain.harness import build_harness

        if lang not in self.testee_langs:
            raise ValueError(f"the toc op has no testee for {lang}")
        answers: dict[int, str] = {}
        exact = {s: c for s, c in cases.items() if c.get("motion") == "exact"}
        if exact:   # the exact motion (sin, cos): max2code/conformance/exact_op.py
            answers.update(exact_op.batch(lang, exact))
        by_eq: dict[str, list[int]] = {}
        for seq, case in cases.items():
            if seq in exact:
                continue
            if case.get("motion", "taylor") != "taylor":
                answers[seq] = f"error: malformed toc case: motion must be 'taylor' or 'exact', not {case.get('motion')!r}"
                continue
            why = _malformed(case)
            if why:
                answers[seq] = f"error: malformed toc case: {why}"
            else:
                by_eq.setdefault(case["equation"], []).append(seq)
        for equation, seqs in sorted(by_eq.items()):
            path = equation_file(equation)
            g = generate_file(GenerateRequest(path=str(path), lang=lang, out_name="generated"))
            missing = {s: [n for n in g.function.params if n not in cases[s]["params"]] for s in seqs}
            for s in [s for s in seqs if missing[s]]:
                answers[s] = f"error: malformed toc case: missing parameters {', '.join(missing[s])}"
            seqs = [s for s in seqs if not missing[s]]
            if not seqs:
                continue
            params = [[float(cases[s]["params"][n]) for n in g.function.params] for s in seqs]
            with tempfile.TemporaryDirectory(prefix=f"toc-{lang}-") as tmp:
                if g.selection is not None:     # NAME_toc: the selected variant, then the runtime's solver
                    h = build_harness(lang, g, tmp, mode="toc")
                    got = h.evaluate([p + [0.0, float(cases[s]["horizon"])] for p, s in zip(params, seqs)])
                else:       # no roles, no NAME_toc: the equation's function, then the runtime's solver on (0, T]
                    h = build_poly_harness(lang, g.text, g.function.params, g.function.name, False, g.function.degree,
                                           tmp)
                    got, _ = h.run([p + [float(cases[s]["horizon"])] for p, s in zip(params, seqs)])
                for s, (status, t) in zip(seqs, got):
                    answers[s] = {1.0: repr(t), 0.0: "none"}.get(status, "unsupported")
        return answers

    def wire(self, case: dict, seq: int) -> str:
        """The case as a line for a testee of the user's own (docs/conformance.md, "Wire format"):
        toc SEQ EQUATION MOTION HORIZON COUNT NAME1 HEX1 ... (the parameters in the case's order)."""
        if not isinstance(case.get("equation"), str) or not re.fullmatch(r"[A-Za-z0-9_.+-]+", case["equation"]):
            raise ValueError("equation must be a name without spaces")
        if not isinstance(case.get("params"), dict) or not all(re.fullmatch(r"\S+", k) for k in case["params"]):
            raise ValueError("params must be an object of name: number")
        motion = case.get("motion", "taylor")
        if motion not in ("taylor", "exact"):
            raise ValueError(f"motion must be 'taylor' or 'exact', not {motion!r}")
        params = [f"{k} {hex_of(num(v))}" for k, v in case["params"].items()]
        return " ".join(["toc", str(seq), case["equation"], motion, hex_of(num(case["horizon"])),
                         str(len(params))] + params)

    @staticmethod
    def read(answer: str) -> str:
        """A testee's wire answer as the judge reads it: HEX as the double's repr; none, overlapped, error as they are."""
        if re.fullmatch(r"[0-9a-f]{16}", answer):
            return repr(float_of(answer))
        return answer

    def judge(self, case: dict, answer: str):
        if case.get("motion") == "exact" or "accept" in case:
            return exact_op.judge(case, answer)
        expect, tol = case.get("expect"), float(case.get("tol", 0.0))
        if answer.startswith("error"):
            return Verdict(False, "-", why=answer[len("error: "):])
        if answer == "unsupported":
            return Verdict(False, answer, why="the entry refused the parameters")
        if answer == "none":
            return Verdict(expect is None, "none", why="" if expect is None else f"missed contact at {expect!r}")
        t = float(answer)
        if expect is None:
            return Verdict(False, answer, why="invented a contact")
        err = abs(t - expect)
        return Verdict(err <= tol, answer, relerr=err / abs(expect), why="" if err <= tol else f"expected {expect!r} +- {tol:.1e}")


def main(argv: list[str] | None = None) -> int:
    cases = generate()
    with open(CASE_FILE, "w", encoding="utf-8") as fh:
        for c in cases:
            fh.write(json.dumps(c, sort_keys=True) + "\n")
    print(f"wrote {CASE_FILE}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
