"""Run the Python simulator: `python -m max2code_rt.sim_main CC.py PE.py
[--step DT [--live]]` reads a compiled scene on stdin and writes the flat trace on
stdout (docs/simulator.md); on a stuck or bad scene it writes `X message`
and exits 1.

With `--step DT` the run drives the live world (docs/engine-api.md) in steps
instead: advance(k DT) for k = 1, 2, ... below the end, then finish(); after
each advance it writes, on stderr, `P T BODY PX PY VX VY ANGLE OMEGA` (every
body's state(body, T), %.17g) and `C T COUNT` (the contacts advance
returned).  The trace must be the batch run's, byte for byte.  With
`--live` too, the scene's inputs (in time order) are taken out of the scene
and made as live inputs at their times instead: the same bytes again."""
from __future__ import annotations

import importlib.util
import sys

from max2code_rt.sim import SimError, World, simulate
from max2code_rt.sim.scene import MAX_TEXT, check_text


def _load(path: str, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def split_inputs(text: str) -> tuple[str, list[list[str]]]:
    """The flat scene with its input lines taken out (`inputs 0`), and
    those lines' fields (T BODY MODE X Y) in order."""
    head, sep, tail = text.partition("\ninputs ")
    if not sep:
        raise SimError("scene: expected 'inputs'")
    lines = tail.split("\n")
    k = int(lines[0])
    return head + "\ninputs 0\nend\n", [lines[1 + i].split()[1:] for i in range(k)]


def stepped(text: str, cc, pe, out, probe, dt: float, live: bool) -> None:
    """The scene through the live API in steps of dt (the ports' `--step`);
    with live, its inputs are made live: advance to each input's time, then
    the live operation of its mode (docs/engine-api.md, "Checking a port")."""
    inputs: list[list[str]] = []
    if live:
        check_text(text, "scene")       # the whole text, as the batch run checks it
        text, inputs = split_inputs(text)
    w = World(text, cc, pe, out)
    ops = (w.set_velocity, w.add_velocity, w.apply_impulse, w.teleport,
           lambda body, x, y: w.remove_body(body))                           # by MODE
    end = w.s.end
    nxt = 0             # the next live input
    k = 1
    while True:
        t = k * dt
        while nxt < len(inputs) and (not (t < end) or float(inputs[nxt][0]) <= t):
            f = inputs[nxt]
            w.advance(float(f[0]))
            if ops[int(f[2])](int(f[1]), float(f[3]), float(f[4])) is False:
                raise SimError(f"live input {nxt}: teleport refused (the body would overlap another)")
            nxt += 1
        if not (t < end):
            break
        got = w.advance(t)
        every = w.states(t)         # every body at once, checked against one by one
        for b in range(len(w.s.bodies)):
            if w.state(b, t) != every[b]:
                raise SimError(f"states(t) gives body {b} another state than state({b}, t)")
            px, py, vx, vy, ang, om = every[b]
            probe.write(f"P {t:.17g} {b} {px:.17g} {py:.17g} {vx:.17g} {vy:.17g} {ang:.17g} {om:.17g}\n")
        probe.write(f"C {t:.17g} {len(got)}\n")
        k += 1
    w.finish()


def main(argv: list[str]) -> int:
    live = "--live" in argv
    args = [a for a in argv if a != "--live"]
    if len(args) not in (2, 4) or (len(args) == 4 and args[2] != "--step") or (live and len(args) != 4):
        print("usage: python -m max2code_rt.sim_main CIRCLE_CIRCLE.py POINT_EDGE.py [--step DT [--live]] < scene",
              file=sys.stderr)
        return 2
    cc = _load(args[0], "m2c_gen_circle_circle")
    pe = _load(args[1], "m2c_gen_point_edge")
    out = sys.stdout
    # bytes read as latin-1 never fail to decode: the scene's check names a bad byte by its offset;
    # one byte more than a flat text may have is enough to refuse a longer one
    text = sys.stdin.buffer.read(MAX_TEXT + 1).decode("latin-1")
    try:
        if len(args) == 4:
            stepped(text, cc, pe, out, sys.stderr, float(args[3]), live)
        else:
            simulate(text, cc, pe, out)
    except SimError as exc:
        out.write(f"X {exc}\n")
        out.flush()
        return 1
    out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
