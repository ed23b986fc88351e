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

from max2code.paths import RUNTIMES
from max2code.sim.ctool import CTool

SOURCE = RUNTIMES / "c" / "tools" / "m2c_trace_json.c"
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-shared", "-fPIC"]
_long_p = ctypes.POINTER(ctypes.c_long)
TOOL = CTool(SOURCE, FLAGS, "trace-json", ctypes.CDLL, [
    ("tj_new", ctypes.c_void_p, [ctypes.c_char_p, ctypes.c_long, ctypes.c_long, ctypes.c_long]),
    ("tj_free", None, [ctypes.c_void_p]),
    ("tj_finals", ctypes.c_long, [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_long, ctypes.c_char_p, ctypes.c_long]),
    ("tj_convert", ctypes.c_long, [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_long, ctypes.c_char_p, ctypes.c_long,
                                   ctypes.c_int, _long_p, _long_p])])


def library() -> ctypes.CDLL | None:
    """The loaded library, or None when it cannot be built or loaded (then
    why_not() says why)."""
    return TOOL.library()


def why_not() -> str:
    """Why library() returned None (empty when it did not)."""
    return TOOL.why_not()


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

    def convert(self, data: bytes, frames: bool, size: int | None = None) -> tuple[memoryview, int, int] | None:
        """The JSON lines of `data` (its first `size` bytes when given: whole
        events, as ASCII bytes), its number of events and of lines, or None
        when Python must convert it.
        The lines are a view of this converter's buffer, not a copy (62 MB
        on the 10^4-disk gas): valid until the next call."""
        size = len(data) if size is None else size
        while True:
            n = self.lib.tj_convert(self.handle, data, size, self.buf, self.cap, int(frames),
                                    ctypes.byref(self.events), ctypes.byref(self.lines))
            if n == -2:                  # room for a line's worth more than the trace's bytes, grown as needed
                self.cap = max(2 * self.cap, 4 * size)
                self.buf = ctypes.create_string_buffer(self.cap)
                continue
            if n < 0:
                return None
            return memoryview(self.buf).cast("B")[:n], self.events.value, self.lines.value

    def finals(self, data: bytes) -> bytes | None:
        """The JSON of complete F lines, comma-separated (ASCII), or None when
        Python must convert them."""
        while True:
            n = self.lib.tj_finals(self.handle, data, len(data), self.buf, self.cap)
            if n == -2:
                self.cap = max(2 * self.cap, 4 * len(data))
                self.buf = ctypes.create_string_buffer(self.cap)
                continue
            return None if n < 0 else ctypes.string_at(self.buf, n)

    def __del__(self):
        if getattr(self, "handle", None):
            self.lib.tj_free(self.handle)
            self.handle = None
