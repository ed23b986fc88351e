"""The compiled C world (runtimes/c/include/m2c_world.h) driven from Python
through ctypes, with the methods of the pure-Python reference's World
(runtimes/python/max2code_rt/sim/, docs/engine-api.md): a Python program
runs the engine at C speed and can switch to the reference by changing one
argument of max2code.sim.live.open_world.

Why ctypes and not cffi: the library is ours and already built (one
libm2c_world.so per scene build, max2code/sim/simulate.py world_library),
its interface is a dozen plain C functions over doubles, ints and two small
structs, so ctypes declares it in a few lines with nothing to compile and no
dependency; cffi's API mode would add a C compiler step at import time and
its ABI mode is ctypes by another name.  The price is per call (about a
microsecond), which the game pays a few thousand times a second at most.

Contacts come back as the reference's own Contact objects, states as the
same 6-tuples, errors as the same SimError, so results of the two engines
compare with ==.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import functools
import operator
import os
import weakref

from max2code_rt.sim import Contact, SimError


class _Contact(ctypes.Structure):
    _fields_ = [("t", ctypes.c_double), ("a", ctypes.c_int), ("b", ctypes.c_int), ("feature", ctypes.c_int),
                ("i", ctypes.c_int), ("j", ctypes.c_int), ("px", ctypes.c_double), ("py", ctypes.c_double),
                ("nx", ctypes.c_double), ("ny", ctypes.c_double), ("impulse", ctypes.c_double),
                ("support", ctypes.c_int)]


class _State(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double), ("y", ctypes.c_double), ("vx", ctypes.c_double), ("vy", ctypes.c_double),
                ("angle", ctypes.c_double), ("omega", ctypes.c_double)]


class _Input(ctypes.Structure):
    _fields_ = [("t", ctypes.c_double), ("body", ctypes.c_int), ("mode", ctypes.c_int), ("x", ctypes.c_double),
                ("y", ctypes.c_double)]


_CONTACT_FN = ctypes.CFUNCTYPE(None, ctypes.POINTER(_Contact), ctypes.c_void_p)
_P = ctypes.c_void_p
_D = ctypes.c_double
_I = ctypes.c_int
# name: (result, arguments), exactly as m2c_world.h declares them
_SIGNATURES = {
    "m2c_world_new": (_P, [ctypes.c_char_p, _P]),
    "m2c_world_last_error": (ctypes.c_char_p, []),
    "m2c_world_free": (None, [_P]),
    "m2c_world_time": (_D, [_P]),
    "m2c_world_body_count": (_I, [_P]),
    "m2c_world_end_time": (_D, [_P]),
    "m2c_world_advance": (_I, [_P, _D, _CONTACT_FN, _P]),
    "m2c_world_next_event_time": (_D, [_P]),
    "m2c_world_state": (_I, [_P, _I, _D, ctypes.POINTER(_State)]),
    "m2c_world_states": (_I, [_P, _D, ctypes.POINTER(ctypes.c_double), _I]),
    "m2c_world_finish": (_I, [_P, _CONTACT_FN, _P]),
    "m2c_world_set_velocity": (_I, [_P, _I, _D, _D]),
    "m2c_world_add_velocity": (_I, [_P, _I, _D, _D]),
    "m2c_world_apply_impulse": (_I, [_P, _I, _D, _D]),
    "m2c_world_teleport": (_I, [_P, _I, _D, _D]),
    "m2c_world_remove_body": (_I, [_P, _I]),
    "m2c_world_add_body": (_I, [_P, ctypes.c_char_p]),
    "m2c_world_input_count": (_I, [_P]),
    "m2c_world_input": (_I, [_P, _I, ctypes.POINTER(_Input)]),
    "m2c_world_added": (ctypes.c_longlong, [_P]),
    "m2c_world_error": (ctypes.c_char_p, [_P]),
}
_libs: dict[str, ctypes.CDLL] = {}
_libc = None


# the range of the C API's int parameters (body indices)


def _fmt(x: float) -> str:
    return "%.17g" % x


def load_library(path: str) -> ctypes.CDLL:
    """The library at path with its functions declared (loaded once per path)."""
    path = os.fspath(path)
    lib = _libs.get(path)
    if lib is None:
        lib = ctypes.CDLL(path)
        for name, (res, args) in _SIGNATURES.items():
            fn = getattr(lib, name)
            fn.restype, fn.argtypes = res, args
        _libs[path] = lib
    return lib


def _c_library():
    global _libc
    if _libc is None:
        _libc = ctypes.CDLL(ctypes.util.find_library("c"))
        _libc.tmpfile.restype, _libc.tmpfile.argtypes = _P, []
        _libc.fflush.restype, _libc.fflush.argtypes = _I, [_P]
        _libc.fclose.restype, _libc.fclose.argtypes = _I, [_P]
        _libc.fileno.restype, _libc.fileno.argtypes = _I, [_P]
    return _libc


class _Handles:
    """What a CWorld owns in C: the world, its trace file, and what the trace
    goes to.  The CWorld's finalizer frees them through this object (it
    never refers to the CWorld), so a world dropped without close() frees
    them when it is collected."""
    __slots__ = ("lib", "w", "file", "out", "sent", "contacts", "error")

    def __init__(self, lib, out):
        self.lib, self.w, self.file, self.out, self.sent = lib, None, None, out, 0
        self.contacts: list[Contact] = []
        self.error: BaseException | None = None


def _collect(h: _Handles, c, _user) -> None:
    """The contact callback (bound to the handles, not the world: no cycle)."""
    try:
        k = c.contents
        h.contacts.append(Contact(k.t, k.a, k.b, k.feature, k.i, k.j, k.px, k.py, k.nx, k.ny, k.impulse,
                                  k.support != 0))
    except BaseException as exc:       # never let an exception cross the C frames
        h.error = exc


def _pass_trace(h: _Handles) -> None:
    """Hand the trace bytes written since the last call to out.write."""
    if h.file is None:
        return
    libc = _c_library()
    libc.fflush(h.file)
    fd = libc.fileno(h.file)
    while True:
        chunk = os.pread(fd, 1 << 20, h.sent)
        if not chunk:
            break
        h.sent += len(chunk)
        h.out.write(chunk.decode("ascii"))


def _release(h: _Handles) -> None:
    """Free the world (its last trace bytes passed on), then close the trace
    file; again, nothing happens."""
    try:
        if h.w is not None:
            w, h.w = h.w, None
            h.lib.m2c_world_free(w)      # writes out what the world still buffers
            _pass_trace(h)
    finally:
        if h.file is not None:
            f, h.file = h.file, None
            _c_library().fclose(f)


def _release_quietly(h: _Handles) -> None:
    """_release for the finalizer: a sink that fails then has no one to tell."""
    try:
        _release(h)
    except Exception:       # noqa: BLE001
        pass


INT_MIN, INT_MAX = -2 ** 31, 2 ** 31 - 1        # the C parameters' int


class CWorld:
    """A live world in C.  `out`: None (no trace) or an object with write(str),
    as the reference's World takes: the C world writes its flat trace to a
    temporary file whose new bytes are passed on after every call that may
    write (advance, the inputs, finish) and at close() (the C world buffers
    its trace: the last bytes come when it is freed).  A world dropped
    without close() is freed when it is collected (its trace passed on as
    at close()); close() again does nothing."""

    def __init__(self, library: str, scene_text: str, out=None):
        self._lib = load_library(library)
        self._h = h = _Handles(self._lib, out)
        self._finalizer = weakref.finalize(self, _release_quietly, h)
        self._states_buf = None
        self._finished = False
        if out is not None:
            h.file = _c_library().tmpfile()
            if not h.file:
                self._finalizer()
                raise OSError("tmpfile() failed: no trace file for the C world")
        w = self._lib.m2c_world_new(_ascii(scene_text, "the scene"), h.file)
        if not w:
            msg = (self._lib.m2c_world_last_error() or b"").decode("utf-8", "replace")
            self._finalizer()
            raise SimError(msg)
        h.w = w
        self._callback = _CONTACT_FN(functools.partial(_collect, h))

    # ---- plumbing ----------------------------------------------------------------
    def _handle(self):
        if self._h.w is None:
            raise SimError("the world is closed")
        return self._h.w

    def _fail(self) -> SimError:
        return SimError(self._lib.m2c_world_error(self._h.w).decode("utf-8", "replace"))

    def _pass_trace(self) -> None:
        _pass_trace(self._h)

    def _take(self) -> list[Contact]:
        h = self._h
        got, h.contacts = h.contacts, []
        if h.error is not None:
            err, h.error = h.error, None
            raise err
        return got

    def _body(self, body, missing: str = "no body {k} (the world has {n})") -> int:
        """body as the C int of an index of the world, or SimError (ctypes
        would pass 2^32 on as body 0) with the message `missing`."""
        try:
            k = operator.index(body)
        except TypeError:
            raise SimError(f"a body is an index (an int), not {type(body).__name__} {body!r}") from None
        n = self.body_count()
        if not 0 <= k < n:
            raise SimError(missing.format(k=k, n=n))
        return k

    def _live(self) -> None:
        """SimError once finish() has run: the trace has its final lines."""
        self._handle()
        if self._finished:
            raise SimError(FINISHED)

    def close(self) -> None:
        """Free the C world (its trace passed on first); the object is then
        unusable.  Again: nothing happens."""
        if self._finalizer.detach() is not None:
            _release(self._h)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ---- the live API (docs/engine-api.md) ------------------------------------------
    @property
    def time(self) -> float:
        """s: the world's current time."""
        return self._lib.m2c_world_time(self._handle())

    def body_count(self) -> int:
        return self._lib.m2c_world_body_count(self._handle())

    def end_time(self) -> float:
        """s: the scene's end time."""
        return self._lib.m2c_world_end_time(self._handle())

    def advance(self, t: float) -> list[Contact]:
        """Every event before t handled, the world's time moved to t; the contacts handled."""
        w = self._handle()
        rc = self._lib.m2c_world_advance(w, _real(t, "advance: t"), self._callback, None)
        self._pass_trace()
        if rc != 0:
            self._h.contacts = []
            raise self._fail()
        return self._take()

    def next_event_time(self) -> float:
        """s: the time of the next event that is due (inf when none)."""
        return self._lib.m2c_world_next_event_time(self._handle())

    def state(self, body: int, t: float) -> tuple[float, float, float, float, float, float]:
        """(px, py, vx, vy, angle, omega) of a body at t, from the world's time to the next event's."""
        w = self._handle()
        s = _State()
        if self._lib.m2c_world_state(w, self._body(body), _real(t, "state: t"), ctypes.byref(s)) != 0:
            raise self._fail()
        return s.x, s.y, s.vx, s.vy, s.angle, s.omega

    def states(self, t: float) -> list[tuple[float, float, float, float, float, float]]:
        """Every body's state at t (entry k: body k's, as state gives it), in
        one call into C: a frame that draws every body pays one crossing of
        ctypes instead of one per body."""
        w = self._handle()
        n = self._lib.m2c_world_body_count(w)
        buf = self._states_buf
        if buf is None or len(buf) < 6 * n:
            buf = self._states_buf = (ctypes.c_double * (6 * max(n, 1)))()
        if self._lib.m2c_world_states(w, _real(t, "states: t"), buf, n) != 0:
            raise self._fail()
        v = buf[:6 * n]
        return list(zip(v[0::6], v[1::6], v[2::6], v[3::6], v[4::6], v[5::6]))

    # ---- live inputs at the world's time (recorded in the world's input list) ----------
    def _input(self, fn, body, *args) -> int:
        self._live()
        k = self._body(body, "live input: body {k} does not exist")      # as the engines say it
        rc = fn(self._handle(), k, *args)
        self._pass_trace()
        if rc < 0:
            raise self._fail()
        return rc

    def set_velocity(self, body: int, vx: float, vy: float) -> None:
        self._input(self._lib.m2c_world_set_velocity, body, _real(vx, "vx"), _real(vy, "vy"))

    def add_velocity(self, body: int, dvx: float, dvy: float) -> None:
        self._live()
        self._input(self._lib.m2c_world_add_velocity, body, _real(dvx, "dvx"), _real(dvy, "dvy"))

    def apply_impulse(self, body: int, jx: float, jy: float) -> None:
        """An impulse (N s) through the centre: dv = J inv_mass."""
        self._live()
        self._input(self._lib.m2c_world_apply_impulse, body, _real(jx, "jx"), _real(jy, "jy"))

    def teleport(self, body: int, x: float, y: float) -> bool:
        """Move the body's centre to (x, y) now, keeping its velocity; False
        (the world unchanged, nothing recorded) when it would overlap another body there."""
        return self._input(self._lib.m2c_world_teleport, body, _real(x, "x"), _real(y, "y")) == 1

    def remove_body(self, body: int) -> None:
        """Take a body (movable or fixed) out of the world now (input MODE 4)."""
        self._input(self._lib.m2c_world_remove_body, body)

    def add_body(self, text: str) -> int:
        """A body from its flat lines (the state at the world's time) added now:
        its index, or -1 (the world unchanged) when it would overlap a body."""
        self._live()
        k = self._lib.m2c_world_add_body(self._handle(), _ascii(text, "add_body: the body's text"))
        self._pass_trace()
        if k == -2:
            raise self._fail()
        return k


    @property
    def added(self) -> int:
        """How many bodies add_body added (a recording refuses such a session)."""
        return self._lib.m2c_world_added(self._handle())

    def input_log(self) -> list[tuple[float, int, int, float, float]]:
        """(t, body, mode, x, y) of every input, the scene's own first, then
        the live ones in the order they were made (what a recording writes)."""
        w = self._handle()
        rec = _Input()
        out = []
        for k in range(self._lib.m2c_world_input_count(w)):
            if self._lib.m2c_world_input(w, k, ctypes.byref(rec)) != 0:
                raise SimError(f"the C world has no input {k}")
            out.append((rec.t, rec.body, rec.mode, rec.x, rec.y))
        return out

    def finish(self) -> list[Contact]:
        """The events at the end time, then the trace's final lines; the last
        contacts.  No input may follow (SimError)."""
        self._live()
        w = self._handle()
        rc = self._lib.m2c_world_finish(w, self._callback, None)
        self._finished = True
        self._pass_trace()
        if rc != 0:
            self._h.contacts = []
            raise self._fail()
        return self._take()


FINISHED = "live input: the world is finished"          # as the engines say it


def _real(x, what: str) -> float:
    """x as the C double, or SimError naming it (a string, an int beyond the doubles)."""
    try:
        return float(x)
    except (TypeError, ValueError, OverflowError):
        raise SimError(f"{what}: expected a number, got {x!r:.60}") from None


def _ascii(text, what: str) -> bytes:
    """text as the C string (ASCII, no NUL), or SimError naming it."""
    if not isinstance(text, str):
        raise SimError(f"{what}: expected a str, got {type(text).__name__}")
    if not text.isascii() or "\0" in text:
        raise SimError(f"{what}: the flat text is ASCII without NUL characters")
    return text.encode("ascii")


