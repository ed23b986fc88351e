"""Where max2code finds its data and puts its builds: the one place that
knows the layout.  ROOT holds the design card's top-level folders
(templates/, equations/, runtimes/, tests/conformance/); BUILD is where the
runtime libraries and harnesses are compiled."""
from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "build"
TEMPLATES = ROOT / "templates"
EQUATIONS = ROOT / "equations"
RUNTIMES = ROOT / "runtimes"
CASES = ROOT / "tests" / "conformance"
