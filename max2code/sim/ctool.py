"""The command's own C accelerators (the trace converter, the scene reader):
each one source file under runtimes/c/tools/, built once with gcc into a
shared library under BUILD/<folder>/<hash of source and flags>/ and loaded
through ctypes.  A library that cannot be built or loaded is None, and
why_not() says why; its caller then takes the Python path, which gives the
same bytes.

Each edit of a source leaves a new folder: past KEEP of them the oldest are
removed, under a lock (BUILD/<folder>/lock) so that none goes while another
run may still load from it.  A run holds the lock shared from finding its
folder until its library is loaded; removing takes it exclusive without
waiting, and leaves the pile for a later run when another holds it.  A
library already loaded by a run stays mapped in that process when its file
is removed (POSIX), so only loading needs the lock."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

try:
    import fcntl
except ImportError:         # not on Windows: nothing is ever removed there
    fcntl = None

from max2code import filestate
from max2code.paths import BUILD

KEEP = 3        # library folders kept per tool: the current one and the two newest others (a checkout that goes back
                # and forth between two branches rebuilds neither)
_DIGEST = re.compile(r"[0-9a-f]{16}")       # a library folder's name: nothing else in BUILD/<folder>/ is removed


class CTool:
    """One C source built into a shared library on first use.  `loader` is
    ctypes.CDLL, or ctypes.PyDLL for code that calls the interpreter;
    `signatures` lists (function name, restype, argtypes)."""

    def __init__(self, source: Path, flags: list[str], folder: str, loader, signatures):
        self.source, self.flags, self.folder = source, flags, folder
        self.loader, self.signatures = loader, signatures
        self._lib = None
        self._tried = False
        self._why = ""          # why the library could not be had (after library() returned None)

    def build(self) -> str:
        """The shared library's path, compiled when its source or flags
        changed; OSError or CalledProcessError when it cannot be."""
        memo = BUILD / self.folder / "source.state"     # the digest of the source as it was (filestate.py)
        now = filestate.state([str(self.source)], "\0".join(self.flags))
        digest = filestate.recall(memo, now)
        if digest is None:
            import hashlib      # only here: importing it (OpenSSL) costs more than a run of a small scene
            src = self.source.read_bytes()
            digest = hashlib.sha256(src + "\0".join(self.flags).encode()).hexdigest()[:16]
            filestate.remember(memo, now, digest)
        folder = BUILD / self.folder / digest
        lib = folder / f"lib{self.source.stem}.so"
        if not lib.exists():
            folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(suffix=".so", dir=folder)
            os.close(fd)
            try:
                subprocess.run(["gcc", *self.flags, str(self.source), "-o", tmp], stdin=subprocess.DEVNULL,
                               check=True, capture_output=True, timeout=300)
                os.replace(tmp, lib)         # whole or not at all, with other runs building at once
            finally:
                if os.path.exists(tmp):
                    os.unlink(tmp)
        return str(lib)

    def library(self):
        """The loaded library with its functions' types set, or None when it
        cannot be built or loaded (then why_not() says why)."""
        if not self._tried:
            self._tried = True
            lock = self._lock()
            try:
                path = self.build()
                lib = self.loader(path)
                self._prune(lock, os.path.basename(os.path.dirname(path)))
            except subprocess.CalledProcessError as exc:
                err = (exc.stderr or b"").decode("ascii", "replace").strip().splitlines()
                self._why = f"gcc failed on {self.source.name}" + (f": {err[0]}" if err else "")
                return None
            except FileNotFoundError as exc:
                self._why = f"{exc.filename or 'gcc'} not found"
                return None
            except (OSError, subprocess.SubprocessError) as exc:
                self._why = f"{type(exc).__name__}: {exc}"
                return None
            finally:
                if lock is not None:
                    os.close(lock)      # releases it
            for name, res, args in self.signatures:
                fn = getattr(lib, name)
                fn.restype, fn.argtypes = res, args
            self._lib = lib
        return self._lib

    def why_not(self) -> str:
        """Why library() returned None (empty when it did not)."""
        return self._why

    def _lock(self) -> int | None:
        """A descriptor of BUILD/<folder>/lock holding a shared lock (waited
        for while another run removes old folders: a few ms), or None where
        there is no lock to be had (then nothing is removed)."""
        if fcntl is None:
            return None
        try:
            (BUILD / self.folder).mkdir(parents=True, exist_ok=True)
            fd = os.open(BUILD / self.folder / "lock", os.O_RDWR | os.O_CREAT, 0o666)
        except OSError:
            return None
        try:
            fcntl.flock(fd, fcntl.LOCK_SH)
        except OSError:
            os.close(fd)
            return None
        return fd

    def _prune(self, lock: int | None, current: str) -> None:
        """Remove all but the newest KEEP library folders (never `current`,
        the one this run loaded), when no other run holds the lock."""
        if lock is None:
            return
        root = BUILD / self.folder
        try:
            old = [e for e in os.scandir(root) if e.name != current and _DIGEST.fullmatch(e.name) and e.is_dir()]
        except OSError:
            return
        if len(old) < KEEP:
            return
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            return          # another run may be loading from one of them: left for a later run
        old.sort(key=_mtime, reverse=True)
        for e in old[KEEP - 1:]:
            shutil.rmtree(e.path, ignore_errors=True)


def _mtime(entry: os.DirEntry) -> int:
    try:
        return entry.stat().st_mtime_ns
    except OSError:
        return 0        # gone meanwhile: the first to go
