"""Whether a set of files is as it was when a digest of it was last taken,
from their stat alone (no reading, no hashing): the build-cache checks of
`max2code simulate` run on every command, and hashing the sources there cost
2 ms plus 5-9 ms to import hashlib (OpenSSL), against a simulation of a few
ms on the example scenes.

A file's state is its path, size, modification and change times (ns) and
inode: writing a file changes its change time, which no program can set
back, and replacing it changes its inode.  The one case stat cannot see is a
file written twice within one tick of the file system's clock (a few ms)
with the same size, the second time after its state was taken: so a state is
remembered only when every file is older than RACY_NS; until then each run
hashes again."""
from __future__ import annotations

import os
import time
from pathlib import Path

RACY_NS = 2_000_000_000     # a file changed in the last 2 s may change again with the same stat
_clock = time.time_ns       # the clock that the files' times are compared with


class State:
    """The state of some files: `text` (one line per file), `newest` (the
    latest modification or change time among them, ns)."""

    def __init__(self, text: str, newest: int):
        self.text, self.newest = text, newest


def state(paths, head: str = "") -> State | None:
    """The state of the files `paths` (in this order), after a first line
    `head` (what else the digest depends on: flags, versions); None when one
    of them cannot be stat'ed (the caller then reads and hashes, and reports
    whatever is wrong)."""
    lines = [head]
    newest = 0
    try:
        for p in paths:
            st = os.stat(p)
            lines.append(f"{p}\0{st.st_size} {st.st_mtime_ns} {st.st_ctime_ns} {st.st_ino}")
            newest = max(newest, st.st_mtime_ns, st.st_ctime_ns)
    except OSError:
        return None
    return State("\n".join(lines), newest)


def recall(memo: Path, now: State | None) -> str | None:
    """The digest remembered in the file `memo` for exactly this state, else None."""
    if now is None:
        return None
    try:
        text = memo.read_text(encoding="utf-8")
    except (OSError, ValueError):
        return None
    saved, sep, digest = text.rpartition("\n")
    return digest if sep and digest and saved == now.text else None


def remember(memo: Path, now: State | None, digest: str) -> None:
    """Remember `digest` for the state `now` in the file `memo` (written
    whole, then renamed), unless a file is younger than RACY_NS; a memo that
    cannot be written is left out (the next run hashes again)."""
    if now is None or _clock() - now.newest < RACY_NS or "\n" in digest:
        return
    tmp = memo.with_name(f"{memo.name}.{os.getpid()}.tmp")
    try:
        memo.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text(f"{now.text}\n{digest}", encoding="utf-8")
        os.replace(tmp, memo)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
