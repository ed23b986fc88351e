"""The facts that the generator and the four runtimes share, in one place.

Each runtime is its own source tree in its own language (a runtime must
build without max2code installed), so each keeps its own spelling of these
facts: tests/docs/test_facts.py reads every copy, in every runtime, and fails
when one differs from the values here.  Change a fact here first, then in
each file that test names.

- VERSION: the release, as max2code.__version__, the Python runtime's
  pyproject.toml, the Rust crate's Cargo.toml (and Cargo.lock), the C
  library's Makefile (VERSION, the shared library's name) and CHANGELOG.md.
- MAX_DEGREE: the largest degree the runtimes' root solvers and the
  exact-motion driver take (docs/roots.md).
- EVENT_KINDS: the simulator's event kinds, in the order they are handled
  at equal times; a kind's code is its index (docs/simulator.md).  The
  order decides the trace's bytes.
- TRACE_EVENTS: the words of the trace's E lines.
- STAT_NAMES: the trace's N lines (the simulator's counters), in the order
  they are written.
"""
from __future__ import annotations

from max2code import __version__

VERSION = __version__

MAX_DEGREE = 16

EVENT_KINDS = ("input", "collision", "stop", "leave", "cell", "horizon", "frame")

TRACE_EVENTS = ("collision", "support", "stop", "leave", "sleep", "wake", "input", "add", "frame")

STAT_NAMES = ("collisions", "inputs", "frames", "cells", "horizons", "stale", "pairs", "features",
              "supports", "stops", "leaves", "sleeps", "wakes")
