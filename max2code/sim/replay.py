"""Replay a simulator trace: the state of every body at any time, exactly.

A trace (the JSON lines `max2code simulate` writes, docs/simulator.md) gives,
for each collision and input, the new state of each movable body it changed.
Between two such states a body moves exactly as the simulator moves it:

    p(t) = p + (v + a dt / 2) dt,   v(t) = v + a dt,   angle(t) = angle + w dt

with `a` the body's acceleration from the scene (gravity included for
movable bodies).  These are the runtime's own operations in the runtime's
order, so replaying a Python trace reproduces its final states bit for bit.

Per body the states are kept as a time-sorted list of segments, and a query
is one bisection: `Replay.state_at(body, t)` costs O(log k) for a body with k
state changes, whatever the number of bodies or events.  Nothing here draws;
max2code/draw/render.py does.
"""
from __future__ import annotations

import json
import math
from bisect import bisect_left, bisect_right
from dataclasses import dataclass
from typing import NamedTuple

from max2code.errors import Max2CodeError
from max2code.textio import InputError, read_text
from max2code.sim.scene import REMOVE, SET_VELOCITY, TELEPORT, Body, Scene

EVENT_KINDS = ("collision", "support", "stop", "leave", "sleep", "wake", "input", "frame")


class TraceError(Max2CodeError):
    """A trace that cannot be read, or that does not belong to the scene."""


class State(NamedTuple):
    """A body's motion from time `t` on (until its next state change)."""
    t: float
    px: float
    py: float
    vx: float
    vy: float
    angle: float
    omega: float
    ax: float = 0.0       # acceleration in force from t (a supported body's differs from the scene's)
    ay: float = 0.0

    @property
    def position(self) -> tuple[float, float]:
        return (self.px, self.py)

    @property
    def velocity(self) -> tuple[float, float]:
        return (self.vx, self.vy)


@dataclass
class Event:
    """One event line of the trace."""
    line: int
    t: float
    kind: str
    bodies: tuple[int, ...]           # indices into scene.bodies
    feature: str | None = None        # collisions: circle-circle, circle-vertex, circle-edge, vertex-edge
    point: tuple[float, float] | None = None
    normal: tuple[float, float] | None = None
    impulse: float = 0.0


def advance(s: State, b: Body, t: float) -> State:
    """The state `s` of body `b` carried forward (or back) to time t."""
    dt = t - s.t
    ax, ay = s.ax, s.ay
    return State(t, s.px + (s.vx + 0.5 * ax * dt) * dt, s.py + (s.vy + 0.5 * ay * dt) * dt,
                 s.vx + ax * dt, s.vy + ay * dt, s.angle + s.omega * dt, s.omega, ax, ay)


def initial_state(b: Body) -> State:
    return State(0.0, b.position[0], b.position[1], b.velocity[0], b.velocity[1], b.angle, b.angular_velocity,
                 b.acceleration[0], b.acceleration[1])


class Replay:
    """A scene plus the state changes of a trace.

    `times[k]` and `states[k]` are body k's state-change times (the first is
    0, the scene's initial state) and the states from then on.  Several
    changes at one instant (a ball hitting two others at once) are all kept;
    a query at that instant sees the last one, as the simulator does."""

    def __init__(self, scene: Scene, path: str = "<trace>"):
        self.scene = scene
        self.path = path
        self.index = {b.name: k for k, b in enumerate(scene.bodies)}
        self.states: list[list[State]] = [[initial_state(b)] for b in scene.bodies]
        self.times: list[list[float]] = [[0.0] for _ in scene.bodies]
        self.events: list[Event] = []
        self.final: dict[int, State] | None = None      # the trace's own final states, when it has them
        self.end_time = scene.end_time
        self.stats: dict | None = None

    # ---- queries ----------------------------------------------------------
    def body_index(self, body: int | str) -> int:
        if isinstance(body, str):
            try:
                return self.index[body]
            except KeyError:
                raise TraceError(f"{self.path}: error: no body is named {body!r} in {self.scene.path}") from None
        return body

    def segment(self, body: int | str, t: float) -> State:
        """The state change in force at time t (the last one at or before t;
        the initial state for t < 0)."""
        k = self.body_index(body)
        i = bisect_right(self.times[k], t) - 1
        return self.states[k][max(i, 0)]

    def state_at(self, body: int | str, t: float) -> State:
        """Position, velocity, angle and angular velocity of a body at time t."""
        k = self.body_index(body)
        s = self.segment(k, t)
        return s if s.t == t else advance(s, self.scene.bodies[k], t)

    def state_before(self, body: int | str, t: float) -> State:
        """The state just before t: the one in force before the changes at t,
        carried to t."""
        k = self.body_index(body)
        i = bisect_left(self.times[k], t) - 1
        return advance(self.states[k][max(i, 0)], self.scene.bodies[k], t)

    def shape_at(self, body: int | str, t: float):
        """The body in the world at time t: ('circle', (cx, cy), r) or
        ('polygon', [(x, y), ...]) with the vertices counter-clockwise."""
        k = self.body_index(body)
        b = self.scene.bodies[k]
        s = self.state_at(k, t)
        if b.polygon:
            return ("polygon", polygon_at(b, s.px, s.py, s.angle))
        return ("circle", circle_centre_at(b, s.px, s.py, s.angle), b.radius)

    def change_times(self) -> list[float]:
        """Every instant at which some body's motion changed, sorted."""
        return sorted({t for ts in self.times for t in ts[1:]})

    @property
    def frame_times(self) -> list[float]:
        return [e.t for e in self.events if e.kind == "frame"]

    @property
    def collisions(self) -> list[Event]:
        return [e for e in self.events if e.kind == "collision"]

    def final_error(self) -> tuple[float, str]:
        """Largest distance between the trace's final positions and the
        replayed ones, and the body where it is (0.0, '' without a final line)."""
        worst, who = 0.0, ""
        if not self.final:
            return worst, who
        for k, f in self.final.items():
            s = self.state_at(k, self.end_time)
            d = math.hypot(s.px - f.px, s.py - f.py)
            if d > worst or not who:
                worst, who = d, self.scene.bodies[k].name
        return worst, who

    # ---- building ---------------------------------------------------------
    def add_state(self, k: int, s: State, line: int) -> None:
        if s.t < self.times[k][-1]:
            raise TraceError(f"{self.path}:{line}: error: a state of {self.scene.bodies[k].name} at t={s.t!r} "
                             f"comes before its previous one at t={self.times[k][-1]!r}")
        self.times[k].append(s.t)
        self.states[k].append(s)


def polygon_at(b: Body, px: float, py: float, angle: float) -> list[tuple[float, float]]:
    ca, sa = math.cos(angle), math.sin(angle)
    return [(px + ca * x - sa * y, py + sa * x + ca * y) for x, y in b.vertices]


def circle_centre_at(b: Body, px: float, py: float, angle: float) -> tuple[float, float]:
    if b.orbit_radius == 0.0:
        return (px, py)
    a = angle + b.orbit_angle
    return (px + b.orbit_radius * math.cos(a), py + b.orbit_radius * math.sin(a))


# ---------------------------------------------------------------- reading
class _Lines:
    def __init__(self, path: str, scene: Scene, index: dict[str, int]):
        self.path = path
        self.scene = scene
        self.index = index
        self.line = 0

    def fail(self, msg: str):
        raise TraceError(f"{self.path}:{self.line}: error: {msg}")

    def number(self, obj: dict, key: str, what: str) -> float:
        v = obj.get(key)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            self.fail(f"{what}: expected a finite number for '{key}', got {json.dumps(v)}")
        return float(v)

    def vec(self, obj: dict, key: str, what: str) -> tuple[float, float]:
        v = obj.get(key)
        if not (isinstance(v, list) and len(v) == 2
                and all(not isinstance(x, bool) and isinstance(x, (int, float)) and math.isfinite(x) for x in v)):
            self.fail(f"{what}: expected [x, y] for '{key}', got {json.dumps(v)}")
        return (float(v[0]), float(v[1]))

    def body(self, name) -> int:
        k = self.index.get(name) if isinstance(name, str) else None
        if k is None:
            self.fail(f"body {json.dumps(name)} is not in {self.scene.path}: the trace belongs to another scene")
        return k

    def state(self, obj, t: float | None, what: str) -> tuple[int, State]:
        if not isinstance(obj, dict):
            self.fail(f"{what}: expected an object, got {json.dumps(obj)[:60]}")
        k = self.body(obj.get("body"))
        px, py = self.vec(obj, "position", what)
        vx, vy = self.vec(obj, "velocity", what)
        # the acceleration from then on: a supported body's is its own, else the scene's
        ax, ay = self.vec(obj, "acceleration", what) if "acceleration" in obj else self.scene.bodies[k].acceleration
        return k, State(t if t is not None else 0.0, px, py, vx, vy,
                        self.number(obj, "angle", what), self.number(obj, "angular_velocity", what), ax, ay)


def read_trace(text: str, scene: Scene, path: str = "<trace>", *, tolerance: float | None = 1e-6) -> Replay:
    """Read a JSON-lines trace of `scene` into a Replay.  Errors (bad JSON,
    unknown bodies or kinds, states of fixed bodies (but at an input that
    sets its velocity), times out of order or
    past the end, a final line that does not list exactly the scene's
    bodies) name the file and line.  With a `tolerance` (None: no check),
    the trace must agree with the scene to that many metres (times the
    larger of 1 and the coordinates): each state change puts the body where
    the replay has it (events change velocities and accelerations only), and
    the final positions are the replayed ones.  A trace of another scene
    whose bodies happen to share the names fails here."""
    rp = Replay(scene, path)
    rd = _Lines(path, scene, rp.index)
    last_t = 0.0
    seen_final = False
    for rd.line, raw in enumerate(text.splitlines(), 1):
        if not raw.strip():
            continue
        try:
            obj = json.loads(raw)
        except (json.JSONDecodeError, RecursionError) as exc:
            msg = exc.msg if isinstance(exc, json.JSONDecodeError) else "nested too deeply"
            rd.fail(f"not a JSON trace line ({msg}): is this the trace written by 'max2code simulate -o'?")
        if isinstance(obj, dict) and "end_time" in obj and "bodies" in obj:
            rd.fail("this is a scene, not a trace (give the scene, then the trace 'max2code simulate -o' wrote)")
        if not isinstance(obj, dict) or not isinstance(obj.get("kind"), str):
            rd.fail("expected an object with a 'kind' (a trace line of 'max2code simulate')")
        kind = obj["kind"]
        if seen_final and kind != "stats":
            rd.fail(f"a '{kind}' line after the final states")
        if kind == "stats":
            rp.stats = obj
            continue
        if kind == "final":
            seen_final = True
            t = rd.number(obj, "t", "final")
            if t != scene.end_time:
                rd.fail(f"final: the trace ends at t={t!r}, the scene {scene.path} at end_time={scene.end_time!r}")
            bodies = obj.get("bodies")
            if not isinstance(bodies, list):
                rd.fail("final: expected a list of 'bodies'")
            final: dict[int, State] = {}
            for s in bodies:
                k, st = rd.state(s, t, "final")
                final[k] = st
            if len(final) != len(scene.bodies) or len(bodies) != len(scene.bodies):
                rd.fail(f"final: lists {len(bodies)} bodies, the scene {scene.path} has {len(scene.bodies)}: "
                        "the trace belongs to another scene")
            rp.final = final
            continue
        if kind not in EVENT_KINDS:
            rd.fail(f"unknown kind {json.dumps(kind)} (expected one of {', '.join(EVENT_KINDS + ('final', 'stats'))})")
        t = rd.number(obj, "t", kind)
        if t < last_t:
            rd.fail(f"{kind} at t={t!r} comes before the previous event at t={last_t!r}")
        if t > scene.end_time:
            rd.fail(f"{kind} at t={t!r} is after the end_time of {scene.path} ({scene.end_time!r})")
        last_t = t
        names = obj.get("bodies", [])
        if not isinstance(names, list):
            rd.fail(f"{kind}: expected a list of 'bodies'")
        ev = Event(rd.line, t, kind, tuple(rd.body(n) for n in names))
        if kind in ("collision", "support"):
            if len(ev.bodies) != 2:
                rd.fail(f"{kind}: expected 2 bodies, got {len(ev.bodies)}")
            ev.feature = obj.get("feature") if isinstance(obj.get("feature"), str) else None
            ev.point = rd.vec(obj, "point", kind)
            ev.normal = rd.vec(obj, "normal", kind)
            ev.impulse = rd.number(obj, "impulse", kind)
        elif kind == "input" and len(ev.bodies) != 1:
            rd.fail(f"input: expected 1 body, got {len(ev.bodies)}")
        teleport = None         # an input that moves the body (the only event that does)
        k_in = obj.get("input")
        if kind == "input" and isinstance(k_in, int) and 0 <= k_in < len(scene.inputs):
            if scene.inputs[k_in].mode == TELEPORT:
                teleport = scene.inputs[k_in]
            elif scene.inputs[k_in].mode == REMOVE and ev.bodies:
                # a removed body stops where it is, for good (the trace has no state for it)
                k = ev.bodies[0]
                p = advance(rp.states[k][-1], scene.bodies[k], t)
                rp.add_state(k, State(t, p.px, p.py, 0.0, 0.0, p.angle, 0.0, 0.0, 0.0), rd.line)
        states = obj.get("states", [])
        if not isinstance(states, list):
            rd.fail(f"{kind}: expected a list of 'states'")
        for s in states:
            k, st = rd.state(s, t, f"{kind} state")
            driven = (kind == "input" and isinstance(k_in, int) and 0 <= k_in < len(scene.inputs)
                      and scene.inputs[k_in].mode == SET_VELOCITY and scene.inputs[k_in].body == k)
            if scene.bodies[k].fixed and not driven:       # only an input that sets its velocity moves it
                rd.fail(f"{kind}: the trace changes the motion of {scene.bodies[k].name}, which is fixed in "
                        f"{scene.path}: the trace belongs to another scene")
            if k not in ev.bodies and kind != "wake":       # a wake changes every body woken with it
                rd.fail(f"{kind}: a state of {scene.bodies[k].name}, which is not in this {kind}")
            if tolerance is not None:
                p = advance(rp.states[k][-1], scene.bodies[k], t)
                if teleport is not None:
                    p = p._replace(px=teleport.velocity[0], py=teleport.velocity[1])
                d = math.hypot(p.px - st.px, p.py - st.py)
                if not d <= tolerance * max(1.0, abs(st.px), abs(st.py)):
                    rd.fail(f"does not match {scene.path}: replayed from the scene, {scene.bodies[k].name} is at "
                            f"({p.px:.6g}, {p.py:.6g}) at t={t!r}, the trace puts it at ({st.px:.6g}, {st.py:.6g}) "
                            f"({d:.3g} m apart)")
            rp.add_state(k, st, rd.line)
        rp.events.append(ev)
    if rd.line == 0 or (not rp.events and rp.final is None):
        raise TraceError(f"{path}: error: empty trace: no events and no final states")
    if tolerance is not None and rp.final:
        for k, f in rp.final.items():
            s = rp.state_at(k, scene.end_time)
            d = math.hypot(s.px - f.px, s.py - f.py)
            if not d <= tolerance * max(1.0, abs(f.px), abs(f.py)):
                raise TraceError(f"{path}: error: does not match {scene.path}: replayed from the scene, "
                                 f"{scene.bodies[k].name} ends at ({s.px:.6g}, {s.py:.6g}), the trace says "
                                 f"({f.px:.6g}, {f.py:.6g}) ({d:.3g} m apart)")
    return rp


def load_trace(path: str, scene: Scene, **kw) -> Replay:
    try:
        text = read_text(path)
    except InputError as exc:
        raise TraceError(f"{exc} (expected the JSON lines of 'max2code simulate')") from None
    return read_trace(text, scene, path, **kw)
