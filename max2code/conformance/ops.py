"""The conformance wire format (doubles as 16 hex digits) and the "roots"
op: how a case is sent to a testee and how its answer is judged."""
from __future__ import annotations

import struct
from dataclasses import dataclass


# --------------------------------------------------------------------- wire
def hex_of(x: float) -> str:
    return "%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def float_of(h: str) -> float:
    return struct.unpack("<d", struct.pack("<Q", int(h, 16)))[0]


def num(v) -> float:
    """A case number: a JSON number or one of the strings nan, inf, -inf."""
    if isinstance(v, str):
        return float(v)
    return float(v)


# ---------------------------------------------------------------------- ops
@dataclass
class Verdict:
    ok: bool
    shown: str               # the answer as printed
    relerr: float | None = None
    why: str = ""
    wellcond: bool = False   # matched a simple root whose tolerance is the 1e-12 relative floor


class RootsOp:
    """op "roots": smallest root of sum coeffs[i] t^i in (lo, hi]."""

    name = "roots"

    def wire(self, case: dict, seq: int) -> str:
        c = [num(v) for v in case["coeffs"]]
        return " ".join(["roots", str(seq), hex_of(num(case["lo"])), hex_of(num(case["hi"])),
                         str(len(c))] + [hex_of(v) for v in c])

    def degree(self, case: dict) -> int:
        return len(case["coeffs"]) - 1

    def judge(self, case: dict, answer: str) -> Verdict:
        lo, hi = num(case["lo"]), num(case["hi"])
        roots = case.get("roots", [])
        if answer.startswith("error"):
            return Verdict(False, answer, why="testee error")
        if answer == "none":
            sure = [r for r, _m, tol in roots if lo + tol < r <= hi - tol]
            if sure:
                return Verdict(False, "none", why=f"missed root {sure[0]!r}")
            return Verdict(True, "none")
        try:
            t = float_of(answer)
        except ValueError:
            return Verdict(False, answer, why="unreadable answer")
        shown = repr(t)
        if not (lo < t <= hi):
            return Verdict(False, shown, why="answer outside (lo, hi]")
        for j, (r, m, tol) in enumerate(roots):
            if abs(t - r) <= tol:
                skipped = [ri for ri, _mi, toli in roots[:j] if not ri <= lo + toli]
                if skipped:
                    return Verdict(False, shown, why=f"skipped smaller root {skipped[0]!r}")
                rel = abs(t - r) / abs(r) if r != 0.0 else abs(t)
                well = m == 1 and tol <= 1.000001e-12 * abs(r)
                return Verdict(True, shown, relerr=rel, wellcond=well)
        want = case.get("expect")
        return Verdict(False, shown, why=f"not a root (expected {want!r})")
