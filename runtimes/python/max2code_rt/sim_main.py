"""Run the Python simulator: `python -m max2code_rt.sim_main CC.py PE.py`
reads a compiled scene on stdin and writes the flat trace on stdout
(docs/simulator.md); on a stuck or bad scene it writes `X message` and
exits 1."""
from __future__ import annotations

import importlib.util
import sys

from max2code_rt.sim import SimError, simulate


def _load(path: str, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("usage: python -m max2code_rt.sim_main CIRCLE_CIRCLE.py POINT_EDGE.py < scene", file=sys.stderr)
        return 2
    cc = _load(argv[0], "m2c_gen_circle_circle")
    pe = _load(argv[1], "m2c_gen_point_edge")
    out = sys.stdout
    try:
        simulate(sys.stdin.read(), cc, pe, out)
    except SimError as exc:
        out.write(f"X {exc}\n")
        out.flush()
        return 1
    out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
