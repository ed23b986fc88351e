"""Conformance testee for the Python runtime: `python -m max2code_rt.testee`.

Reads the wire format of docs/roots.md ("Conformance suite") on stdin."""
from __future__ import annotations

import struct
import sys

from max2code_rt.roots import MAX_DEGREE, smallest_root


def _f(h: str) -> float:
    return struct.unpack("<d", struct.pack("<Q", int(h, 16)))[0]


def _h(x: float) -> str:
    return "%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def main() -> int:
    out = []
    for line in sys.stdin:
        parts = line.split()
        if len(parts) < 2:
            continue
        op, seq = parts[0], parts[1]
        if op != "roots":
            out.append(f"{seq} error unknown-op")
            continue
        lo, hi, count = _f(parts[2]), _f(parts[3]), int(parts[4])
        if count > MAX_DEGREE + 1:
            out.append(f"{seq} error degree")
            continue
        c = [_f(h) for h in parts[5:5 + count]]
        t = smallest_root(c, lo, hi)
        out.append(f"{seq} none" if t is None else f"{seq} {_h(t)}")
    sys.stdout.write("\n".join(out) + ("\n" if out else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
