"""One progress bar for long work (Maxima deriving variants, table and
benchmark sweeps, rendering), on stderr.  On a terminal it is drawn on one
line that each step redraws; when stderr is not a terminal (a log file, a
pipe, CI) plain lines are printed instead: one at the start, one each time
another tenth of the work is done, and one at the end."""
from __future__ import annotations

import sys

WIDTH = 24


def bar(i: int, n: int, what: str, prefix: str = "max2code") -> None:
    """Show step i of n; the last step ends the line."""
    stream = sys.stderr
    if not _is_terminal(stream):
        n1 = max(n, 1)
        if i <= 0 or i >= n or 10 * i // n1 > 10 * (i - 1) // n1:
            print(f"{prefix}: {i}/{n} {what}", file=stream, flush=True)
        return
    done = int(WIDTH * i / max(n, 1))
    end = "\n" if i >= n else ""
    print(f"\r{prefix}: [{'#' * done}{'.' * (WIDTH - done)}] {i}/{n} {what:<50}", end=end,
          file=stream, flush=True)


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):     # replaced by an object without a file, or closed
        return False
