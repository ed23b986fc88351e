"""Run the Python simulator: `python -m max2code_rt.sim_main CC.py PE.py
[--step DT]` reads a compiled scene on stdin and writes the flat trace on
stdout (docs/simulator.md); on a stuck or bad scene it writes `X message`
and exits 1.

With `--step DT` the run drives the live world (docs/engine-api.md) in steps
instead: advance(k DT) for k = 1, 2, ... below the end, then finish(); after
each advance it writes, on stderr, `P T BODY PX PY VX VY ANGLE OMEGA` (every
body's state(body, T), %.17g) and `C T COUNT` (the contacts advance
returned).  The trace must be the batch run's, byte for byte."""
from __future__ import annotations

import importlib.util
import sys

from max2code_rt.sim import SimError, World, simulate


def _load(path: str, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def stepped(text: str, cc, pe, out, probe, dt: float) -> None:
    """The scene through the live API in steps of dt (the ports' `--step`)."""
    w = World(text, cc, pe, out)
    end = w.s.end
    k = 1
    while k * dt < end:
        t = k * dt
        got = w.advance(t)
        for b in range(len(w.s.bodies)):
            px, py, vx, vy, ang, om = w.state(b, t)
            probe.write(f"P {t:.17g} {b} {px:.17g} {py:.17g} {vx:.17g} {vy:.17g} {ang:.17g} {om:.17g}\n")
        probe.write(f"C {t:.17g} {len(got)}\n")
        k += 1
    w.finish()


def main(argv: list[str]) -> int:
    if len(argv) not in (2, 4) or (len(argv) == 4 and argv[2] != "--step"):
        print("usage: python -m max2code_rt.sim_main CIRCLE_CIRCLE.py POINT_EDGE.py [--step DT] < scene",
              file=sys.stderr)
        return 2
    cc = _load(argv[0], "m2c_gen_circle_circle")
    pe = _load(argv[1], "m2c_gen_point_edge")
    out = sys.stdout
    try:
        if len(argv) == 4:
            stepped(sys.stdin.read(), cc, pe, out, sys.stderr, float(argv[3]))
        else:
            simulate(sys.stdin.read(), cc, pe, out)
    except SimError as exc:
        out.write(f"X {exc}\n")
        out.flush()
        return 1
    out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
