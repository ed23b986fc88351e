"""Scenes: read and check a JSON scene (docs/simulator.md), and compile it
to the flat text every runtime's simulator reads.

Everything a runtime would otherwise compute with functions that might round
differently between languages (atan2, hypot, the polygon's centroid and
moment of inertia, the grid) is computed here once, in Python, and handed
over as exact doubles.
"""
from __future__ import annotations

import contextlib
import functools
import gc
import json
import math
import operator
import os
from itertools import accumulate, compress, repeat

from max2code.errors import Max2CodeError
from max2code.facts import MAX_DEGREE
from max2code.record import FrozenRecord, Record
from max2code.textio import InputError, read_text

SHAPES = ("circle", "polygon")
DEFAULT_MAX_EVENTS = 10_000_000      # events (collisions, inputs, frames) per run
DEFAULT_MAX_FRAME_RATE = 1000.0      # frames per simulated second
# Lengths (and speeds times the end time) up to LENGTH_MAX keep their squares
# and the products in the contact polynomials finite; sizes down to
# LENGTH_MIN keep their squares from underflowing to zero.
LENGTH_MAX = 1e150
LENGTH_MIN = 1e-150
# How big a scene may be (docs/simulator.md, "Limits"), checked before its lists are built.
MAX_BODIES = 1_000_000
MAX_VERTICES = 1024             # per polygon
MAX_INPUTS = 10_000_000
MAX_NESTING = 256               # brackets inside brackets in the JSON text (a scene needs 5; the C reader,
                                # scene_c.py, takes at most 201, so it needs no check of its own)
COUNT_LIMIT = 10 ** 18          # max_events and max_events_at_one_time stay below: the flat scene's integers
                                # have at most 18 digits
# The C engine's memory for a scene, measured as its peak resident size
# (gases of 5*10^4 to 2*10^5 disks, 200 and 400 polygons of 1024 vertices,
# 2*10^5 and 4*10^5 inputs), rounded up: the estimate is refused past
# MAX2CODE_MAX_MEMORY bytes (default DEFAULT_MAX_MEMORY).
BYTES_PER_BODY, BYTES_PER_VERTEX, BYTES_PER_INPUT, BYTES_BASE = 450, 320, 140, 16_000_000
DEFAULT_MAX_MEMORY = 1_000_000_000
MEMORY_ENV = "MAX2CODE_MAX_MEMORY"
SCENE_KEYS = {"name": "a title", "end_time": "seconds simulated", "frame_rate": "frames per second (0: none)",
              "gravity": "[x, y] acceleration of every movable body (m/s^2)",
              "tolerance": "distance tolerance (m)", "rest_speed": "smallest separation speed of a contact (m/s)",
              "taylor_order": "Taylor order of the turns' sin and cos", "bodies": "the bodies",
              "inputs": "scripted inputs (velocity, impulse, teleport)", "max_events_at_one_time": "guard against a stuck scene",
              "max_events": "events (collisions, inputs, frames) a run may write",
              "max_frame_rate": "largest frame_rate accepted", "comment": "free text"}
BODY_KEYS = {"name", "shape", "radius", "vertices", "mass", "fixed", "position", "velocity", "acceleration",
             "angle", "angular_velocity", "orbit", "restitution", "friction", "comment"}
ORBIT_KEYS = {"radius", "angle"}
INPUT_KINDS = ("set_velocity", "add_velocity", "impulse", "teleport", "remove")     # the flat MODE is the index
SET_VELOCITY, ADD_VELOCITY, IMPULSE, TELEPORT, REMOVE = range(5)
INPUT_KEYS = {"time", "body", *INPUT_KINDS}


class SceneError(Max2CodeError):
    """A bad scene: the message names the file and the field."""


class Body(Record):
    _fields = ("name", "polygon", "fixed", "mass", "inertia", "restitution", "position", "velocity", "acceleration",
               "angle", "angular_velocity", "radius", "orbit_radius", "orbit_angle", "vertices", "friction")

    def __init__(self, name: str, polygon: bool, fixed: bool, mass: float, inertia: float, restitution: float,
                 position: tuple[float, float], velocity: tuple[float, float], acceleration: tuple[float, float],
                 angle: float, angular_velocity: float, radius: float = 0.0, orbit_radius: float = 0.0,
                 orbit_angle: float = 0.0, vertices: list[tuple[float, float]] | None = None, friction: float = 0.0):
        self.name, self.polygon, self.fixed = name, polygon, fixed
        self.mass = mass            # inf when fixed
        self.inertia = inertia      # about the centre of mass; inf when fixed; 0 for circles (never turned by contact)
        self.restitution = restitution
        self.position, self.velocity = position, velocity
        self.acceleration = acceleration    # gravity included for movable bodies
        self.angle, self.angular_velocity = angle, angular_velocity
        self.radius, self.orbit_radius, self.orbit_angle = radius, orbit_radius, orbit_angle
        self.vertices = [] if vertices is None else vertices    # about the centre of mass, counter-clockwise
        self.friction = friction    # Coulomb coefficient; a contact uses the product of both bodies' values

    @functools.cached_property
    def bound(self) -> float:
        """Radius of a circle about the centre of rotation holding the whole body
        (computed once: read it only after the vertices or radius are set)."""
        if self.polygon:
            return max(math.hypot(x, y) for x, y in self.vertices)
        return self.orbit_radius + self.radius

    @property
    def turns(self) -> bool:
        return self.angular_velocity != 0.0 and (self.polygon or self.orbit_radius > 0.0)

    @property
    def may_turn(self) -> bool:
        """Turns now, or may be set turning by a contact off its centre (a movable polygon)."""
        return self.turns or (self.polygon and not self.fixed)


class Input(Record):
    _fields = ("time", "body", "mode", "velocity")

    def __init__(self, time: float, body: int, mode: int, velocity: tuple[float, float]):
        self.time, self.body = time, body
        self.mode = mode    # index in INPUT_KINDS: set/add velocity (m/s), impulse (N s), teleport (the new centre, m)
        self.velocity = velocity    # the mode's vector (named for the first two)


class Scene(Record):
    _fields = ("path", "name", "end_time", "frame_rate", "gravity", "tolerance", "rest_speed", "taylor_order",
               "max_same", "bodies", "inputs", "max_events")

    def __init__(self, path: str, name: str, end_time: float, frame_rate: float, gravity: tuple[float, float],
                 tolerance: float, rest_speed: float, taylor_order: int, max_same: int, bodies: list[Body],
                 inputs: list[Input], max_events: int = DEFAULT_MAX_EVENTS):
        self.path, self.name, self.end_time, self.frame_rate = path, name, end_time, frame_rate
        self.gravity, self.tolerance, self.rest_speed = gravity, tolerance, rest_speed
        self.taylor_order, self.max_same = taylor_order, max_same
        self.bodies, self.inputs, self.max_events = bodies, inputs, max_events

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (dataclasses.replace)."""
        values = dict(zip(self._fields, self._values()))
        values.update(changes)
        return Scene(**values)

    @property
    def effects(self) -> tuple[str, ...]:
        """The world effects the scene uses (variants.WORLD_EFFECTS): a movable
        polygon counts as turning, since a contact off its centre sets it spinning."""
        out = []
        if any(map(operator.ne, map(_acceleration, self.bodies), repeat((0.0, 0.0)))):
            out.append("acceleration")
        if turning(self.bodies):
            out.append("orbit")
        return tuple(out)


# a field of many bodies at once: map(_bound, bodies)
_acceleration, _bound, _fixed = (operator.attrgetter("acceleration"), operator.attrgetter("bound"),
                                 operator.attrgetter("fixed"))
_is_polygon, _position, _radius = (operator.attrgetter("polygon"), operator.attrgetter("position"),
                                operator.attrgetter("radius"))
_spin = operator.attrgetter("angular_velocity")


def _any_spin(bodies: list[Body]) -> bool:
    return any(map(operator.ne, map(_spin, bodies), repeat(0.0)))


def turning(bodies: list[Body]) -> list[Body]:
    """The bodies that may turn (Body.may_turn), in order.  When none spins,
    only the movable polygons may: the circles (a gas's many) need no look."""
    if _any_spin(bodies):
        return [b for b in bodies if b.may_turn]
    return [b for b in compress(bodies, map(_is_polygon, bodies)) if not b.fixed]


# ---------------------------------------------------------------- reading
class _Reader:
    def __init__(self, path: str):
        self.path = path

    def fail(self, where: str, msg: str):
        raise SceneError(f"{self.path}: error: {where}: {msg}")

    def keys(self, obj, allowed, where: str, required=()):
        if not isinstance(obj, dict):
            self.fail(where, f"expected an object, got {type(obj).__name__}")
        for k in obj:
            if k not in allowed:
                self.fail(f"{where}.{k}" if where else k, f"unknown key (expected one of: {', '.join(sorted(allowed))})")
        for k in required:
            if k not in obj:
                self.fail(where or "scene", f"missing required key '{k}'")

    def number(self, obj, key, where, default=None, *, positive=False, nonneg=False):
        name = f"{where}.{key}" if where else key
        if key not in obj:
            if default is None:
                self.fail(where or "scene", f"missing required key '{key}'")
            return float(default)
        v = obj[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(name, f"expected a number, got {json.dumps(v)}")
        v = self.real(v, name)
        if not math.isfinite(v):
            self.fail(name, f"must be finite, got {v}")
        if positive and not v > 0.0:
            self.fail(name, f"must be positive, got {v}")
        if nonneg and v < 0.0:
            self.fail(name, f"must not be negative, got {v}")
        return v

    def vec(self, obj, key, where, default=(0.0, 0.0)):
        name = f"{where}.{key}" if where else key
        if key not in obj:
            if default is None:
                self.fail(where, f"missing required key '{key}'")
            return default
        v = obj[key]
        if not (isinstance(v, list) and len(v) == 2):
            self.fail(name, f"expected [x, y], got {json.dumps(v)}")
        out = []
        for i, x in enumerate(v):
            if isinstance(x, bool) or not isinstance(x, (int, float)):
                self.fail(f"{name}[{i}]", f"expected a number, got {json.dumps(x)}")
            x = self.real(x, f"{name}[{i}]")
            if not math.isfinite(x):
                self.fail(f"{name}[{i}]", f"must be finite, got {x}")
            out.append(x)
        return (out[0], out[1])

    def real(self, v, name: str) -> float:
        """A JSON number as a double; an integer beyond the doubles' range
        (JSON allows 10^400 written out) is refused, naming the field."""
        try:
            return float(v)
        except OverflowError:
            self.fail(name, f"must be finite, got an integer of {len(str(abs(v)))} digits (beyond a double's range)")


def _polygon(rd: _Reader, raw, where: str):
    """Counter-clockwise vertices about the centroid, the centroid, area and
    the second moment of area about the centroid."""
    if not isinstance(raw, list) or len(raw) < 3:
        rd.fail(f"{where}.vertices", "a polygon needs a list of at least 3 [x, y] vertices")
    if len(raw) > MAX_VERTICES:
        rd.fail(f"{where}.vertices", f"{len(raw):,} vertices is more than {MAX_VERTICES:,}, the most a polygon may have")
    pts = []
    for i, p in enumerate(raw):
        pts.append(rd.vec({"vertices[%d]" % i: p}, "vertices[%d]" % i, where, None))
    area2 = sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1] for i in range(len(pts)))
    if area2 == 0.0:
        rd.fail(f"{where}.vertices", "the polygon has zero area")
    if area2 < 0.0:
        pts.reverse()
        area2 = -area2
    n = len(pts)
    scale = max(math.hypot(x, y) for x, y in pts) or 1.0
    for i in range(n):
        (x0, y0), (x1, y1), (x2, y2) = pts[i - 1], pts[i], pts[(i + 1) % n]
        cross = (x1 - x0) * (y2 - y1) - (y1 - y0) * (x2 - x1)
        if cross <= 1e-12 * scale * scale:
            rd.fail(f"{where}.vertices", f"the polygon is not strictly convex at vertex {i} ({x1}, {y1})")
    # Left turns alone allow a star that winds round more than once (a pentagram: twice); a convex polygon's
    # edges go up once and down once, so the signs of their y components change exactly twice round it.
    rising = [y1 > y0 for (_, y0), (_, y1) in zip(pts, pts[1:] + pts[:1]) if y1 != y0]
    turns = sum(map(operator.ne, rising, rising[-1:] + rising[:-1])) // 2
    if turns != 1:
        rd.fail(f"{where}.vertices", f"the polygon is not convex: its edges wind {turns} times around it "
                                     "(it crosses itself)")
    cx = cy = 0.0
    for i in range(n):
        (x0, y0), (x1, y1) = pts[i], pts[(i + 1) % n]
        c = x0 * y1 - x1 * y0
        cx += (x0 + x1) * c
        cy += (y0 + y1) * c
    cx /= 3.0 * area2
    cy /= 3.0 * area2
    local = [(x - cx, y - cy) for x, y in pts]
    second = 0.0
    for i in range(n):
        (x0, y0), (x1, y1) = local[i], local[(i + 1) % n]
        c = x0 * y1 - x1 * y0
        second += c * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1)
    second /= 12.0            # integral of r^2 over the area
    return local, (cx, cy), area2 / 2.0, second


def _body(rd: _Reader, b, k: int, gravity: tuple[float, float], names: dict[str, int]) -> Body:
    """bodies[k], checked field by field: the first fault is reported."""
    where = f"bodies[{k}]"
    rd.keys(b, BODY_KEYS, where, required=("shape", "position"))
    name = b.get("name", f"body{k}")
    if not isinstance(name, str) or not name:
        rd.fail(f"{where}.name", "expected a non-empty string")
    if name in names:
        rd.fail(f"{where}.name", f"'{name}' is already the name of bodies[{names[name]}]")
    names[name] = k
    where = f"bodies[{k}] ({name})"
    shape = b["shape"]
    if shape not in SHAPES:
        rd.fail(f"{where}.shape", f"expected one of {', '.join(SHAPES)}, got {json.dumps(shape)}")
    fixed = b.get("fixed", False)
    if not isinstance(fixed, bool):
        rd.fail(f"{where}.fixed", "expected true or false")
    if fixed:
        if "mass" in b:
            rd.fail(f"{where}.mass", "a fixed body has no mass (it is not moved by contacts)")
        mass = math.inf
    else:
        mass = rd.number(b, "mass", where, positive=True)
    restitution = rd.number(b, "restitution", where, 1.0, nonneg=True)
    if restitution > 1.0:
        rd.fail(f"{where}.restitution", f"must be at most 1, got {restitution}")
    friction = rd.number(b, "friction", where, 0.0, nonneg=True)
    pos = rd.vec(b, "position", where, None)
    vel = rd.vec(b, "velocity", where)
    acc = rd.vec(b, "acceleration", where)
    if not fixed:
        acc = (acc[0] + gravity[0], acc[1] + gravity[1])
    angle = rd.number(b, "angle", where, 0.0)
    omega = rd.number(b, "angular_velocity", where, 0.0)
    body = Body(name, shape == "polygon", fixed, mass, math.inf if fixed else 0.0, restitution,
                pos, vel, acc, angle, omega)
    body.friction = friction
    if shape == "circle":
        if "vertices" in b:
            rd.fail(f"{where}.vertices", "a circle has no vertices")
        body.radius = rd.number(b, "radius", where, positive=True)
        if "orbit" in b:
            rd.keys(b["orbit"], ORBIT_KEYS, f"{where}.orbit", required=("radius",))
            body.orbit_radius = rd.number(b["orbit"], "radius", f"{where}.orbit", positive=True)
            body.orbit_angle = rd.number(b["orbit"], "angle", f"{where}.orbit", 0.0)
            if not fixed:
                rd.fail(f"{where}.orbit", "an orbiting circle must be fixed (its orbit is prescribed motion)")
        elif omega != 0.0:
            rd.fail(f"{where}.angular_velocity", "a circle turns only about an orbit's centre: give 'orbit' or leave it out")
    else:
        if "radius" in b or "orbit" in b:
            rd.fail(f"{where}.{'radius' if 'radius' in b else 'orbit'}", "a polygon has vertices, not a radius or orbit")
        if "vertices" not in b:
            rd.fail(where, "missing required key 'vertices'")
        local, (cx, cy), area, second = _polygon(rd, b["vertices"], where)
        # the centre of mass becomes the body's position
        ca, sa = math.cos(angle), math.sin(angle)
        body.position = (pos[0] + ca * cx - sa * cy, pos[1] + sa * cx + ca * cy)
        body.vertices = local
        if not fixed:
            body.inertia = mass * second / area
    return body


_CIRCLE_KEYS = frozenset(BODY_KEYS - {"vertices", "orbit"})
_BIG_INT = 2 ** 62
_ABSENT = object()          # a key left out (JSON null is a value, and a wrong one)
_ORIGIN = [0.0, 0.0]        # a pair left out
_first, _second = operator.itemgetter(0), operator.itemgetter(1)


def _real(v, default):
    """A finite JSON number as a float (the default when absent), or None
    when the careful path must look at it."""
    if v is _ABSENT:
        return default
    t = type(v)
    if t is float:
        return v if math.isfinite(v) else None
    if t is int and -_BIG_INT < v < _BIG_INT:
        return float(v)
    return None


def _pair(v, default):
    """A JSON [x, y] of finite numbers as floats (the default when absent),
    or None when the careful path must look at it."""
    if v is _ABSENT:
        return default
    if type(v) is not list or len(v) != 2:
        return None
    x, y = _real(v[0], None), _real(v[1], None)
    if x is None or y is None:
        return None
    return (x, y)


def _circle(b, k: int, gravity: tuple[float, float], names: dict[str, int]) -> Body | None:
    """bodies[k] when it is a plain circle every field of which is well formed
    (the common case: one pass, no error bookkeeping); None for anything else
    (polygons, orbits, any doubtful field), which _body then reads field by
    field and reports.  What this accepts, _body accepts with the same values."""
    if type(b) is not dict or b.get("shape") != "circle" or not b.keys() <= _CIRCLE_KEYS:
        return None
    name = b.get("name", _ABSENT)
    if name is _ABSENT:
        name = f"body{k}"
    elif type(name) is not str or not name:
        return None
    if name in names:
        return None
    fixed = b.get("fixed", False)
    if fixed is True:
        if "mass" in b:
            return None
        mass = math.inf
    elif fixed is False:
        mass = _real(b.get("mass", _ABSENT), None)
        if mass is None or not mass > 0.0:
            return None
    else:
        return None
    g = b.get
    # all numbers floats (JSON with a '.' or an exponent): one type chain and one sum tell
    restitution, friction, radius = g("restitution", 1.0), g("friction", 0.0), g("radius")
    angle, omega, pos, vel = g("angle", 0.0), g("angular_velocity", 0.0), g("position"), g("velocity", _ORIGIN)
    acc = g("acceleration", _ORIGIN)
    if type(pos) is type(vel) is type(acc) is list and len(pos) == len(vel) == len(acc) == 2:
        (px, py), (vx, vy), (ax, ay) = pos, vel, acc
        m = 1.0 if fixed else mass
        if (type(restitution) is type(friction) is type(radius) is type(angle) is type(omega) is type(px) is type(py)
                is type(vx) is type(vy) is type(ax) is type(ay) is float
                # a sum of finite numbers may still overflow: then the slower checks below decide
                and math.isfinite(m + restitution + friction + radius + angle + omega + px + py + vx + vy + ax + ay)):
            if not (0.0 <= restitution <= 1.0 and friction >= 0.0 and radius > 0.0 and omega == 0.0):
                return None
            if not fixed:
                ax, ay = ax + gravity[0], ay + gravity[1]
            names[name] = k
            body = Body(name, False, fixed, mass, math.inf if fixed else 0.0, restitution, (px, py), (vx, vy),
                        (ax, ay), angle, omega, radius=radius, friction=friction)
            body.__dict__["bound"] = 0.0 + radius      # Body.bound of a circle without orbit, cached
            return body
    restitution = _real(g("restitution", _ABSENT), 1.0)
    friction = _real(g("friction", _ABSENT), 0.0)
    radius = _real(g("radius", _ABSENT), None)
    angle = _real(g("angle", _ABSENT), 0.0)
    omega = _real(g("angular_velocity", _ABSENT), 0.0)
    pos = _pair(g("position", _ABSENT), None)
    vel = _pair(g("velocity", _ABSENT), (0.0, 0.0))
    acc = _pair(g("acceleration", _ABSENT), (0.0, 0.0))
    if (restitution is None or not 0.0 <= restitution <= 1.0 or friction is None or not friction >= 0.0
            or radius is None or not radius > 0.0 or angle is None or omega is None or omega != 0.0
            or pos is None or vel is None or acc is None):
        return None
    if not fixed:
        acc = (acc[0] + gravity[0], acc[1] + gravity[1])
    names[name] = k
    return Body(name, False, fixed, mass, math.inf if fixed else 0.0, restitution, pos, vel, acc, angle, omega,
                radius=radius, friction=friction)


_BRACKETS = bytes(sorted(set(range(256)) - set(b'"[]{}')))     # translate's delete: all but quotes and brackets
_PARENS = bytes.maketrans(b"[{]}", b"(())")
_STEP = [0] * 256
_STEP[40], _STEP[41] = 1, -1        # '(' and ')'


def nesting(data: bytes, limit: int = MAX_NESTING) -> int:
    """How deep the brackets of a JSON text nest outside its strings, exactly
    up to limit + 1 (a deeper text gives limit + 1), made without parsing:
    the decoders recurse once per level (orjson crashed at 10^6), so the
    reader refuses a deep text before it decodes it.  Escapes go first
    (an escaped backslash, then an escaped quote), then everything but
    quotes and brackets; two quotes side by side close one string and open
    the next, or make an empty one: either way nothing between them was
    outside a string, so they go too, and only a text with brackets inside
    its strings is split at its quotes.  Then every innermost pair of
    brackets goes, one level a pass; a text whose brackets do not pair up
    (not JSON: the decoder says where) is measured by its running count."""
    if b"\\" in data:
        data = data.replace(b"\\\\", b"").replace(b'\\"', b"")
    s = data.translate(None, _BRACKETS).replace(b'""', b"")
    if b'"' in s:
        s = b"".join(s.split(b'"')[::2])
    s = s.translate(_PARENS)
    depth = 0
    while s and depth <= limit:
        if b"(" * (limit + 1 - depth) in s:
            return limit + 1
        shorter = s.replace(b"()", b"")
        if len(shorter) == len(s):
            return depth + max(0, max(accumulate(map(_STEP.__getitem__, s))))
        s = shorter
        depth += 1
    return depth


FAST_JSON_BYTES = 1 << 20          # scenes at least this long are decoded by orjson, when it is installed
_DIGITS = bytes.maketrans(b"123456789", b"000000000")
_LONG = b"0" * 19       # orjson keeps ints from -2^63 to 2^64 - 1: 19 digits and more may be beyond


def _decode(text: str):
    """json.loads of the scene.  A big scene (FAST_JSON_BYTES) goes through
    orjson when it is installed (about 2x faster; the same values: it reads
    doubles correctly rounded, keeps the last of repeated keys, and refuses
    what json would read otherwise: NaN, Infinity, numbers beyond the
    doubles, lone surrogates, deep nesting), unless it holds a whole number
    of 19 digits or more, which orjson may make a float where json keeps an
    int (found as a run of 19 digits that does not follow a '.'); on
    anything orjson refuses, json decodes and reports the fault."""
    if len(text) >= FAST_JSON_BYTES and _orjson() is not None:
        data = text.encode("utf-8", "surrogatepass")
        runs = data.translate(_DIGITS)
        at = runs.find(_LONG)
        while at > 0 and runs[at - 1] == 46:        # 46: '.': a fraction's digits; on to the run's end
            end = at + len(_LONG)
            while end < len(runs) and runs[end] == 48:
                end += 1
            at = runs.find(_LONG, end)
        if at < 0:
            try:
                return _orjson().loads(data)
            except Exception:       # noqa: BLE001 -- json decodes it again and names the fault
                pass
    return json.loads(text)


@functools.cache
def _orjson():
    try:
        import orjson
    except ImportError:
        return None
    return orjson


def load_scene(path: str, *, check: bool = True) -> Scene:
    try:
        text = read_text(path)
    except InputError as exc:
        raise SceneError(str(exc)) from None
    return parse_scene(text, path, check=check)


@contextlib.contextmanager
def _no_gc():
    """Reading a big scene makes many small objects that all stay alive: the
    cyclic collector, left on, would walk them again and again for nothing."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def parse_scene(text: str, path: str = "<scene>", *, check: bool = True) -> Scene:
    """The scene of a JSON text, every field checked; SceneError names the
    first fault.  check=False leaves out the checks of the whole scene that
    come last (magnitudes, then overlaps at t = 0): check_scene makes them
    (`max2code simulate` runs them while the simulator reads the scene)."""
    with _no_gc():
        scene = _parse_scene(text, path)
        if check:
            _check_scene(scene)
    return scene


def check_scene(scene: Scene) -> None:
    """The last checks of parse_scene, for a scene read with check=False:
    SceneError when a body reaches too far or two bodies overlap at t = 0."""
    with _no_gc():
        _check_scene(scene)


def _check_scene(scene: Scene) -> None:
    _check_magnitudes(scene, _Reader(scene.path))
    _check_spins(scene, _Reader(scene.path))
    _check_overlaps(scene)


def _check_spins(scene: Scene, rd: _Reader) -> None:
    """Refuse a body that turns so fast that following one pair of it to the
    end would take more than max_events Taylor windows.  A pair with a
    turning body is predicted a window at a time, each window a horizon event
    (which counts against max_events), and a window sweeps at most the body's
    own window angle (body_window; a pair in which both turn, less): a pair
    that stays within reach of the body for the whole run needs at least
    |angular_velocity| end_time / window of them.  A scene whose bodies are
    all fixed predicts no pair and is not refused."""
    if len(scene.bodies) < 2 or all(b.fixed for b in scene.bodies):
        return
    circles = None
    for k, b in enumerate(scene.bodies):
        if not b.turns:
            continue
        if circles is None:
            circles = circle_lever(scene)
        window = body_window(b, scene, circles)
        windows = abs(b.angular_velocity) * scene.end_time / window
        if windows > scene.max_events:
            rd.fail(f"bodies[{k}] ({b.name})",
                    f"turns at {abs(b.angular_velocity):g} rad/s: one pair of it followed to end_time takes "
                    f"{windows:.3g} Taylor windows ({window:.3g} rad each), each a horizon event, more than "
                    f"max_events ({scene.max_events}); turn it slower, shorten end_time or raise max_events")


def _parse_scene(text: str, path: str) -> Scene:
    rd = _Reader(path)
    if nesting(text.encode("utf-8", "surrogatepass")) > MAX_NESTING:
        raise SceneError(f"{path}: error: nested too deeply (more than {MAX_NESTING} levels of brackets; "
                         "a scene needs 5)")
    try:
        raw = _decode(text)
    except json.JSONDecodeError as exc:
        raise SceneError(f"{path}:{exc.lineno}:{exc.colno}: error: not valid JSON: {exc.msg}") from None
    except RecursionError:
        raise SceneError(f"{path}: error: not valid JSON: nested too deeply") from None
    rd.keys(raw, SCENE_KEYS, "", required=("end_time", "bodies"))
    if "name" in raw and not isinstance(raw["name"], str):
        rd.fail("name", "expected a string")
    end = rd.number(raw, "end_time", "", positive=True)
    fps = rd.number(raw, "frame_rate", "", 0.0, nonneg=True)
    gravity = rd.vec(raw, "gravity", "")
    tol = rd.number(raw, "tolerance", "", 1e-9, positive=True)
    rest = rd.number(raw, "rest_speed", "", 0.05, nonneg=True)
    order = rd.number(raw, "taylor_order", "", 4, positive=True)
    if order != int(order) or not 1 <= order <= 7:
        rd.fail("taylor_order", f"must be an integer from 1 to 7 (the root solver takes degree {MAX_DEGREE} at most), "
                                f"got {order}")
    max_same = rd.number(raw, "max_events_at_one_time", "", 100000, positive=True)
    if max_same != int(max_same) or max_same >= COUNT_LIMIT:
        rd.fail("max_events_at_one_time", f"must be a whole number below 10^18, got {max_same:g}")
    max_events = rd.number(raw, "max_events", "", DEFAULT_MAX_EVENTS, positive=True)
    if max_events != int(max_events) or max_events >= COUNT_LIMIT:
        rd.fail("max_events", f"must be a whole number below 10^18, got {max_events:g}")
    max_fps = rd.number(raw, "max_frame_rate", "", DEFAULT_MAX_FRAME_RATE, positive=True)
    if fps > max_fps:
        rd.fail("frame_rate", f"{fps:g} frames per simulated second is above max_frame_rate ({max_fps:g}); "
                              "raise max_frame_rate if you mean it")
    if fps * end > max_events:
        rd.fail("frame_rate", f"{fps:g} frames per second for end_time {end:g} s is {fps * end:.3g} frames, more than "
                              f"max_events ({max_events:.0f}); lower frame_rate or raise max_events")
    if end > LENGTH_MAX:
        rd.fail("end_time", f"{end:g} s is more than {LENGTH_MAX:g} s, whose square overflows")
    if tol < LENGTH_MIN or tol > LENGTH_MAX:
        rd.fail("tolerance", f"{tol:g} m is outside {LENGTH_MIN:g}..{LENGTH_MAX:g} m (its square under- or overflows)")
    if rest > LENGTH_MAX:
        rd.fail("rest_speed", f"{rest:g} m/s is more than {LENGTH_MAX:g} m/s, whose square overflows")
    if not isinstance(raw["bodies"], list) or not raw["bodies"]:
        rd.fail("bodies", "expected a non-empty list of bodies")
    raw_inputs = raw.get("inputs", [])
    if not isinstance(raw_inputs, list):
        rd.fail("inputs", "expected a list")
    _check_size(rd, raw["bodies"], raw_inputs)

    bodies: list[Body] = []
    names: dict[str, int] = {}
    for k, b in enumerate(raw["bodies"]):
        body = _circle(b, k, gravity, names)
        if body is None:
            body = _body(rd, b, k, gravity, names)
        bodies.append(body)

    inputs: list[Input] = []
    removed: dict[int, int] = {}        # body -> the input that removes it
    for k, e in enumerate(raw_inputs):
        where = f"inputs[{k}]"
        rd.keys(e, INPUT_KEYS, where, required=("time", "body"))
        t = rd.number(e, "time", where, nonneg=True)
        if t > end:
            rd.fail(f"{where}.time", f"is after end_time ({t} > {end})")
        if not isinstance(e["body"], str):
            rd.fail(f"{where}.body", f"expected a body's name (a string), got {json.dumps(e['body'])}")
        if e["body"] not in names:
            rd.fail(f"{where}.body", f"no body is named {json.dumps(e['body'])}")
        bi = names[e["body"]]
        modes = [m for m in INPUT_KINDS if m in e]
        if len(modes) != 1:
            rd.fail(where, f"give exactly one of {', '.join(INPUT_KINDS)}")
        fb = bodies[bi]
        if fb.fixed and modes[0] != "remove" and not (modes[0] == "set_velocity" and fb.polygon
                                                      and fb.angular_velocity == 0.0):
            rd.fail(f"{where}.body", f"'{e['body']}' is fixed: inputs move movable bodies only (or set the velocity "
                                     "of a fixed polygon that does not turn, or remove a body)")
        if bi in removed:
            rd.fail(f"{where}.body", f"'{e['body']}' was removed by inputs[{removed[bi]}]")
        if modes[0] == "remove":
            if e["remove"] is not True:
                rd.fail(f"{where}.remove", "expected true")
            if any(x.body == bi and x.time > t for x in inputs):
                rd.fail(f"{where}.time", f"'{e['body']}' has an input listed before this one at a later time")
            removed[bi] = k
            inputs.append(Input(t, bi, REMOVE, (0.0, 0.0)))
            continue
        inputs.append(Input(t, bi, INPUT_KINDS.index(modes[0]), rd.vec(e, modes[0], where, None)))

    scene = Scene(path, raw.get("name", path), end, fps, gravity, tol, rest, int(order), int(max_same), bodies, inputs,
                  int(max_events))
    return scene


def max_memory() -> int:
    """Bytes of engine memory a scene may need (estimate_memory): MEMORY_ENV
    when set, else DEFAULT_MAX_MEMORY."""
    text = os.environ.get(MEMORY_ENV, "").strip()
    if not text:
        return DEFAULT_MAX_MEMORY
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not (v > 0.0 and math.isfinite(v)):
        raise SceneError(f"{MEMORY_ENV}: error: expected a positive number of bytes (such as 4e9), got {text!r}")
    return int(v)


def estimate_memory(bodies: int, vertices: int, inputs: int) -> int:
    """Bytes the C engine needs for a scene of this size (its measured peak,
    rounded up: BYTES_PER_BODY and the others)."""
    return BYTES_BASE + BYTES_PER_BODY * bodies + BYTES_PER_VERTEX * vertices + BYTES_PER_INPUT * inputs


def check_memory(path: str, bodies: int, vertices: int, inputs: int) -> None:
    """SceneError when the scene's estimate is above max_memory()."""
    need, limit = estimate_memory(bodies, vertices, inputs), max_memory()
    if need > limit:
        raise SceneError(
            f"{path}: error: scene: needs about {need / 1e6:,.0f} MB in the engine ({bodies:,} bodies x "
            f"{BYTES_PER_BODY} B + {vertices:,} vertices x {BYTES_PER_VERTEX} B + {inputs:,} inputs x "
            f"{BYTES_PER_INPUT} B + {BYTES_BASE / 1e6:g} MB), more than the limit of {limit / 1e6:,.0f} MB; "
            f"set {MEMORY_ENV}=BYTES to raise it")


def _check_size(rd: _Reader, raw_bodies: list, raw_inputs: list) -> None:
    """The counts of docs/simulator.md's "Limits" and the memory estimate,
    before any body or input is read."""
    if len(raw_bodies) > MAX_BODIES:
        rd.fail("bodies", f"{len(raw_bodies):,} bodies is more than {MAX_BODIES:,}, the most a scene may have")
    if len(raw_inputs) > MAX_INPUTS:
        rd.fail("inputs", f"{len(raw_inputs):,} inputs is more than {MAX_INPUTS:,}, the most a scene may have")
    vertices = 0
    for k, b in enumerate(raw_bodies):
        if type(b) is dict:
            v = b.get("vertices")
            if type(v) is list:
                if len(v) > MAX_VERTICES:
                    rd.fail(f"bodies[{k}].vertices", f"{len(v):,} vertices is more than {MAX_VERTICES:,}, "
                                                     "the most a polygon may have")
                vertices += len(v)
    check_memory(rd.path, len(raw_bodies), vertices, len(raw_inputs))


def _check_magnitudes(scene: Scene, rd: _Reader) -> None:
    """Refuse what a double cannot carry through the contact polynomials:
    a body that reaches farther than LENGTH_MAX from the origin by the end
    time (position + |velocity| T + |acceleration| T^2/2 + its size, inputs
    included), a size below the tolerance (a radius, an orbit's radius, a
    polygon's edge) or LENGTH_MIN, a mass or moment of inertia whose inverse
    overflows.  Everything else is simulated."""
    T = scene.end_time
    kick = [0.0] * len(scene.bodies)
    jump = [0.0] * len(scene.bodies)
    for e in scene.inputs:
        if e.mode == SET_VELOCITY:
            kick[e.body] = max(kick[e.body], math.hypot(*e.velocity))
        elif e.mode == TELEPORT:
            jump[e.body] = max(jump[e.body], math.hypot(*e.velocity))
    for e in scene.inputs:        # added velocities and impulses add up
        if e.mode == ADD_VELOCITY:
            kick[e.body] += math.hypot(*e.velocity)
        elif e.mode == IMPULSE:
            kick[e.body] += math.hypot(*e.velocity) / scene.bodies[e.body].mass
    lim_v, lim_a = LENGTH_MAX / T, LENGTH_MAX / T / T
    hypot = math.hypot
    tol = scene.tolerance
    for k, b in enumerate(scene.bodies):
        if not b.polygon:       # the common case, the same tests without the messages
            r, o = b.radius, b.orbit_radius
            speed = hypot(*b.velocity) + kick[k]
            accel = hypot(*b.acceleration)
            far = max(hypot(*b.position), jump[k])
            if (not r > LENGTH_MAX and not r < tol and not o > LENGTH_MAX and not 0.0 < o < tol
                    and not far > LENGTH_MAX and not speed > lim_v and not accel > lim_a
                    and not abs(b.angular_velocity) > lim_v
                    and far + speed * T + accel * T * T / 2.0 + b.bound <= LENGTH_MAX
                    and (b.fixed or math.isfinite(1.0 / b.mass))):
                continue
        _check_body_magnitudes(rd, T, k, b, kick[k], jump[k], tol, scene.inputs)


def _check_body_magnitudes(rd: _Reader, T: float, k: int, b: Body, kick: float, jump: float, tol: float = 0.0,
                           inputs: list[Input] = ()) -> None:
    """_check_magnitudes for one body, reporting its first fault: its own
    field, or the input (of `inputs`, the scene's) that takes it past a
    limit.  Sizes are refused below the tolerance `tol` (0: not checked):
    a contact is found only to within it."""
    where = f"bodies[{k}] ({b.name})"
    sizes = [("radius", b.radius)] if not b.polygon else [("vertices", math.hypot(x, y)) for x, y in b.vertices]
    if b.orbit_radius:
        sizes.append(("orbit.radius", b.orbit_radius))
    for field_name, v in sizes:
        if v > LENGTH_MAX:
            rd.fail(f"{where}.{field_name}", f"{v:g} m is more than {LENGTH_MAX:g} m (its square overflows)")
        if 0.0 < v < LENGTH_MIN:
            rd.fail(f"{where}.{field_name}", f"{v:g} m is less than {LENGTH_MIN:g} m (its square underflows to 0)")
        if field_name != "vertices" and v < tol:
            rd.fail(f"{where}.{field_name}", f"{v:g} m is less than the tolerance ({tol:g} m), within which "
                                             "contacts are found; scale the scene or lower the tolerance")
    n = len(b.vertices)
    for i in range(n):
        (x0, y0), (x1, y1) = b.vertices[i], b.vertices[(i + 1) % n]
        edge = math.hypot(x1 - x0, y1 - y0)
        if edge < tol:
            rd.fail(f"{where}.vertices", f"the edge from vertex {i} is {edge:g} m long, less than the tolerance "
                                         f"({tol:g} m), within which contacts are found; scale the scene or lower "
                                         "the tolerance")
    own_speed, own_far = math.hypot(*b.velocity), math.hypot(*b.position)
    speed = own_speed + kick
    accel = math.hypot(*b.acceleration)
    far = max(own_far, jump)       # teleports included
    too_far = f"is too large for end_time ({T:g} s): the motion would pass {LENGTH_MAX:g}, where squares overflow; " \
              "scale the scene"
    for field_name, v, limit in (("position", own_far, LENGTH_MAX), ("velocity", own_speed, LENGTH_MAX / T),
                                 ("acceleration", accel, LENGTH_MAX / T / T),
                                 ("angular_velocity", abs(b.angular_velocity), LENGTH_MAX / T)):
        if v > limit:
            rd.fail(f"{where}.{field_name}", f"{v:g} {too_far}")
    if jump > LENGTH_MAX:
        j = _teleport_to(inputs, k, jump)
        rd.fail(f"inputs[{j}].teleport", f"{jump:g} m from the origin is more than {LENGTH_MAX:g} m, where squares "
                                         "overflow; scale the scene")
    if speed > LENGTH_MAX / T:
        j = _kicked_past(inputs, k, b, lambda kicks: own_speed + kicks > LENGTH_MAX / T)
        rd.fail(f"inputs[{j}].{INPUT_KINDS[inputs[j].mode]}", f"takes the speed of {where} to {speed:g} m/s, which "
                                                              f"{too_far}")
    if b.polygon:
        pts = world_vertices(b)
        n = len(pts)
        (x0, y0) = pts[0]
        twice_area = sum((pts[i][0] - x0) * (pts[i + 1][1] - y0) - (pts[i + 1][0] - x0) * (pts[i][1] - y0)
                         for i in range(1, n - 1))
        if any(pts[i] == pts[(i + 1) % n] for i in range(n)) or not twice_area > 0.0:
            rd.fail(f"{where}.position", f"at {own_far:g} m from the origin the polygon's vertices round together in "
                                         "doubles (an edge vanishes or the polygon turns inside out); move the "
                                         "scene nearer the origin or scale it")
    rest = accel * T * T / 2.0 + b.bound
    reach = far + speed * T + rest
    if not reach <= LENGTH_MAX:
        fault = f"reaches {reach:g} m from the origin within end_time ({T:g} s), beyond {LENGTH_MAX:g} m where " \
                "squares overflow; scale the scene"
        if own_far + own_speed * T + rest <= LENGTH_MAX:      # an input takes it there
            if far + own_speed * T + rest > LENGTH_MAX:
                j = _teleport_to(inputs, k, jump)
            else:
                j = _kicked_past(inputs, k, b, lambda kicks: far + (own_speed + kicks) * T + rest > LENGTH_MAX)
            rd.fail(f"inputs[{j}].{INPUT_KINDS[inputs[j].mode]}", f"with it {where} {fault}")
        rd.fail(where, fault)
    if not b.fixed:
        if not math.isfinite(1.0 / b.mass):
            rd.fail(f"{where}.mass", f"{b.mass:g} kg is too small: 1/mass overflows")
        if b.polygon and not (b.inertia > 0.0 and math.isfinite(1.0 / b.inertia)):
            rd.fail(f"{where}.mass", f"the moment of inertia ({b.inertia:g}) of this mass and shape cannot be "
                                     "inverted in doubles; scale the scene")


def _teleport_to(inputs: list[Input], k: int, jump: float) -> int:
    """The index of body k's teleport farthest from the origin (`jump` m)."""
    return next(j for j, e in enumerate(inputs) if e.body == k and e.mode == TELEPORT
                and math.hypot(*e.velocity) == jump)


def _kicked_past(inputs: list[Input], k: int, b: Body, past) -> int:
    """The index of body k's first input after which past(kicks) holds:
    kicks is the speed its inputs may add so far, as _check_magnitudes adds
    it (the largest set velocity plus every added velocity and impulse;
    the last such input when none does, the sums having rounded apart)."""
    most = added = 0.0
    last = -1
    for j, e in enumerate(inputs):
        if e.body != k:
            continue
        if e.mode == SET_VELOCITY:
            most = max(most, math.hypot(*e.velocity))
        elif e.mode == ADD_VELOCITY:
            added += math.hypot(*e.velocity)
        elif e.mode == IMPULSE:
            added += math.hypot(*e.velocity) / b.mass
        else:
            continue
        last = j
        if past(most + added):
            return j
    return last         # the sum rounded otherwise than _check_magnitudes's: the last input that adds


# ---------------------------------------------------------------- geometry
def world_vertices(b: Body) -> list[tuple[float, float]]:
    """A polygon's vertices placed at its position and angle (t = 0)."""
    ca, sa = math.cos(b.angle), math.sin(b.angle)
    return [(b.position[0] + ca * x - sa * y, b.position[1] + sa * x + ca * y) for x, y in b.vertices]


def circle_centre(b: Body) -> tuple[float, float]:
    if b.orbit_radius == 0.0:
        return b.position
    a = b.angle + b.orbit_angle
    return (b.position[0] + b.orbit_radius * math.cos(a), b.position[1] + b.orbit_radius * math.sin(a))


def penetration(a: Body, b: Body) -> float:
    """How deep two bodies overlap at t = 0 (<= 0: apart or touching)."""
    return penetration_placed(a, world_vertices(a) if a.polygon else None,
                              b, world_vertices(b) if b.polygon else None)


def penetration_placed(a: Body, pa, b: Body, pb, above: float = -math.inf) -> float:
    """penetration(a, b) from the polygons' world vertices (pa, pb; None for
    a circle).  With `above`, two polygons stop at the first separating axis
    that shows the depth is at most `above`, and return that axis's depth (at
    most `above`, at least the true depth): for a caller that only wants
    depths greater than `above`."""
    if pa is None and pb is None:
        (x1, y1), (x2, y2) = circle_centre(a), circle_centre(b)
        return a.radius + b.radius - math.hypot(x2 - x1, y2 - y1)
    if pa is None or pb is None:
        c, pts = (a, pb) if pa is None else (b, pa)
        x, y = circle_centre(c)
        n = len(pts)
        # signed distance from the centre to the polygon
        inside_depth = math.inf
        outside = 0.0
        for i in range(n):
            (x0, y0), (x1, y1) = pts[i], pts[(i + 1) % n]
            ex, ey = x1 - x0, y1 - y0
            ln = math.hypot(ex, ey)
            d = ((x - x0) * ey - (y - y0) * ex) / ln          # > 0 outside this edge
            inside_depth = min(inside_depth, -d)
            u = max(0.0, min(1.0, ((x - x0) * ex + (y - y0) * ey) / (ln * ln)))
            dist = math.hypot(x - (x0 + u * ex), y - (y0 + u * ey))
            outside = dist if i == 0 else min(outside, dist)
        if inside_depth > 0.0:
            return c.radius + inside_depth
        return c.radius - outside
    # two polygons: separating axes
    depth = math.inf
    for pts, other in ((pa, pb), (pb, pa)):
        n = len(pts)
        for i in range(n):
            (x0, y0), (x1, y1) = pts[i], pts[(i + 1) % n]
            ex, ey = x1 - x0, y1 - y0
            ln = math.hypot(ex, ey)
            nx, ny = ey / ln, -ex / ln
            lo = min((x - x0) * nx + (y - y0) * ny for x, y in other)
            depth = min(depth, -lo)
            if depth <= above:
                return depth
    return depth


def _box(b: Body) -> tuple[float, float, float, float]:
    """A box holding the body at t = 0."""
    if b.polygon:
        pts = world_vertices(b)
        xs, ys = [x for x, _ in pts], [y for _, y in pts]
        return (min(xs), min(ys), max(xs), max(ys))
    x, y = circle_centre(b)
    return (x - b.radius, y - b.radius, x + b.radius, y + b.radius)


def _check_overlaps(scene: Scene) -> None:
    """Bodies must not overlap at t = 0 beyond the tolerance (touching is fine).
    Pairs are found through a grid (and boxes for the large bodies), so this
    stays fast for 10^5 bodies; the first overlapping pair in index order is
    reported."""
    bodies = scene.bodies
    if not bodies:
        return
    tol = scene.tolerance
    # the fields of all bodies at once
    bound, fixed = list(map(_bound, bodies)), list(map(_fixed, bodies))
    position = list(map(_position, bodies))
    xs, ys = list(map(_first, position)), list(map(_second, position))
    cell = 2.0 * max(compress(bound, map(operator.not_, fixed))) if not all(fixed) else 1.0
    is_big = list(map(operator.gt, bound, repeat(cell / 2.0)))
    big = list(compress(range(len(bodies)), is_big))
    small = list(compress(range(len(bodies)), map(operator.not_, is_big)))
    found: list[tuple[int, int, float]] = []

    def test(i: int, j: int) -> None:
        if fixed[i] and fixed[j]:
            return
        reach = bound[i] + bound[j] + tol
        if (xs[i] - xs[j]) ** 2 + (ys[i] - ys[j]) ** 2 > reach * reach:
            return
        d = penetration(bodies[i], bodies[j])
        if d > tol:
            found.append((min(i, j), max(i, j), d))

    # the grid of the small bodies; cell (gx, gy) is the whole number gx * rows + gy - low, with a free
    # row either side, so that its neighbours are the key plus a constant
    floor = math.floor
    gx = list(map(floor, map(operator.truediv, map(xs.__getitem__, small), repeat(cell))))
    gy = list(map(floor, map(operator.truediv, map(ys.__getitem__, small), repeat(cell))))
    grid: dict[int, list[int]] = {}
    get = grid.get
    if small:
        low = min(gy) - 1
        rows = max(gy) - low + 2
        for i, key in zip(small, map(operator.sub, map(operator.add, map(operator.mul, gx, repeat(rows)), gy),
                                     repeat(low))):
            members = get(key)
            if members is None:
                grid[key] = [i]
            else:
                members.append(i)
        # each pair of neighbouring cells once: the cell itself and four of its eight neighbours,
        # (1, -1), (1, 0), (1, 1) and (0, 1), each step for all cells at once (most neighbours of a
        # gas's cells are empty: no Python runs for them); the distance test of `test` first, inlined
        keys, cells = list(grid), list(grid.values())
        for members in compress(cells, map(operator.gt, map(len, cells), repeat(1))):
            for k, i in enumerate(members):
                for j in members[k + 1:]:
                    test(i, j)
        for step in (rows - 1, rows, rows + 1, 1):
            near = list(map(get, map(operator.add, keys, repeat(step))))
            for members, others in zip(compress(cells, near), filter(None, near)):
                for j in others:
                    xj, yj, bj = xs[j], ys[j], bound[j]
                    for i in members:
                        reach = bound[i] + bj + tol
                        if (xs[i] - xj) ** 2 + (ys[i] - yj) ** 2 <= reach * reach:
                            test(i, j)
    boxes: dict[int, tuple[float, float, float, float]] = {}     # _box of the bodies near a big one, made once

    def box(j: int) -> tuple[float, float, float, float]:
        if j not in boxes:
            b = bodies[j]
            boxes[j] = ((b.position[0] - b.radius, b.position[1] - b.radius, b.position[0] + b.radius,
                         b.position[1] + b.radius) if not b.polygon and b.orbit_radius == 0.0 else _box(b))
        return boxes[j]

    big_set = set(big)
    everyone = range(len(bodies))
    for i in big:
        ax0, ay0, ax1, ay1 = box(i)
        near = everyone
        if max(-ax0, ax1, -ay0, ay1) + tol < cell * 2.0 ** 40:
            # A small body reaches at most half a cell from its position, so one
            # whose box comes within tol of this box sits in a cell this box
            # (widened by tol) covers or in one next to it: those cells, and the
            # big bodies, when that is fewer than all bodies (the same pairs
            # then pass the box test below).
            gx0, gx1 = math.floor((ax0 - tol) / cell) - 1, math.floor((ax1 + tol) / cell) + 1
            gy0, gy1 = math.floor((ay0 - tol) / cell) - 1, math.floor((ay1 + tol) / cell) + 1
            if (gx1 - gx0 + 1) * (gy1 - gy0 + 1) < len(bodies):
                # the rows that hold small bodies only (a key outside them would be another column's)
                gy0, gy1 = (max(gy0, low + 1), min(gy1, low + rows - 2)) if small else (0, -1)
                near = [j for gx in range(gx0, gx1 + 1) for gy in range(gy0, gy1 + 1)
                        for j in grid.get(gx * rows + gy - low, ())] + big
        for j in near:
            if j == i or (j < i and j in big_set):
                continue
            bx0, by0, bx1, by1 = box(j)
            if ax0 > bx1 + tol or bx0 > ax1 + tol or ay0 > by1 + tol or by0 > ay1 + tol:
                continue            # the boxes hold the bodies: apart by more than the tolerance
            test(i, j)
    if found:
        i, j, d = min(found)
        a, b = bodies[i], bodies[j]
        raise SceneError(f"{scene.path}: error: bodies[{i}] ({a.name}) and bodies[{j}] ({b.name}) overlap at t = 0 "
                         f"by {d:.3g} m (tolerance {tol:g})")


# ---------------------------------------------------------------- compiling
def window_angle(scene: Scene) -> float:
    """Largest angle a turn may sweep in one prediction so that the Taylor
    polynomials of order n stay within the tolerance: the remainder of sin
    and cos is at most a^(n+1)/(n+1)!, times the lever (the sum of two
    bounding radii at most)."""
    bounds = list(map(_bound, turning(scene.bodies)))
    if not bounds:
        return 0.5
    # near a contact the lever is at most the two bodies' bounding radii
    lever = 2.0 * max(bounds) + max(b.bound for b in scene.bodies if not b.fixed or b.turns)
    return _angle_for(lever, scene.taylor_order, scene.tolerance)


def _angle_for(lever: float, n: int, tol: float) -> float:
    """The largest angle (at most 0.5 rad) whose order-n Taylor remainder of
    sin and cos, a^(n+1)/(n+1)!, times the lever stays below the tolerance."""
    return min(0.5, (math.factorial(n + 1) * tol / lever) ** (1.0 / (n + 1)))


def circle_lever(scene: Scene) -> float:
    """The largest radius of a circle that does not turn (no orbit, or no
    spin): the partner that adds most to the lever of a turning body whose
    partner does not turn (0 when the scene has none)."""
    if not _any_spin(scene.bodies):     # then none turns
        circles = compress(scene.bodies, map(operator.not_, map(_is_polygon, scene.bodies)))
        return max(map(_radius, circles), default=0.0)
    return max((b.radius for b in scene.bodies if not b.polygon and not b.turns), default=0.0)


def body_window(b: Body, scene: Scene, circles: float) -> float:
    """A body's own window angle, used when it turns and its partner does
    not: the Taylor remainder of the pair's gap is then at most its own
    bounding radius (a vertex's orbit against the partner's edge line; the
    partner's vertex against its own turning edge, near contact) plus a
    circle partner's radius, times a^(n+1)/(n+1)!.  0 for a body that can
    never turn (the runtime never uses it)."""
    if not b.may_turn:
        return 0.0
    return _angle_for(b.bound + circles, scene.taylor_order, scene.tolerance)


class Grid(FrozenRecord):
    # margin: m, how far past a cell's edge a moving centre goes before it changes cell
    _fields = ("x0", "y0", "cw", "ch", "nx", "ny", "margin", "large")

    def __init__(self, x0: float, y0: float, cw: float, ch: float, nx: int, ny: int, margin: float,
                 large: tuple[bool, ...]):
        self._set(x0=x0, y0=y0, cw=cw, ch=ch, nx=nx, ny=ny, margin=margin, large=large)


# Cells are this many times as wide as the largest movable body, and the
# slack is spent on a margin (hysteresis): a centre changes cell only once it
# is `margin` past the edge, so a body that crosses and turns back (the usual
# case after a collision near an edge) makes no second crossing.  Two bodies
# whose cells are not neighbours still cannot touch while each is at most
# `margin` outside its cell, since cell >= largest + 2 margin.  Measured on
# bench/sim.py's gas (docs/simulator.md, "Cell size, measured"): 1.15 takes
# the events per collision from 2.9 to 2.4 (10^4 disks) and 3.1 to 2.3
# (10^5) for +1.8 % / -3.3 % instructions per collision.
CELL_FACTOR = 1.15


def make_grid(scene: Scene) -> Grid:
    """A uniform grid whose cells are at least as wide as the largest movable
    body plus twice the margin: bodies in cells that are not neighbours
    cannot touch.  Bodies wider than the largest movable one (fixed walls)
    are kept in a separate list instead.  Cells CELL_FACTOR times that
    width with the slack spent on the margin cost about what the cell
    crossings they save cost; wider cells without a margin were measured
    to cost more (docs/simulator.md, "Cell size, measured")."""
    bound = list(map(_bound, scene.bodies))
    size = 2.0 * max(compress(bound, map(operator.not_, map(_fixed, scene.bodies))), default=1.0) * (1.0 + 1e-6)
    large = tuple(map(operator.gt, map(operator.mul, bound, repeat(2.0)), repeat(size)))
    small = list(compress(scene.bodies, map(operator.not_, large)))
    if not small:
        return Grid(0.0, 0.0, size, size, 1, 1, 0.0, large)
    pos = list(map(_position, small))
    xs = list(map(_first, pos))
    ys = list(map(_second, pos))
    cell = size * CELL_FACTOR
    x0, y0 = min(xs) - cell, min(ys) - cell
    w, h = max(xs) - min(xs) + 2.0 * cell, max(ys) - min(ys) + 2.0 * cell
    limit = max(16, 4 * len(small))
    nx, ny = max(1, int(w // cell)), max(1, int(h // cell))
    while nx * ny > limit:
        nx, ny = max(1, nx // 2), max(1, ny // 2)
    cw, ch = w / nx, h / ny
    # the whole slack (a dilute scene's cells, widened to fit the limit, get more)
    margin = max(0.0, 0.5 * (min(cw, ch) - size))
    return Grid(x0, y0, cw, ch, nx, ny, margin, large)


def _r(x: float) -> str:
    return repr(float(x))


def body_lines(b: Body, large: bool, window: float, covers: list[int] | None = None) -> list[str]:
    """A body's `body` line and its `v` lines in the flat format (covers:
    per edge, the fixed body covering it, -1 none: covered_edges)."""
    out = []
    inv_m = 0.0 if b.fixed else 1.0 / b.mass
    inv_i = 0.0 if (b.fixed or not b.polygon) else 1.0 / b.inertia
    (px, py), (vx, vy), (ax, ay) = b.position, b.velocity, b.acceleration
    reals = " ".join(map(repr, map(float, (inv_m, inv_i, b.restitution, b.friction, px, py, vx, vy, ax, ay,
                                            b.angle, b.angular_velocity, b.radius, b.orbit_radius,
                                            b.orbit_angle, b.bound, window))))
    out.append(f"body {'1' if b.polygon else '0'} {'1' if b.fixed else '0'} {reals} "
               f"{'1' if large else '0'} {len(b.vertices)}")
    n = len(b.vertices)
    for k in range(n):
        (x0, y0), (x1, y1) = b.vertices[k], b.vertices[(k + 1) % n]
        ex, ey = x1 - x0, y1 - y0
        ln = math.hypot(ex, ey)
        nx, ny = ey / ln, -ex / ln                  # outward: the polygon is counter-clockwise
        tx, ty = ex / ln, ey / ln
        out.append(" ".join(["v", _r(x0), _r(y0), _r(math.hypot(x0, y0)), _r(math.atan2(y0, x0)),
                             _r(math.atan2(ny, nx)), _r(nx * x0 + ny * y0),
                             _r(tx * x0 + ty * y0), _r(tx * x1 + ty * y1), _r(nx), _r(ny),
                             str(covers[k] if covers else -1)]))
    return out


def _static(b: Body) -> bool:
    return b.fixed and b.velocity == (0.0, 0.0) and b.acceleration == (0.0, 0.0) and b.angular_velocity == 0.0


def _edges(pts: list[tuple[float, float]]) -> list[tuple[float, float, float]]:
    """(nx, ny, h) per edge of a counter-clockwise polygon: the outward unit
    normal and the line's offset, n . p <= h inside."""
    out = []
    n = len(pts)
    for k in range(n):
        (x0, y0), (x1, y1) = pts[k], pts[(k + 1) % n]
        ln = math.hypot(x1 - x0, y1 - y0)
        nx, ny = (y1 - y0) / ln, -(x1 - x0) / ln
        out.append((nx, ny, nx * x0 + ny * y0))
    return out


def covered_edges(scene: Scene) -> dict[int, list[int]]:
    """The faces of fixed polygons that no body can touch: edge k of a fixed,
    unmoving polygon P (no input sets its velocity) is covered by another
    fixed, unmoving polygon Q (the
    first by index) when both its ends lie in Q (within the tolerance) and Q
    goes on past the edge on its outside: at each end, every edge of Q whose
    line it lies on (within the tolerance) faces away from the edge's
    outward normal (dot product <= 1e-9).  Q convex: the edge and the space
    just outside it are inside Q, so a body touching it would overlap Q.  (A
    wall's bottom face lying flush on a floor: a corner pinched between it
    and the floor's top would meet both faces at one instant, forever.)
    Returns {body index: per edge, Q's index or -1} for the bodies that have
    a covered edge."""
    tol = scene.tolerance
    driven = {e.body for e in scene.inputs if e.mode == SET_VELOCITY}     # fixed bodies an input sets moving
    static = [(k, b) for k, b in enumerate(scene.bodies) if b.polygon and _static(b) and k not in driven]
    if len(static) < 2:
        return {}
    shapes = {k: (world_vertices(b), b) for k, b in static}
    lines = {k: _edges(pts) for k, (pts, _) in shapes.items()}
    out: dict[int, list[int]] = {}
    for k, (pts, b) in shapes.items():
        covers = [-1] * len(pts)
        for e, (nx, ny, _) in enumerate(lines[k]):
            ends = (pts[e], pts[(e + 1) % len(pts)])
            for q, (_, bq) in shapes.items():
                if q == k:
                    continue
                dx, dy = bq.position[0] - b.position[0], bq.position[1] - b.position[1]
                reach = b.bound + bq.bound + tol
                if dx * dx + dy * dy > reach * reach:
                    continue
                ok = True
                for x, y in ends:
                    for qx, qy, qh in lines[q]:
                        d = qx * x + qy * y - qh
                        if d > tol or (d >= -tol and qx * nx + qy * ny > 1e-9):
                            ok = False
                            break
                    if not ok:
                        break
                if ok:
                    covers[e] = q
                    break
        if any(c >= 0 for c in covers):
            out[k] = covers
    return out


def _circle_line(b: Body, large: bool, window: float) -> str:
    """body_lines of a circle (it has no `v` lines), in one f-string: the
    same text, a third of the time for 10^5 disks (`!r` of a float is
    repr(float(x)); every field of a read Body is a float)."""
    inv_m = 0.0 if b.fixed else 1.0 / b.mass
    (px, py), (vx, vy), (ax, ay) = b.position, b.velocity, b.acceleration
    return (f"body 0 {'1' if b.fixed else '0'} {inv_m!r} 0.0 {b.restitution!r} {b.friction!r} {px!r} {py!r} "
            f"{vx!r} {vy!r} {ax!r} {ay!r} {b.angle!r} {b.angular_velocity!r} {b.radius!r} {b.orbit_radius!r} "
            f"{b.orbit_angle!r} {b.bound!r} {float(window)!r} {'1' if large else '0'} 0")


def compile_scene(scene: Scene) -> str:
    """The flat text a runtime's simulator reads (docs/simulator.md)."""
    return "".join(compile_parts(scene))


def compile_parts(scene: Scene, bodies: int = 2048):
    """compile_scene in pieces of whole lines, about `bodies` bodies each,
    made as they are asked for (a simulator can read one while the next is
    made)."""
    with _no_gc():
        yield from _compile_parts(scene, bodies)


def _compile_parts(scene: Scene, size: int):
    g = make_grid(scene)
    out = ["m2c-scene 1",
           f"end {_r(scene.end_time)}",
           f"frame {_r(1.0 / scene.frame_rate if scene.frame_rate > 0 else 0.0)}",
           f"tolerance {_r(scene.tolerance)}",
           f"rest_speed {_r(scene.rest_speed)}",
           f"window_angle {_r(window_angle(scene))}",
           f"max_same_time {scene.max_same}",
           f"max_events {scene.max_events}",
           f"grid {_r(g.x0)} {_r(g.y0)} {_r(g.cw)} {_r(g.ch)} {g.nx} {g.ny} {_r(g.margin)}",
           f"bodies {len(scene.bodies)}"]
    circles = circle_lever(scene)
    covered = covered_edges(scene)
    for k, (b, large) in enumerate(zip(scene.bodies, g.large)):
        if b.polygon:
            out += body_lines(b, large, body_window(b, scene, circles), covered.get(k))
        else:
            # a circle may turn only when it orbits and spins (Body.may_turn): else its window is 0
            window = body_window(b, scene, circles) if b.orbit_radius > 0.0 and b.angular_velocity != 0.0 else 0.0
            out.append(_circle_line(b, large, window))
        if len(out) >= size:
            yield "\n".join(out) + "\n"
            out = []
    out.append(f"inputs {len(scene.inputs)}")
    for e in scene.inputs:
        out.append(f"input {_r(e.time)} {e.body} {e.mode} {_r(e.velocity[0])} {_r(e.velocity[1])}")
    out.append("end")
    yield "\n".join(out) + "\n"
