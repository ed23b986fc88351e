"""The common case of `max2code simulate`'s scene read, checked and compiled
in C: runtimes/c/tools/m2c_scene_flat.c, built once into a shared library
under BUILD/scene-flat/ and called through ctypes, in this process (it
writes numbers with the interpreter's own repr, so its flat text is
max2code/sim/scene.py's byte for byte).

The case: circles without orbit and fixed polygons that do not turn, no
inputs (the gases of 10^4 and 10^5 disks of bench/simulate_cmd.py: for them
Python spent 2.5 s CPU reading, checking and compiling what the engine then
simulates in 0.8 s).  The C code reads the whole JSON text and the circles;
each polygon's own text is read here by scene.py's reader (they are few),
which also checks its magnitudes, gives its box for the C overlap checks and
writes its lines.  Anything else, and any fault or doubt, is "not mine":
read_scene returns None and the caller reads the scene in Python, which
gives the same bytes or the precise error; so does a machine without gcc."""
from __future__ import annotations

import ctypes
import json

from max2code.paths import RUNTIMES
from max2code.record import Record
from max2code.sim.ctool import CTool
from max2code.sim.scene import (COUNT_LIMIT, MAX_BODIES, Scene, SceneError, _body, _box, _check_body_magnitudes,
                                _Reader, body_lines, check_memory, covered_edges)

SOURCE = RUNTIMES / "c" / "tools" / "m2c_scene_flat.c"
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-ffp-contract=off", "-shared", "-fPIC"]
FACTS = 11          # the numbers sf_facts gives
_p, _long_p = ctypes.c_void_p, ctypes.POINTER(ctypes.c_long)
TOOL = CTool(SOURCE, FLAGS, "scene-flat", ctypes.PyDLL, [
    ("sf_new", _p, []), ("sf_free", None, [_p]),
    ("sf_parse", ctypes.c_int, [_p, ctypes.c_char_p, ctypes.c_long]),
    ("sf_polygons", ctypes.c_long, [_p]),
    ("sf_polygon", None, [_p, ctypes.c_long, _long_p, _long_p, _long_p]),
    ("sf_facts", None, [_p, ctypes.POINTER(ctypes.c_double)]),
    ("sf_names", _p, [_p, _long_p]),
    ("sf_compile", ctypes.c_int, [_p, ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_ubyte)]),
    ("sf_text", _p, [_p, _long_p]),
    ("sf_part", ctypes.c_long, [_p, ctypes.c_long, ctypes.c_long]),
    ("sf_number", ctypes.c_int, [ctypes.c_char_p, ctypes.c_long, ctypes.POINTER(ctypes.c_double)]),
    ("sf_repr", ctypes.c_long, [ctypes.c_double, ctypes.c_char_p, ctypes.c_long])])


PART = 4096        # bodies' lines made at a time by parts()


class FlatScene(Record):
    """A scene the C reader took: what `max2code simulate` needs of it, and
    its flat scene, made in pieces by parts() (a simulator reads one while
    the next is made) from the C reader's state, which it owns."""
    _fields = ("path", "end_time", "taylor_order", "effects", "max_events", "json_names", "names_text", "most", "head",
               "polygon_lines", "_lib", "_handle")

    def __init__(self, path: str, end_time: float, taylor_order: int, effects: tuple[str, ...], max_events: int,
                 json_names: list[str], names_text: bytes, most: int, head: bytes, polygon_lines: dict[int, bytes],
                 _lib: ctypes.PyDLL, _handle: int):
        self.path, self.end_time, self.taylor_order = path, end_time, taylor_order
        self.effects, self.max_events = effects, max_events
        self.json_names = json_names    # each body's name as JSON text, in index order
        self.names_text = names_text    # the same, each followed by a newline
        self.most = most                # the largest body, input or vertex index a trace line may name
        self.head = head                # the flat scene up to the bodies' lines
        self.polygon_lines = polygon_lines      # by body index
        self._lib, self._handle = _lib, _handle

    def parts(self):
        """The flat scene (compile_scene's text) in pieces of whole lines
        (not after release())."""
        if not self._handle:
            raise ValueError("the flat scene was released")
        yield self.head
        n, k = len(self.json_names), 0
        while k < n:
            lines = self.polygon_lines.get(k)
            if lines is not None:
                yield lines
                k += 1
                continue
            end = self._lib.sf_part(self._handle, k, k + PART)
            if end < 0:
                raise MemoryError("m2c_scene_flat: sf_part")
            size = ctypes.c_long()
            yield ctypes.string_at(self._lib.sf_text(self._handle, ctypes.byref(size)), size.value)
            k = end
        yield b"inputs 0\nend\n"

    @property
    def flat(self) -> bytes:
        return b"".join(self.parts())

    def release(self) -> None:
        """Free the C reader's state (the bodies' arrays: 17 MB at 10^5 bodies) once the flat scene is written."""
        if getattr(self, "_handle", None):
            self._lib.sf_free(self._handle)
            self._handle = None

    __del__ = release


def library() -> ctypes.PyDLL | None:
    """The loaded library (a PyDLL: its calls keep the interpreter's lock, which
    the interpreter's number conversions it calls need), or None when it
    cannot be built or loaded (why_not() says why)."""
    return TOOL.library()


def why_not() -> str:
    """Why library() returned None (empty when it did not)."""
    return TOOL.why_not()


def read_scene(path: str) -> FlatScene | None:
    """The scene at `path` read, checked and compiled, when it is the C
    reader's case; else None (then scene.load_scene reads it, and reports
    any fault)."""
    lib = library()
    if lib is None:
        return None
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError:
        return None
    h = lib.sf_new()
    if not h:
        return None
    scene = None
    try:
        scene = _read(lib, h, path, data)
        return scene
    finally:
        if scene is None:
            lib.sf_free(h)          # else the scene frees it


def _read(lib, h, path: str, data: bytes) -> FlatScene | None:
    if lib.sf_parse(h, data, len(data)) != 0:
        return None
    facts = (ctypes.c_double * FACTS)()
    lib.sf_facts(h, facts)
    end, fps, gx, gy, tol, rest, order, max_same, max_events, n, accelerates = facts
    if n > MAX_BODIES or max_same >= COUNT_LIMIT or max_events >= COUNT_LIMIT:
        return None                     # Python names the fault
    rd = _Reader(path)
    index, start, stop = ctypes.c_long(), ctypes.c_long(), ctypes.c_long()
    at: list[int] = []
    polygons = []
    try:
        for j in range(lib.sf_polygons(h)):
            lib.sf_polygon(h, j, index, start, stop)
            k = index.value
            b = _body(rd, json.loads(data[start.value:stop.value]), k, (gx, gy), {})
            if not b.fixed or b.angular_velocity != 0.0:
                return None             # a polygon that turns or may: the window angles are Python's
            _check_body_magnitudes(rd, end, k, b, 0.0, 0.0, tol)
            at.append(k)
            polygons.append(b)
        check_memory(path, int(n), sum(len(b.vertices) for b in polygons), 0)
    except SceneError:
        return None                     # Python reads the whole scene and reports its first fault
    given = (ctypes.c_double * (7 * len(polygons) + 1))()
    for j, b in enumerate(polygons):
        given[7 * j:7 * j + 7] = [b.bound, *b.position, *_box(b)]
    large = (ctypes.c_ubyte * (len(polygons) + 1))()
    if lib.sf_compile(h, given, large) != 0:
        return None
    size = ctypes.c_long()
    head = ctypes.string_at(lib.sf_text(h, ctypes.byref(size)), size.value)
    names_text = ctypes.string_at(lib.sf_names(h, ctypes.byref(size)), size.value)
    names = names_text.decode("ascii").split("\n")
    names.pop()
    # the polygons' lines
    own = Scene(path, path, end, fps, (gx, gy), tol, rest, int(order), int(max_same), polygons, [], int(max_events))
    covered = covered_edges(own)        # (only polygons can cover, or be covered)
    polygon_lines = {}
    for j, b in enumerate(polygons):
        covers = covered.get(j)
        lines = body_lines(b, bool(large[j]), 0.0, [at[q] if q >= 0 else -1 for q in covers] if covers else None)
        polygon_lines[at[j]] = "".join(x + "\n" for x in lines).encode("ascii")
    effects = ("acceleration",) if accelerates or any(b.acceleration != (0.0, 0.0) for b in polygons) else ()
    most = max(int(n), max((len(b.vertices) for b in polygons), default=0))
    return FlatScene(path, end, int(order), effects, int(max_events), names, names_text, most, head, polygon_lines,
                     lib, h)
