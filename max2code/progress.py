"""One progress bar for long work (Maxima deriving variants, table and
benchmark sweeps), drawn on stderr on one line."""
from __future__ import annotations

import sys

WIDTH = 24


def bar(i: int, n: int, what: str, prefix: str = "max2code") -> None:
    """Show step i of n; the last step ends the line."""
    done = int(WIDTH * i / max(n, 1))
    end = "\n" if i >= n else ""
    print(f"\r{prefix}: [{'#' * done}{'.' * (WIDTH - done)}] {i}/{n} {what:<50}", end=end,
          file=sys.stderr, flush=True)
