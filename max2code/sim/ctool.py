"""The command's own C accelerators (the trace converter, the scene reader):
each one source file under runtimes/c/tools/, built once with gcc into a
shared library under BUILD/<folder>/<hash of source and flags>/ and loaded
through ctypes.  A library that cannot be built or loaded is None, and
why_not() says why; its caller then takes the Python path, which gives the
same bytes."""
from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

from max2code import filestate
from max2code.paths import BUILD


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
            try:
                lib = self.loader(self.build())
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
            for name, res, args in self.signatures:
                fn = getattr(lib, name)
                fn.restype, fn.argtypes = res, args
            self._lib = lib
        return self._lib

    def why_not(self) -> str:
        """Why library() returned None (empty when it did not)."""
        return self._why
