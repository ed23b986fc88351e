"""The flat trace's common lines (states, collisions, supports, frames) in C:
runtimes/c/tools/m2c_trace_json.c, built once into a shared library under
BUILD/trace-json/ and called through ctypes, one chunk of whole events at a
time.  Python converts at about the rate the engine writes, so the command
took twice the engine's time even with the two on two cores; in C the
conversion is a small part of it (docs/simulator.md).

The C code is only an accelerator: a chunk it does not take (any line but
those four kinds, any number or index not in its plain form) goes to
TraceConverter.feed_chunk, which writes the same bytes or the precise
error; and without a C compiler the command converts in Python."""
from __future__ import annotations

import ctypes
import hashlib
import os
import subprocess
import tempfile

from max2code.paths import BUILD, RUNTIMES

SOURCE = RUNTIMES / "c" / "tools" / "m2c_trace_json.c"
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-shared", "-fPIC"]
_lib: ctypes.CDLL | None = None
_tried = False
_why = ""          # why the library could not be had (after library() returned None)


def build() -> str:
    """The shared library's path, compiled when its source or flags changed;
    OSError or CalledProcessError when it cannot be."""
    src = SOURCE.read_bytes()
    digest = hashlib.sha256(src + "\0".join(FLAGS).encode()).hexdigest()[:16]
    folder = BUILD / "trace-json" / digest
    lib = folder / "libm2c_trace_json.so"
    if not lib.exists():
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(suffix=".so", dir=folder)
        os.close(fd)
        try:
            subprocess.run(["gcc", *FLAGS, str(SOURCE), "-o", tmp], check=True, capture_output=True, timeout=300)
            os.replace(tmp, lib)         # whole or not at all, with other runs building at once
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return str(lib)


def library() -> ctypes.CDLL | None:
    """The loaded library, or None when it cannot be built or loaded (then
    why_not() says why)."""
    global _lib, _tried, _why
    if not _tried:
        _tried = True
        try:
            lib = ctypes.CDLL(build())
        except subprocess.CalledProcessError as exc:
            err = (exc.stderr or b"").decode("ascii", "replace").strip().splitlines()
            _why = f"gcc failed on {SOURCE.name}" + (f": {err[0]}" if err else "")
            return None
        except FileNotFoundError as exc:
            _why = f"{exc.filename or 'gcc'} not found"
            return None
        except (OSError, subprocess.SubprocessError) as exc:
            _why = f"{type(exc).__name__}: {exc}"
            return None
        lib.tj_new.restype = ctypes.c_void_p
        lib.tj_new.argtypes = [ctypes.c_char_p, ctypes.c_long, ctypes.c_long, ctypes.c_long]
        lib.tj_free.restype = None
        lib.tj_free.argtypes = [ctypes.c_void_p]
        lib.tj_finals.restype = ctypes.c_long
        lib.tj_finals.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_long, ctypes.c_char_p, ctypes.c_long]
        lib.tj_convert.restype = ctypes.c_long
        lib.tj_convert.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_long, ctypes.c_char_p, ctypes.c_long,
                                   ctypes.c_int, ctypes.POINTER(ctypes.c_long), ctypes.POINTER(ctypes.c_long)]
        _lib = lib
    return _lib


def why_not() -> str:
    """Why library() returned None (empty when it did not)."""
    return _why


class CTrace:
    """One run's converter: the bodies' names as JSON text, the largest
    vertex or body index a feature may name (`text`: the names each followed
    by a newline, when the caller has them so)."""

    def __init__(self, lib: ctypes.CDLL, names: list[str], most: int, text: bytes | None = None):
        if text is None:
            text = "".join(n + "\n" for n in names).encode("ascii")
        self.lib = lib
        self.handle = lib.tj_new(text, len(text), len(names), most)
        if not self.handle:
            raise MemoryError("m2c_trace_json: tj_new")
        self.cap = 1 << 18
        self.buf = ctypes.create_string_buffer(self.cap)
        self.events = ctypes.c_long(0)
        self.lines = ctypes.c_long(0)

    def convert(self, data: bytes, frames: bool) -> tuple[str, int] | None:
        """The JSON lines of `data` (whole events, as ASCII bytes), its
        number of events and of lines, or None when Python must convert it."""
        while True:
            n = self.lib.tj_convert(self.handle, data, len(data), self.buf, self.cap, int(frames),
                                    ctypes.byref(self.events), ctypes.byref(self.lines))
            if n == -2:                  # room for a line's worth more than the trace's bytes, grown as needed
                self.cap = max(2 * self.cap, 4 * len(data))
                self.buf = ctypes.create_string_buffer(self.cap)
                continue
            if n < 0:
                return None
            return ctypes.string_at(self.buf, n), self.events.value, self.lines.value

    def finals(self, data: bytes) -> str | None:
        """The JSON of complete F lines, comma-separated, or None when Python
        must convert them."""
        while True:
            n = self.lib.tj_finals(self.handle, data, len(data), self.buf, self.cap)
            if n == -2:
                self.cap = max(2 * self.cap, 4 * len(data))
                self.buf = ctypes.create_string_buffer(self.cap)
                continue
            return None if n < 0 else ctypes.string_at(self.buf, n).decode("ascii")

    def __del__(self):
        if getattr(self, "handle", None):
            self.lib.tj_free(self.handle)
            self.handle = None
