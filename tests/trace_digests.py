"""Pinned digests of every example scene's trace (as Box2D pins its
EXPECTED_HASH): a change made in all four runtimes at once still shows.

The trace is the flat text the simulator writes (docs/simulator.md), from the
C runtime; tests/simulator/test_crosscheck.py proves the other three write the same
bytes.  After an intended change of the simulator, refresh the pins with

    python3 tests/trace_digests.py --update

and say in the commit why the traces changed."""
from __future__ import annotations

import hashlib
import json
import os
import sys
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
PINS = ROOT / "tests" / "data" / "trace-digests.json"
# the runtime whose trace is pinned; a reference change not yet ported can be
# pinned from the Python runtime with M2C_DIGEST_LANG=python
LANG = os.environ.get("M2C_DIGEST_LANG", "c")


def examples() -> list[Path]:
    return sorted(p for p in (ROOT / "examples").glob("*.json"))


def digest(path: Path) -> str:
    from max2code.sim.scene import load_scene
    from max2code.sim.simulate import run_scene
    return hashlib.sha256(run_scene(load_scene(str(path)), LANG).raw.encode()).hexdigest()


def pinned() -> dict[str, str]:
    return json.loads(PINS.read_text(encoding="utf-8"))


def main(argv: list[str]) -> int:
    if argv != ["--update"]:
        print(__doc__)
        return 2
    pins = {p.name: digest(p) for p in examples()}
    PINS.write_text(json.dumps(pins, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    print(f"{PINS}: {len(pins)} examples")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main(sys.argv[1:]))
