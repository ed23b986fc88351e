"""The discrete-event simulator: the Python runtime, and the reference for
the C, Rust and Modula-2 ones (docs/simulator.md).

It reads a compiled scene (the flat text format of docs/simulator.md, made
by `max2code simulate` from a JSON scene) and writes the flat trace.  Every
prediction goes through the generated entry functions of
equations/circle-circle.mxm and equations/point-edge.mxm (the module objects
`cc` and `pe` hold `circle_circle_coefficients`, `circle_circle_variant`,
`point_edge_coefficients`, `point_edge_variant`), and through the runtime's
root solver.  The four runtimes perform the same IEEE double operations in
the same order, so they write the same bytes.
"""
from __future__ import annotations

import heapq
import math

from max2code_rt.roots import smallest_root

HALF_PI = 1.5707963267948966   # pi/2 rounded to double (cos x = sin(x + pi/2))

# event kinds, in the order they are handled at equal times
INPUT, COLLISION, STOP, LEAVE, CELL, HORIZON, FRAME = 0, 1, 2, 3, 4, 5, 6
KIND_NAMES = ("input", "collision", "stop", "leave", "cell", "horizon", "frame")
# contact features: circle-circle (also circle-vertex) and point-edge
CC, PE = 0, 1
# the most stages (a meeting of the bounds, a clear stretch, a Taylor window)
# one prediction of a pair goes through before it leaves the rest to a horizon
CHAIN = 8
TWO_M40 = 2.0 ** -40  # circles_apart's margins: far above the coefficients' rounding
TWO_M30 = 2.0 ** -30
TWO_M900 = 2.0 ** -900  # ... and its bounds on sizes: nothing underflows or overflows
TWO_M450 = 2.0 ** -450
TWO_P450 = 2.0 ** 450
# simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
# contacts"): how many times one contact is handled at one instant before it
# and the contacts that reach it are solved together; the most sweeps of the
# cluster's sequential impulses, and the sweep that ends them: no impulse in
# it changed a normal speed by more than CLUSTER_TOL rest_speed
CLUSTER_REPEATS = 64
CLUSTER_SWEEPS = 100
CLUSTER_TOL = 1e-9
# the separation speed (times rest_speed) of a cluster's contact that nothing
# presses: above the rounding of a normal speed, so that it is not met again at once
CLUSTER_APART = 2.0 ** -20
# the angle (rad) within which one push holds a free acceleration (wedged)
HOLD_TOL = 1e-9
# a body's part in a cluster's solve: held (fixed, or asleep: infinite mass),
# free, or sliding on a fixed body's edge (moves along the edge only)
HELD, FREE, SLIDER = 0, 1, 2
FEATURE_NAMES = ("circle-circle", "point-edge")
# the trace's N lines, in this order (the fields of Stats)
STAT_NAMES = ("collisions", "inputs", "frames", "cells", "horizons", "stale", "pairs", "features",
              "supports", "stops", "leaves", "sleeps", "wakes")


class SimError(Exception):
    pass


class Vertex:
    """One vertex of a polygon and the edge that starts at it (to the next
    vertex), in the body's frame: all precomputed by the scene compiler."""
    __slots__ = ("lx", "ly", "rho", "beta", "psi", "h", "s1", "s2", "nx", "ny", "cover")
    # lx, ly   m: the vertex about the centre of mass
    # rho, beta  m, rad: its polar form
    # psi      rad: angle of the edge's outward normal
    # h        m: offset of the edge's line, n . v
    # s1, s2   m: the edge's extent along its tangent (-ny, nx)
    # nx, ny   the edge's outward unit normal (cos psi, sin psi, but exact
    #          where the compiler's quotient is: (0, 1) for a level top face)
    # cover    the fixed body that covers the edge (no body can touch it while
    #          that one is there), -1: none

    def __init__(self, vals, cover: int):
        self.lx, self.ly, self.rho, self.beta, self.psi, self.h, self.s1, self.s2, self.nx, self.ny = vals
        self.cover = cover


class Body:
    """A body's constants and its motion, stored as the state at its own
    last update time tb.  Units: s, m, m/s, m/s^2, rad, rad/s, kg."""
    __slots__ = ("idx", "polygon", "fixed", "inv_m", "inv_i", "e", "mu", "px", "py", "vx", "vy", "ax", "ay",
                 "ang", "om", "tb", "r", "orbit", "ophase", "bound", "window", "large", "verts", "stamp", "cx", "cy",
                 "fax", "fay", "sup", "sup_edge", "tx", "ty", "load", "at", "gone", "asleep", "island", "wcells", "seen",
                 "carry")
    # idx            index in the scene
    # polygon, fixed, large   flags (large: not in the grid, in the large list)
    # inv_m, inv_i   1/kg, 1/(kg m^2); 0 for fixed bodies
    # e              restitution, 0..1
    # mu             friction coefficient (Coulomb), >= 0
    # px, py         m: centre (of rotation) at tb
    # vx, vy         m/s: velocity at tb
    # ax, ay         m/s^2: acceleration now (gravity included; while supported,
    #                the support's acceleration plus the relative one along its
    #                edge, less friction)
    # fax, fay       m/s^2: free acceleration (gravity and the body's own), from the scene
    # ang, om        rad, rad/s: angle at tb, angular velocity
    # tb             s: the time of this state
    # r              m: circle radius (0 for polygons)
    # orbit, ophase  m, rad: orbit radius and phase (circles)
    # bound          m: radius of the bounding circle about the centre
    # window         rad: its window angle when it turns and its partner does not (0: it never turns)
    # verts          list of Vertex (polygons), else empty
    # stamp          bumped when the motion changes (lazy invalidation)
    # cx, cy         grid cell (small bodies; a moving centre may be up to the grid margin outside it)
    # sup            index of the body supporting it (fixed), or carrying it (movable), -1: free
    # sup_edge       the supporting edge (index into sup's vertices)
    # tx, ty         unit tangent of the supporting edge (along increasing S1..S2)
    # load           m/s^2: free acceleration relative to the support's pressing onto it, > 0
    # at             m/s^2: free acceleration relative to the support's, along the tangent
    # gone           removed from the world (remove_body, input MODE 4): frozen, out of the grid
    # asleep         frozen in a sleeping island (v = a = w = 0, no events of its own)
    # island         the island's number (the index of its first sleeper), -1: awake
    # wcells         a large body placed in the grid: the cells its box covers (x_lo, x_hi, y_lo, y_hi), else None
    # seen           the mark of the last large_near that listed it
    # carry          how many bodies it carries (their sup is this movable body)


class Stats:
    """The counters written as the trace's N lines (STAT_NAMES order)."""
    __slots__ = STAT_NAMES

    def __init__(self):
        for name in STAT_NAMES:
            setattr(self, name, 0)


# ---- event records: one per kind, with the fields that kind needs ----------
# The queue orders by (t, kind, seq); seq is the scheduling counter.
# stamp_a / stamp_b: the bodies' stamps when the event was scheduled.

class InputEvent:
    __slots__ = ("t", "k")              # k: index in the scene's inputs
    kind = INPUT

    def __init__(self, t: float, k: int):
        self.t, self.k = t, k


class CollisionEvent:
    __slots__ = ("t", "a", "b", "feature", "i", "j", "stamp_a", "stamp_b")
    kind = COLLISION
    # feature CC: circle of a against the circle of b (j < 0) or vertex j of b
    # feature PE: circle of a (i < 0) or vertex i of a against edge j of b

    def __init__(self, t, a, b, feature, i, j, stamp_a, stamp_b):
        self.t, self.a, self.b, self.feature, self.i, self.j = t, a, b, feature, i, j
        self.stamp_a, self.stamp_b = stamp_a, stamp_b


class CellEvent:
    __slots__ = ("t", "body", "axis", "direction", "stamp")
    kind = CELL
    # axis 0: x, 1: y; direction +1 or -1: the neighbouring cell entered

    def __init__(self, t, body, axis, direction, stamp):
        self.t, self.body, self.axis, self.direction, self.stamp = t, body, axis, direction, stamp


class StopEvent:
    __slots__ = ("t", "body", "stamp")
    kind = STOP
    # a sliding supported body's tangential speed reaches zero

    def __init__(self, t, body, stamp):
        self.t, self.body, self.stamp = t, body, stamp


class LeaveEvent:
    __slots__ = ("t", "body", "stamp")
    kind = LEAVE
    # a supported body's centre, projected on the support's edge, reaches its end

    def __init__(self, t, body, stamp):
        self.t, self.body, self.stamp = t, body, stamp


class HorizonEvent:
    __slots__ = ("t", "a", "b", "stamp_a", "stamp_b")
    kind = HORIZON

    def __init__(self, t, a, b, stamp_a, stamp_b):
        self.t, self.a, self.b, self.stamp_a, self.stamp_b = t, a, b, stamp_a, stamp_b


class FrameEvent:
    __slots__ = ("t", "k")              # frame k is at k * frame_dt
    kind = FRAME

    def __init__(self, t: float, k: int):
        self.t, self.k = t, k


def _always(s: float) -> bool:
    return True


def _fmt(x: float) -> str:
    return "%.17g" % x


# input modes (the flat scene's MODE; docs/simulator.md)
SET_VELOCITY, ADD_VELOCITY, IMPULSE, TELEPORT, REMOVE = 0, 1, 2, 3, 4


class Input:
    """A scripted or live input."""
    __slots__ = ("t", "body", "mode", "vx", "vy")
    # t s; body index; mode SET_VELOCITY, ADD_VELOCITY (vx, vy m/s), IMPULSE
    # (vx, vy: the impulse, N s, through the centre), TELEPORT (vx, vy: the
    # new centre, m), REMOVE (vx, vy unused, 0)

    def __init__(self, t: float, body: int, mode: int, vx: float, vy: float):
        self.t, self.body, self.mode, self.vx, self.vy = t, body, mode, vx, vy


class Tokens:
    """The whitespace-separated words of a flat text, read in order."""

    def __init__(self, text: str, what: str):
        self.tok = text.split()
        self.pos = 0
        self.what = what

    def word(self, expect=None) -> str:
        if self.pos >= len(self.tok):
            raise SimError(f"{self.what}: ends early" + (f" (expected '{expect}')" if expect else ""))
        w = self.tok[self.pos]
        self.pos += 1
        if expect is not None and w != expect:
            raise SimError(f"{self.what}: expected '{expect}', found '{w}'")
        return w

    def num(self) -> float:
        w = self.word()
        try:
            return float(w)
        except ValueError:
            raise SimError(f"{self.what}: expected a number, found '{w}'") from None

    def integer(self) -> int:
        w = self.word()
        try:
            return int(w)
        except ValueError:
            raise SimError(f"{self.what}: expected an integer, found '{w}'") from None


def read_body(tk: Tokens, i: int) -> Body:
    """A `body ...` line and its `v` lines (docs/simulator.md, Flat scene)."""
    num, integer = tk.num, tk.integer
    tk.word("body")
    b = Body()
    b.idx = i
    b.polygon = integer() == 1
    b.fixed = integer() == 1
    b.inv_m, b.inv_i, b.e, b.mu = num(), num(), num(), num()
    b.px, b.py, b.vx, b.vy, b.ax, b.ay = num(), num(), num(), num(), num(), num()
    b.fax, b.fay = b.ax, b.ay
    b.sup, b.sup_edge = -1, -1
    b.tx = b.ty = b.load = b.at = 0.0
    b.ang, b.om = num(), num()
    b.r, b.orbit, b.ophase, b.bound, b.window = num(), num(), num(), num(), num()
    b.large = integer() == 1
    nv = integer()
    b.verts = []
    for _ in range(nv):
        tk.word("v")
        b.verts.append(Vertex([num() for _ in range(10)], integer()))
    b.tb = 0.0
    b.stamp = 0
    b.cx = b.cy = 0
    b.gone = False
    b.asleep = False
    b.island = -1
    b.wcells = None
    b.seen = 0
    b.carry = 0
    return b


def drivable(b: Body, mode: int) -> bool:
    """An input of this mode may act on b: any on a movable body; on a fixed
    one, removal, or set_velocity when it is a polygon that does not turn
    (its edges then translate: docs/simulator.md, Contact model)."""
    if not b.fixed or mode == REMOVE:
        return True
    return mode == SET_VELOCITY and b.polygon and b.om == 0.0


class Scene:
    """A compiled scene, read from the flat format."""

    def __init__(self, text: str):
        tk = Tokens(text, "scene")
        word, num, integer = tk.word, tk.num, tk.integer
        word("m2c-scene")
        if integer() != 1:
            raise SimError("scene: unknown version")
        word("end"); self.end = num()
        word("frame"); self.frame_dt = num()
        word("tolerance"); self.tol = num()
        word("rest_speed"); self.rest_speed = num()
        word("window_angle"); self.alpha = num()
        word("max_same_time"); self.max_same = integer()
        word("grid"); self.x0 = num(); self.y0 = num(); self.cw = num(); self.ch = num()
        self.nx = integer(); self.ny = integer(); self.margin = num()
        self.half_cell = 0.5 * min(self.cw, self.ch)
        if not 0.0 <= self.margin < self.half_cell:
            raise SimError(f"scene: grid margin {_fmt(self.margin)} m outside [0, half a cell)")
        word("bodies"); n = integer()
        self.bodies: list[Body] = [read_body(tk, i) for i in range(n)]
        word("inputs"); k = integer()
        self.inputs = []
        for _ in range(k):
            word("input")
            inp = Input(num(), integer(), integer(), num(), num())
            if not 0 <= inp.body < n:
                raise SimError(f"scene: input on body {inp.body}, which does not exist")
            if not 0 <= inp.mode <= 4:
                raise SimError(f"scene: unknown input mode {inp.mode}")
            if not drivable(self.bodies[inp.body], inp.mode):
                raise SimError(f"scene: input {len(self.inputs)} on fixed body {inp.body}: only set_velocity "
                               f"(on a polygon that does not turn) or remove")
            self.inputs.append(inp)
        word("end")


class Contact:
    """A collision or support as advance() reports it: the fields of the
    trace's E collision / E support line (docs/engine-api.md)."""
    __slots__ = ("t", "a", "b", "feature", "i", "j", "px", "py", "nx", "ny", "impulse", "support")
    # support: True when the contact ended in support (E support), else a collision

    def __init__(self, t, a, b, feature, i, j, px, py, nx, ny, impulse, support):
        self.t, self.a, self.b, self.feature, self.i, self.j = t, a, b, feature, i, j
        self.px, self.py, self.nx, self.ny, self.impulse, self.support = px, py, nx, ny, impulse, support

    def __repr__(self):
        return (f"Contact(t={self.t!r}, a={self.a}, b={self.b}, feature={self.feature}, i={self.i}, j={self.j}, "
                f"p=({self.px!r}, {self.py!r}), n=({self.nx!r}, {self.ny!r}), impulse={self.impulse!r}, "
                f"support={self.support})")


class NoTrace:
    """The trace sink of a world without a trace."""

    @staticmethod
    def write(text: str) -> None:
        pass


class World:
    """A live world (docs/engine-api.md): made from a flat scene, driven by
    advance(t); the batch simulator is run() = advance(end) + finish()."""

    def __init__(self, scene_text: str, cc, pe, out=None):
        scene = Scene(scene_text)
        self.s = scene
        self.cc_coef = cc.circle_circle_coefficients
        self.cc_var = cc.circle_circle_variant
        self.pe_coef = pe.point_edge_coefficients
        self.pe_var = pe.point_edge_variant
        self.cc_counts = [0] * len(cc.CIRCLE_CIRCLE_VARIANT_NAMES)
        self.pe_counts = [0] * len(pe.POINT_EDGE_VARIANT_NAMES)
        self.out = NoTrace if out is None else out
        self.heap: list = []
        self.seq = 0
        self.stats = Stats()
        self.cells: list[list[Body]] = [[] for _ in range(scene.nx * scene.ny)]
        # large bodies: a fixed one that does not move is listed in every cell
        # its box covers (walls); the others (moving, or movable) in `large`
        self.walls: list[list[Body]] = [[] for _ in range(scene.nx * scene.ny)]
        self.large: list[Body] = []
        self.mark = 0
        for b in scene.bodies:
            if b.large:
                self.place_large(b)
        self.time = 0.0             # s: the world's current time
        self.last_t = -1.0          # the instant of the last event handled, and how many came at it
        self.same = 0
        self.contacts: list[Contact] = []    # reported by the next advance()
        self.added = 0              # bodies added by add_body (a recording refuses them)
        self.unpaid = False         # a hop since sleeper_impulse cleared it added energy (pay_floor could not pay)
        self.touched_t = -1.0       # the instant of the contacts in touched
        self.touched: list[list[int]] = []   # [a, b, feature, i, j, times] of each contact handled at touched_t
        self.handlers = (self.handle_input, self.handle_collision, self.handle_stop, self.handle_leave,
                         self.handle_cell, self.handle_horizon, self.handle_frame)     # by kind
        self.start()

    @classmethod
    def from_file(cls, path: str, cc, pe, out=None) -> "World":
        with open(path, encoding="ascii") as fh:
            return cls(fh.read(), cc, pe, out)

    # ---- motion -----------------------------------------------------------
    @staticmethod
    def rebase(b: Body, t: float) -> None:
        """Carry b's state to time t (only events do this: re-basing rounds)."""
        dt = t - b.tb
        b.px = b.px + (b.vx + 0.5 * b.ax * dt) * dt
        b.py = b.py + (b.vy + 0.5 * b.ay * dt) * dt
        b.vx = b.vx + b.ax * dt
        b.vy = b.vy + b.ay * dt
        b.ang = b.ang + b.om * dt
        b.tb = t

    @staticmethod
    def state_at(b: Body, t: float):
        """Centre, velocity and angle at time t (the body is not changed)."""
        dt = t - b.tb
        return (b.px + (b.vx + 0.5 * b.ax * dt) * dt, b.py + (b.vy + 0.5 * b.ay * dt) * dt,
                b.vx + b.ax * dt, b.vy + b.ay * dt, b.ang + b.om * dt)

    @staticmethod
    def turn_rate(b: Body) -> float:
        if b.polygon or b.orbit > 0.0:
            return math.fabs(b.om)
        return 0.0

    # ---- the event queue --------------------------------------------------
    def push(self, ev) -> None:
        """Queue an event record; the queue orders by (t, kind, seq)."""
        heapq.heappush(self.heap, (ev.t, ev.kind, self.seq, ev))
        self.seq += 1

    def push_collision(self, t: float, feature: int, A: Body, B: Body, i: int, j: int) -> None:
        self.push(CollisionEvent(t, A.idx, B.idx, feature, i, j, A.stamp, B.stamp))

    def push_horizon(self, t: float, A: Body, B: Body) -> None:
        self.push(HorizonEvent(t, A.idx, B.idx, A.stamp, B.stamp))

    def is_stale(self, ev) -> bool:
        """An event whose bodies' motion changed since it was scheduled.
        Inputs are scripted, not predicted, and frames have no bodies: never."""
        bodies = self.s.bodies
        if ev.kind == COLLISION or ev.kind == HORIZON:
            return bodies[ev.a].stamp != ev.stamp_a or bodies[ev.b].stamp != ev.stamp_b
        if ev.kind == CELL or ev.kind == STOP or ev.kind == LEAVE:
            return bodies[ev.body].stamp != ev.stamp
        return False

    # ---- grid -------------------------------------------------------------
    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        s = self.s
        ix = math.floor((x - s.x0) / s.cw)
        iy = math.floor((y - s.y0) / s.ch)
        ix = 0 if ix < 0 else (s.nx - 1 if ix > s.nx - 1 else ix)
        iy = 0 if iy < 0 else (s.ny - 1 if iy > s.ny - 1 else iy)
        return int(ix), int(iy)

    def cell_remove(self, b: Body) -> None:
        lst = self.cells[b.cy * self.s.nx + b.cx]
        k = lst.index(b)
        last = lst.pop()
        if k < len(lst):
            lst[k] = last

    def cell_add(self, b: Body) -> None:
        self.cells[b.cy * self.s.nx + b.cx].append(b)

    def candidates(self, b: Body, x_lo: int, x_hi: int, y_lo: int, y_hi: int):
        s = self.s
        for jy in range(max(y_lo, 0), min(y_hi, s.ny - 1) + 1):
            for jx in range(max(x_lo, 0), min(x_hi, s.nx - 1) + 1):
                for o in self.cells[jy * s.nx + jx]:
                    if o is not b:
                        yield o

    def place_large(self, b: Body) -> None:
        """A large body into the grid's walls when it is fixed and does not
        move (v = a = 0): its box (a polygon that does not turn: its
        vertices at its time; else its centre +- bound) in cells, every cell
        from cell_of(box's low corner) to cell_of(its high corner), each
        cell's list in the order bodies are placed; else into `large`."""
        if not (b.fixed and b.vx == 0.0 and b.vy == 0.0 and b.ax == 0.0 and b.ay == 0.0):
            self.large.append(b)
            return
        if b.polygon and b.om == 0.0:
            x0, y0 = self.point_at(b, b.verts[0], b.tb)
            x1, y1 = x0, y0
            for v in b.verts:
                x, y = self.point_at(b, v, b.tb)
                x0, x1, y0, y1 = min(x0, x), max(x1, x), min(y0, y), max(y1, y)
        else:
            x0, x1, y0, y1 = b.px - b.bound, b.px + b.bound, b.py - b.bound, b.py + b.bound
        i0, j0 = self.cell_of(x0, y0)
        i1, j1 = self.cell_of(x1, y1)
        b.wcells = (i0, i1, j0, j1)
        nx = self.s.nx
        for jy in range(j0, j1 + 1):
            for jx in range(i0, i1 + 1):
                self.walls[jy * nx + jx].append(b)

    def unplace_large(self, b: Body) -> None:
        if b.wcells is None:
            self.large.remove(b)
            return
        i0, i1, j0, j1 = b.wcells
        nx = self.s.nx
        for jy in range(j0, j1 + 1):
            for jx in range(i0, i1 + 1):
                self.walls[jy * nx + jx].remove(b)

    def walls_in(self, b: Body, x_lo: int, x_hi: int, y_lo: int, y_hi: int, out: list) -> None:
        """Append to out the placed large bodies listed in the cells x_lo..x_hi,
        y_lo..y_hi (clamped to the grid, rows then columns), but b and those
        already carrying the current mark, and mark them."""
        s = self.s
        mark = self.mark
        for jy in range(max(y_lo, 0), min(y_hi, s.ny - 1) + 1):
            for jx in range(max(x_lo, 0), min(x_hi, s.nx - 1) + 1):
                for o in self.walls[jy * s.nx + jx]:
                    if o.seen != mark and o is not b:
                        o.seen = mark
                        out.append(o)

    def large_near(self, b: Body) -> list[Body]:
        """The large bodies b predicts against: those placed in its 3x3 cells
        and every one in `large`, each once, but b, in index order."""
        self.mark += 1
        out: list[Body] = []
        self.walls_in(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1, out)
        for o in self.large:
            if o is not b:
                out.append(o)
        out.sort(key=lambda o: o.idx)
        return out

    # ---- first valid root of one feature ----------------------------------
    @staticmethod
    def pressing(c: list[float], deg: int, d: float, s: float) -> bool:
        """At a zero of the gap c: approaching (first derivative d < 0), or
        resting and pressed together (d == 0, second derivative < 0)."""
        if d < 0.0:
            return True
        if d != 0.0 or deg < 2:
            return False
        dd = 0.0
        for k in range(deg, 1, -1):
            dd = dd * s + k * (k - 1) * c[k]
        return dd < 0.0

    @staticmethod
    def touching_now(c: list[float], deg: int, kappa: float) -> bool:
        """At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
        pressed together (c2 < 0) so that the gap closes again before it
        ever exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.
        (A resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.)"""
        if c[1] < 0.0:
            return True
        if deg < 2 or not (c[2] < 0.0):
            return False
        return c[0] + c[1] * c[1] / (4.0 * -c[2]) <= kappa

    def first_contact(self, c: list[float], deg: int, w: float, kappa: float, check) -> float | None:
        """The smallest s in [0, w] where the gap c(s) reaches zero while
        decreasing, or touches zero with zero slope while pressed together
        (resting contact), and check(s) holds.  At s = 0 the gap counts as
        zero within kappa: approaching or pressed (touching_now) means
        contact now, separating or merely touching never."""
        if deg >= 1 and math.fabs(c[0]) <= kappa and self.touching_now(c, deg, kappa) and check(0.0):
            return 0.0
        lo = 0.0
        for _ in range(deg + 2):
            s = smallest_root(c[:deg + 1], lo, w)
            if s is None:
                return None
            d = 0.0
            for k in range(deg, 0, -1):
                d = d * s + k * c[k]
            if self.pressing(c, deg, d, s) and check(s):
                return s
            lo = s
        return None

    # ---- features ---------------------------------------------------------
    def circle_params(self, b: Body, now: float, v: Vertex | None):
        """circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
        circle's centre (v None) or of a polygon's vertex, at time now."""
        x, y, vx, vy, ang = self.state_at(b, now)
        if v is None:
            d, phase = b.orbit, ang + b.ophase
        else:
            d, phase = v.rho, ang + v.beta
        om = b.om
        if om == 0.0 and d != 0.0:
            # an orbit that does not turn is a fixed offset: fold it in
            x = x + d * math.cos(phase)
            y = y + d * math.sin(phase)
            d = 0.0
        if d == 0.0:
            om = 0.0
            phase = 0.0
        return x, vx, b.ax, d, om, phase + HALF_PI, y, vy, b.ay, om, phase

    @staticmethod
    def centre_params(b: Body, now: float):
        """circle_circle parameters of b's centre of rotation at time now, no
        orbit: the centre of a bounding circle (circle_params of a polygon)."""
        x, y, vx, vy, _ = World.state_at(b, now)
        return x, vx, b.ax, 0.0, 0.0, HALF_PI, y, vy, b.ay, 0.0, 0.0

    def predict_cc(self, A: Body, B: Body, vb: Vertex | None, rb: float, now: float, w: float):
        """Circle of A against circle of B (vb None) or vertex vb of B (radius 0)."""
        return self.circles_first(self.circle_params(A, now, None), A.r, self.circle_params(B, now, vb), rb, w)

    def circles_first(self, pa, ra: float, pb, rb: float, w: float):
        """The first contact within [0, w] of a circle of radius ra moving as
        pa (circle_params) and one of radius rb moving as pb."""
        args = self.cc_args(pa, ra, pb, rb)
        tol = self.s.tol
        kappa = tol * (2.0 * (ra + rb) + tol)
        if self.circles_apart(args, kappa):
            self.cc_count(args)
            return None
        coef = self.cc_coefficients(args)
        return self.first_contact(coef, len(coef) - 1, w, kappa, _always)

    @staticmethod
    def circles_apart(g, kappa: float) -> bool:
        """The pair of circles_gap's parameters g surely has no contact,
        decided without the polynomial (docs/simulator.md, "Pairs that stay
        apart"): neither circle orbits and their relative acceleration is
        zero, so the gap is |p + v s|^2 - R^2 (p, v: the relative position
        and velocity, R = ra + rb), and either the centres separate (p . v > 0
        by more than its rounding: the generated c1 = 2 p.v is then positive,
        c2 = |v|^2 is never negative, and first_contact finds no approach),
        or they approach on a line that passes farther than R from each
        other: (p x v)^2 > (R^2 + kappa) |v|^2 by more than the rounding
        (then the gap now exceeds kappa and its discriminant is clearly
        negative: no root).  The margins (2^-40 and 2^-30 of the terms'
        size) are far above the few units of 2^-53 by which the coefficients
        can be off, and the sizes are bounded so that nothing underflows
        (where rounding is no longer relative: a speed of 1e-162 m/s squares
        to 0) or overflows.  The caller still counts the prediction."""
        if g[2] != 0.0 or g[8] != 0.0 or g[3] != 0.0 or g[14] != 0.0:
            return False
        x, vx, y, vy = g[0], g[1], g[6], g[7]
        px, py = x * vx, y * vy
        size = math.fabs(px) + math.fabs(py)
        if size >= TWO_M900 and px + py > TWO_M40 * size:
            return True
        r = g[22] + g[23]
        v2, p2 = vx * vx + vy * vy, x * x + y * y
        if not (TWO_M450 <= v2 <= TWO_P450 and TWO_M450 <= p2 <= TWO_P450):
            return False
        cross = x * vy - y * vx
        return cross * cross - (r * r + kappa) * v2 > TWO_M30 * p2 * v2

    def circles_gap(self, pa, ra: float, pb, rb: float) -> list[float]:
        """The circle_circle polynomial (squared distance of the centres less
        (ra + rb)^2, in s from the parameters' time) of a circle of radius ra
        moving as pa (circle_params) and one of radius rb moving as pb."""
        return self.cc_coefficients(self.cc_args(pa, ra, pb, rb))

    @staticmethod
    def cc_args(pa, ra: float, pb, rb: float) -> tuple:
        """circle_circle's 24 parameters of a circle of radius ra moving as
        pa (circle_params) and one of radius rb moving as pb."""
        a, b_, c, d, e, f, m, n, o, p, q = pa
        g, h, i, j, k, l, r, s_, u, v, ww = pb
        # only differences of the centres' motions matter: circle 1 moves
        # relative to circle 2's centre of rotation, so that a common gravity
        # cancels (no_accel variants) and far from the origin nothing is lost
        return (a - g, b_ - h, c - i, d, e, f, m - r, n - s_, o - u, p, q,
                0.0, 0.0, 0.0, j, k, l, 0.0, 0.0, 0.0, v, ww, ra, rb)

    def cc_count(self, args) -> None:
        """Counts a circle_circle prediction: its variant and `features`."""
        idx = self.cc_var(*args)
        if idx < 0:
            raise SimError("circle_circle: the scene uses an effect the generated code leaves out")
        self.cc_counts[idx] += 1
        self.stats.features += 1

    def cc_coefficients(self, args) -> list[float]:
        self.cc_count(args)
        return self.cc_coef(*args)

    def predict_pe(self, X: Body, Y: Body, vx_: Vertex | None, j: int, now: float, w: float, i: int = -1):
        """Point of X (circle centre with radius, or vertex vx_, X's vertex i) against the line of edge j
        of Y (none while a fixed body covers the edge: its cover is not gone)."""
        cover = Y.verts[j].cover
        if cover >= 0 and not self.s.bodies[cover].gone:
            return None
        if vx_ is None:
            rho, beta, rad = X.orbit, X.ophase, X.r
        else:
            rho, beta, rad = vx_.rho, vx_.beta, 0.0
        coef = self.pe_coefficients(X, Y, rho, beta, rad, j, now)
        return self.pe_first(coef, X, Y, rho, beta, j, now, w, i)

    def pe_coefficients(self, X: Body, Y: Body, rho: float, beta: float, rad: float, j: int,
                        now: float) -> list[float]:
        """The point_edge polynomial of a circle of radius rad whose centre
        orbits X's centre at rho (phase beta in X's frame) against the line
        of edge j of Y, in s = t - now (its c[0]: the gap now)."""
        ed = Y.verts[j]
        x1, y1, u1, v1, ang1 = self.state_at(X, now)
        x2, y2, u2, v2, ang2 = self.state_at(Y, now)
        phn = ang2 + ed.psi
        wr = X.om - Y.om
        phr = (ang1 + beta) - phn
        h = ed.h + rad
        if wr == 0.0 and rho != 0.0:
            # the point does not turn relative to the edge: its offset along
            # the normal is a constant, folded into the line's offset
            h = h - rho * math.cos(phr)
            rho = 0.0
        args = (x1 - x2, u1 - u2, X.ax - Y.ax, y1 - y2, v1 - v2, X.ay - Y.ay,
                rho, wr, phr, Y.om, phn, h)
        idx = self.pe_var(*args)
        if idx < 0:
            raise SimError("point_edge: the scene uses an effect the generated code leaves out")
        self.pe_counts[idx] += 1
        self.stats.features += 1
        return self.pe_coef(*args)

    def pe_first(self, coef: list[float], X: Body, Y: Body, rho: float, beta: float, j: int, now: float,
                 w: float, i: int = -1):
        """The first contact within [0, w] of pe_coefficients' polygon whose
        point (X's centre, or rho, beta about it) lies on edge j's segment;
        when the point is X's vertex i (i >= 0), both neighbours of that
        vertex must also lie no more than the tolerance behind edge j's line
        (`behind`: else that line does not separate the bodies there, a
        corner meeting a corner: another feature pair is the contact)."""
        ed = Y.verts[j]
        tol = self.s.tol

        def inside(s: float) -> bool:
            t = now + s
            px, py, _, _, pa = self.state_at(X, t)
            if rho != 0.0:
                px, py = px + rho * math.cos(pa + beta), py + rho * math.sin(pa + beta)
            qx, qy, _, _, qa = self.state_at(Y, t)
            th = qa + ed.psi
            c = math.cos(th)
            sn = math.sin(th)
            along = (px - qx) * -sn + (py - qy) * c
            if not (ed.s1 - tol <= along <= ed.s2 + tol):
                return False
            if i < 0:
                return True
            return not self.behind(X, i, t, qx, qy, c, sn, ed.h)

        return self.first_contact(coef, len(coef) - 1, w, tol, inside)

    def behind(self, X: Body, i: int, t: float, qx: float, qy: float, c: float, sn: float, h: float) -> bool:
        """A neighbour of X's vertex i at t lies more than the tolerance
        behind the line (c, sn) . (p - (qx, qy)) = h (an edge's line: its
        outward unit normal (c, sn) at angle th, its body's centre (qx, qy)),
        previous neighbour first (docs/simulator.md, "Corners")."""
        n = len(X.verts)
        px, py, _, _, pa = self.state_at(X, t)
        lim = -self.s.tol
        for k in ((i + n - 1) % n, (i + 1) % n):
            v = X.verts[k]
            kx = px + v.rho * math.cos(pa + v.beta)
            ky = py + v.rho * math.sin(pa + v.beta)
            if (kx - qx) * c + (ky - qy) * sn - h < lim:
                return True
        return False

    def point_at(self, b: Body, v: Vertex | None, t: float) -> tuple[float, float]:
        """World position of a circle's centre (v None) or of a vertex, at t."""
        x, y, _, _, ang = self.state_at(b, t)
        d, beta = (b.orbit, b.ophase) if v is None else (v.rho, v.beta)
        if d == 0.0:
            return x, y
        return x + d * math.cos(ang + beta), y + d * math.sin(ang + beta)

    # ---- pairs ------------------------------------------------------------
    def predict_pair(self, A: Body, B: Body, now: float) -> None:
        """Schedule the first contact of A and B after now, or a horizon
        event where the Taylor polynomials of their turns stop being good.
        Cheap steps chain: a later meeting of the bounds or a clear stretch
        moves `now` on (up to CHAIN stages, at most one Taylor window)."""
        s = self.s
        if A.sup == B.idx or B.sup == A.idx:
            return      # the support's edge line separates them (both convex): only leaving ends it
        if (A.asleep and self.grounded(B)) or (B.asleep and self.grounded(A)):
            return      # a sleeper against a sleeper or an unmoving fixed body: nothing moves
        self.stats.pairs += 1
        ta, tb = self.turn_rate(A), self.turn_rate(B)
        windowed = False
        for _ in range(CHAIN):
            w = s.end - now
            if not (w > 0.0):
                return
            if A.polygon or B.polygon:
                # bounds that do not turn: until they touch, nothing can
                if B.polygon and ta > 0.0 and B.om == 0.0:
                    meet = self.bound_polygon(A, B, now, w)
                elif A.polygon and tb > 0.0 and A.om == 0.0:
                    meet = self.bound_polygon(B, A, now, w)
                else:
                    meet = self.bounds_meet(A, B, now, w)
                if meet is None:
                    return
                if meet > 0.0:
                    now = now + meet
                    continue
            if ta > 0.0 and tb > 0.0:
                w = min(w, s.alpha / (ta + tb))
            elif ta > 0.0:
                w = min(w, A.window / ta)
            elif tb > 0.0:
                w = min(w, B.window / tb)
            if ta > 0.0 or tb > 0.0:
                clear = self.clear_time(A, B, now)
                if clear >= w:
                    # apart all through the window, whatever the turns do: no
                    # roots to solve until they may come within the tolerance
                    now = now + clear
                    continue
            if windowed:
                break       # one Taylor window per prediction: the next at a horizon
            best = self.features(A, B, now, w)
            if best is not None:
                bodies = s.bodies
                self.push_collision(now + best[0], best[1], bodies[best[2]], bodies[best[3]], best[4], best[5])
                return
            if ta == 0.0 and tb == 0.0:
                return      # nothing turns: the window was the whole run
            now = now + w
            windowed = True
        if now < s.end:
            self.push_horizon(now, A, B)

    def features(self, A: Body, B: Body, now: float, w: float):
        """The earliest contact of A's and B's features within [0, w] after now:
        (s, feature, a, b, i, j), or None."""
        best = None
        if not A.polygon and not B.polygon:
            t = self.predict_cc(A, B, None, B.r, now, w)
            if t is not None:
                best = (t, CC, A.idx, B.idx, -1, -1)
        elif not A.polygon:
            best = self.circle_polygon(A, B, now, w, None)
        elif not B.polygon:
            best = self.circle_polygon(B, A, now, w, None)
        else:
            best = self.vertices_edges(A, B, now, w, None)
            best = self.vertices_edges(B, A, now, w, best)
        return best

    def bounds_meet(self, A: Body, B: Body, now: float, w: float) -> float | None:
        """When the bounding circles first touch within (0, w]: 0.0 when they
        overlap or touch now (within the tolerance), None when they do not
        meet (exact: bounding circles do not turn)."""
        x1, y1, u1, v1, _ = self.state_at(A, now)
        x2, y2, u2, v2, _ = self.state_at(B, now)
        args = (x1 - x2, u1 - u2, A.ax - B.ax, 0.0, 0.0, HALF_PI, y1 - y2, v1 - v2, A.ay - B.ay, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0, A.bound, B.bound)
        coef = self.cc_coefficients(args)
        tol = self.s.tol
        if coef[0] <= tol * (2.0 * (A.bound + B.bound) + tol):
            return 0.0
        return smallest_root(coef, 0.0, w)

    def bound_polygon(self, T: Body, P: Body, now: float, w: float) -> float | None:
        """T turns, polygon P does not: when T's bounding circle (radius
        T.bound about T's centre of rotation, which does not turn) first
        touches P itself (its edges, then its vertices) within (0, w]; 0.0 when
        no edge line of P has the circle beyond it by more than the tolerance
        now (overlapping, or near a corner); None when they do not meet.
        Exact: neither the circle nor P turns."""
        tol = self.s.tol
        coefs = []
        apart = False
        for j in range(len(P.verts)):
            c = self.pe_coefficients(T, P, 0.0, 0.0, T.bound, j, now)
            if c[0] > tol:
                apart = True
            coefs.append(c)
        if not apart:
            return 0.0
        meet = None
        for j in range(len(P.verts)):
            t = self.pe_first(coefs[j], T, P, 0.0, 0.0, j, now, w)
            if t is not None and (meet is None or t < meet):
                meet = t
        pt = self.centre_params(T, now)
        for v in P.verts:
            t = self.circles_first(pt, T.bound, self.circle_params(P, now, v), 0.0, w)
            if t is not None and (meet is None or t < meet):
                meet = t
        return meet

    def clear_time(self, A: Body, B: Body, now: float) -> float:
        """How long A and B surely stay more than the tolerance apart, from
        their gap g along a fixed unit axis n now (0 when not apart now).
        Along n the gap changes by (dv . n) s + (da . n) s^2/2 from the
        centres' relative motion (dv, da: the far body's velocity and
        acceleration less the near one's, so that dv . n > 0 opens the gap)
        and closes by at most spin s from the turns (spin: each turning
        body's bound times its turn rate): it stays above the tolerance for
        s below the positive root of |da . n|/2 s^2 + r s - (g - tol),
        r = spin - dv . n (clear_root).  The axis: when one of them is a
        polygon P that does not turn and the other, T, turns, each of P's
        edge normals (fixed: P does not turn; g the gap of T's vertices, or
        of its circle, beyond the edge's line), the largest of the times;
        otherwise the line of the centres (g: the smallest projection of B
        on it less the largest of A's, circles by their radius)."""
        if B.polygon and B.om == 0.0 and self.turn_rate(A) > 0.0:
            return self.clear_axes(A, B, now)
        if A.polygon and A.om == 0.0 and self.turn_rate(B) > 0.0:
            return self.clear_axes(B, A, now)
        x1, y1, u1, v1, _ = self.state_at(A, now)
        x2, y2, u2, v2, _ = self.state_at(B, now)
        dx, dy = x2 - x1, y2 - y1
        d = math.sqrt(dx * dx + dy * dy)
        if not (d > 0.0):
            return 0.0
        nx, ny = dx / d, dy / d
        hi = self.reach(A, nx, ny, now)
        lo = -self.reach(B, -nx, -ny, now)
        spin = A.bound * self.turn_rate(A) + B.bound * self.turn_rate(B)
        tol = self.s.tol
        along = self.clear_root(lo - hi - tol, spin - (nx * (u2 - u1) + ny * (v2 - v1)),
                                math.fabs(nx * (B.ax - A.ax) + ny * (B.ay - A.ay)))
        # and along the best separating axis, which may turn: the norms, |x| + |y|
        anyway = self.clear_root(self.separation(A, B, now) - tol,
                                 spin + math.fabs(u2 - u1) + math.fabs(v2 - v1),
                                 math.fabs(B.ax - A.ax) + math.fabs(B.ay - A.ay))
        return max(along, anyway)

    def reach(self, b: Body, nx: float, ny: float, now: float) -> float:
        """The largest projection of b on the unit axis (nx, ny) at now."""
        if not b.polygon:
            px, py = self.point_at(b, None, now)
            return nx * px + ny * py + b.r
        best = -math.inf
        for v in b.verts:
            px, py = self.point_at(b, v, now)
            best = max(best, nx * px + ny * py)
        return best

    def clear_axes(self, T: Body, P: Body, now: float) -> float:
        """clear_time along each edge normal of P (P does not turn, T does)."""
        _, _, u1, v1, _ = self.state_at(T, now)
        _, _, u2, v2, _ = self.state_at(P, now)
        du, dv, dax, day = u1 - u2, v1 - v2, T.ax - P.ax, T.ay - P.ay
        spin = T.bound * self.turn_rate(T)
        best = 0.0
        for j in range(len(P.verts)):
            ox, oy, off = self.edge_line(P, j, now)
            c = self.clear_root(-self.reach(T, -ox, -oy, now) - off - self.s.tol, spin - (ox * du + oy * dv),
                                math.fabs(ox * dax + oy * day))
            best = max(best, c)
        return best

    @staticmethod
    def clear_root(g: float, r: float, q: float) -> float:
        """The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
        inf when it has none (r <= 0 and q = 0)."""
        if not (g > 0.0):
            return 0.0
        if r > 0.0:
            return 2.0 * g / (r + math.sqrt(r * r + 2.0 * q * g))
        if q > 0.0:
            return (math.sqrt(r * r + 2.0 * q * g) - r) / q
        return math.inf

    @staticmethod
    def _better(best, t, feat, a, b, i, j):
        if t is not None and (best is None or t < best[0]):
            return (t, feat, a, b, i, j)
        return best

    def circle_polygon(self, C: Body, P: Body, now: float, w: float, best):
        for j in range(len(P.verts)):
            best = self._better(best, self.predict_pe(C, P, None, j, now, w), PE, C.idx, P.idx, -1, j)
        for k, v in enumerate(P.verts):
            best = self._better(best, self.predict_cc(C, P, v, 0.0, now, w), CC, C.idx, P.idx, -1, k)
        return best

    def vertices_edges(self, A: Body, B: Body, now: float, w: float, best):
        for i, v in enumerate(A.verts):
            for j in range(len(B.verts)):
                best = self._better(best, self.predict_pe(A, B, v, j, now, w, i), PE, A.idx, B.idx, i, j)
        return best

    # ---- per body -----------------------------------------------------------
    def predict_body(self, b: Body, now: float, skip: Body | None) -> None:
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if o is not skip and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if o is not skip and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)
        if b.sup >= 0 and self.s.bodies[b.sup].fixed:
            self.schedule_support(b, now)     # a carried body moves with its base: no stop, no leave of its own

    def schedule_cell(self, b: Body, now: float) -> None:
        s = self.s
        if b.large or (b.vx == 0.0 and b.vy == 0.0 and b.ax == 0.0 and b.ay == 0.0):
            return
        ulo = now - b.tb
        uhi = s.end - b.tb
        # the margin, or what the cell leaves a body added live that is wider
        # than the scene's widest (it must stay within half a cell of its cell)
        h = s.margin
        room = s.half_cell - b.bound
        if room < h:
            h = room
        best = None
        for axis in (0, 1):
            if axis == 0:
                p, v, a, i, n, origin, size = b.px, b.vx, b.ax, b.cx, s.nx, s.x0, s.cw
            else:
                p, v, a, i, n, origin, size = b.py, b.vy, b.ay, b.cy, s.ny, s.y0, s.ch
            for direction in (1, -1):
                if direction == 1:
                    if i >= n - 1:
                        continue
                    bound = origin + (i + 1) * size + h
                else:
                    if i <= 0:
                        continue
                    bound = origin + i * size - h
                c = [p - bound, v, 0.5 * a]
                if (ulo == 0.0 and c[0] * direction >= 0.0
                        and (v * direction > 0.0 or (v == 0.0 and a * direction > 0.0))):
                    # on the boundary now, or past it (cell_of's quotient and
                    # the boundary's sum origin + i size can round apart), and
                    # moving or accelerating across it: cross at once (the
                    # root finder reports no root at the interval's start,
                    # and none at all for a boundary already behind)
                    if best is None or 0.0 < best[0]:
                        best = (0.0, axis, direction)
                    continue
                lo = ulo
                for _ in range(3):
                    u = smallest_root(c, lo, uhi)
                    if u is None:
                        break
                    if (v + a * u) * direction > 0.0:
                        if best is None or u < best[0]:
                            best = (u, axis, direction)
                        break
                    lo = u
        if best is not None:
            self.push(CellEvent(b.tb + best[0], b.idx, best[1], best[2], b.stamp))

    # ---- handling events ----------------------------------------------------
    def emit_state(self, b: Body) -> None:
        self.out.write(f"S {b.idx} {_fmt(b.tb)} {_fmt(b.px)} {_fmt(b.py)} {_fmt(b.vx)} {_fmt(b.vy)} "
                       f"{_fmt(b.ang)} {_fmt(b.om)} {_fmt(b.ax)} {_fmt(b.ay)}\n")

    def contact_frame(self, t: float, feature: int, A: Body, B: Body, i: int, j: int):
        """Contact point (cx, cy) and unit normal (nx, ny) from A to B of a
        feature at t (both bodies advanced to t)."""
        vA = A.verts[i] if i >= 0 else None
        if feature == CC:
            ax_, ay_ = self.point_at(A, None, t)
            bx_, by_ = self.point_at(B, B.verts[j] if j >= 0 else None, t)
            dx, dy = bx_ - ax_, by_ - ay_
            dist = math.sqrt(dx * dx + dy * dy)
            if dist > 0.0:
                nx, ny = dx / dist, dy / dist
            else:
                nx, ny = 1.0, 0.0
            cx, cy = ax_ + A.r * nx, ay_ + A.r * ny
        else:
            px, py = self.point_at(A, vA, t)
            th = B.ang + B.verts[j].psi
            nx, ny = -math.cos(th), -math.sin(th)       # from A to B: against the edge's outward normal
            rad = A.r if vA is None else 0.0
            cx, cy = px + rad * nx, py + rad * ny
        return cx, cy, nx, ny

    @staticmethod
    def pressed(A: Body, B: Body, nx: float, ny: float) -> bool:
        """The bodies' accelerations push them together along the normal
        (n from A to B): the relative normal acceleration of the centres is
        negative.  (Centripetal terms of turning bodies are left out.)"""
        return (B.ax - A.ax) * nx + (B.ay - A.ay) * ny < 0.0

    def closing(self, A: Body, B: Body, feature: int, i: int, j: int) -> bool:
        """The gap polynomial of the contact's feature (feature, i, j as in a
        CollisionEvent: the one that predicted it), taken again at the
        contact (A's time: both advanced), predicts this contact now
        (touching_now: approaching, c1 < 0, or c2 < 0 and closing again
        before the gap exceeds its kappa).  Its second derivative has the
        centripetal terms of a turn, which `pressed` leaves out."""
        now = A.tb
        if feature == CC:
            vb = B.verts[j] if j >= 0 else None
            rb = B.r if vb is None else 0.0
            c = self.circles_gap(self.circle_params(A, now, None), A.r, self.circle_params(B, now, vb), rb)
            tol = self.s.tol
            kappa = tol * (2.0 * (A.r + rb) + tol)
        else:
            if i >= 0:
                v = A.verts[i]
                c = self.pe_coefficients(A, B, v.rho, v.beta, 0.0, j, now)
            else:
                c = self.pe_coefficients(A, B, A.orbit, A.ophase, A.r, j, now)
            kappa = self.s.tol
        return self.touching_now(c, len(c) - 1, kappa)

    @staticmethod
    def normal_speed(A: Body, B: Body, cx: float, cy: float, nx: float, ny: float) -> float:
        """Normal relative velocity (B's against A's, along n from A to B) of
        the material points at the contact: negative when approaching."""
        uax = A.vx - A.om * (cy - A.py)
        uay = A.vy + A.om * (cx - A.px)
        ubx = B.vx - B.om * (cy - B.py)
        uby = B.vy + B.om * (cx - B.px)
        return (ubx - uax) * nx + (uby - uay) * ny

    # ---- support: resting and sliding on a fixed body ------------------------
    @staticmethod
    def support_frame(B: Body, j: int):
        """Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j
        of B in the world (B does not turn)."""
        ed = B.verts[j]
        c = math.cos(B.ang)
        s = math.sin(B.ang)
        ox = c * ed.nx - s * ed.ny
        oy = s * ed.nx + c * ed.ny
        return -oy, ox, ox, oy

    @staticmethod
    def static(B: Body) -> bool:
        return B.vx == 0.0 and B.vy == 0.0 and B.ax == 0.0 and B.ay == 0.0 and B.om == 0.0

    def can_support(self, A: Body, B: Body, feature: int, i: int, j: int, vn: float) -> bool:
        """A point-edge contact of movable A on edge j of a fixed polygon B
        that does not turn (it may translate) becomes support, everything
        relative to B (docs/simulator.md, Contact model); both advanced."""
        if feature != PE or A.fixed or not B.fixed or B.om != 0.0:
            return False
        tx, ty, ox, oy = self.support_frame(B, j)
        load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        rest = self.s.rest_speed
        if not (load > 0.0) or vn >= rest or A.e * B.e * -vn >= rest:
            return False
        ed = B.verts[j]
        q = (A.px - B.px) * tx + (A.py - B.py) * ty
        if q < ed.s1 or q > ed.s2:
            return False
        # at an end of the edge (within the tolerance) and moving past it: it
        # is leaving (a support would end at once, again and again)
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        tol = self.s.tol
        if (u > 0.0 and q >= ed.s2 - tol) or (u < 0.0 and q <= ed.s1 + tol):
            return False
        if A.polygon:
            if math.fabs(A.om) * A.bound >= rest:
                return False
            return self.flat(A, B, i, j, ox, oy, load)
        return True

    def flat(self, A: Body, B: Body, i: int, j: int, ox: float, oy: float, load: float) -> bool:
        """A neighbour of A's vertex i lies on edge j's line within the face
        tolerance max(tol, rest_speed^2 / load): A rests on a face."""
        ftol = max(self.s.tol, self.s.rest_speed * self.s.rest_speed / load)
        n = len(A.verts)
        h = B.verts[j].h
        for k in ((i + n - 1) % n, (i + 1) % n):
            px, py = self.point_at(A, A.verts[k], A.tb)
            if (px - B.px) * ox + (py - B.py) * oy - h <= ftol:
                return True
        return False

    def enter_support(self, A: Body, B: Body, j: int) -> None:
        """A (advanced to now, as B) keeps only its velocity relative to B
        along the edge, stops turning, and from now on accelerates relative
        to B along the edge only."""
        tx, ty, ox, oy = self.support_frame(B, j)
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        if self.static(B):
            A.vx = u * tx
            A.vy = u * ty
        else:
            A.vx = B.vx + u * tx
            A.vy = B.vy + u * ty
        if A.polygon:
            A.om = 0.0
        A.sup = B.idx
        A.sup_edge = j
        A.tx = tx
        A.ty = ty
        A.load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        A.at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        self.slide_accel(A, u)

    def slide_accel(self, A: Body, u: float) -> None:
        """Acceleration of supported A with tangential speed u relative to
        its support B: the relative free acceleration along the edge less
        Coulomb friction mu |a_n| against the relative motion; at relative
        rest, none while friction can hold it; plus B's acceleration when B
        moves."""
        B = self.s.bodies[A.sup]
        f = A.mu * B.mu * A.load
        if u > 0.0:
            a = A.at - f
        elif u < 0.0:
            a = A.at + f
        elif A.at > f:
            a = A.at - f
        elif A.at < -f:
            a = A.at + f
        else:
            a = 0.0
        if self.static(B):
            A.ax = a * A.tx
            A.ay = a * A.ty
        else:
            A.ax = B.ax + a * A.tx
            A.ay = B.ay + a * A.ty

    def end_support(self, A: Body) -> None:
        """A's support (or carrier) ends: its free acceleration again."""
        B = self.s.bodies[A.sup]
        if not B.fixed:
            B.carry -= 1
        A.ax = A.fax
        A.ay = A.fay
        A.sup = -1
        A.sup_edge = -1

    # ---- carried: at rest on a movable body that does not turn -------------
    def can_carry(self, A: Body, B: Body, feature: int, i: int, j: int, vn: float) -> bool:
        """A point-edge contact of movable A on edge j of a movable polygon B
        that does not turn and is itself supported or carried (its motion a
        polynomial: constant acceleration) becomes carrying (docs/simulator.md,
        "Carried bodies"); both advanced.  As can_support, everything relative
        to B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn)
        < rest_speed), A's centre over the edge; and A at relative rest along
        it (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds
        it (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A
        (no loop), and |vB|^2 <= |vA|^2: taking B's velocity never raises
        A's kinetic energy.  A polygon also turns slower than rest_speed /
        bound and lies on a face (`flat`)."""
        if feature != PE or A.fixed or B.fixed or not B.polygon or B.om != 0.0 or B.sup < 0:
            return False
        bodies = self.s.bodies
        k = B.sup
        while k >= 0:
            if k == A.idx:
                return False
            k = bodies[k].sup
        tx, ty, ox, oy = self.support_frame(B, j)
        load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        rest = self.s.rest_speed
        if not (load > 0.0) or vn >= rest or A.e * B.e * -vn >= rest:
            return False
        ed = B.verts[j]
        q = (A.px - B.px) * tx + (A.py - B.py) * ty
        if q < ed.s1 or q > ed.s2:
            return False
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        if not (u * u < rest * rest):
            return False
        at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        f = A.mu * B.mu * load
        if at > f or at < -f:
            return False
        if B.vx * B.vx + B.vy * B.vy > A.vx * A.vx + A.vy * A.vy:
            return False
        if A.polygon:
            if math.fabs(A.om) * A.bound >= rest:
                return False
            return self.flat(A, B, i, j, ox, oy, load)
        return True

    def enter_carried(self, A: Body, B: Body, j: int) -> None:
        """A (advanced to now, as B) moves with B from now on: B's velocity
        and acceleration exactly (its offset from B constant), no turn."""
        tx, ty, ox, oy = self.support_frame(B, j)
        A.vx = B.vx
        A.vy = B.vy
        if A.polygon:
            A.om = 0.0
        A.sup = B.idx
        A.sup_edge = j
        A.tx = tx
        A.ty = ty
        A.load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        A.at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        A.ax = B.ax
        A.ay = B.ay
        B.carry += 1

    def leave(self, A: Body, t: float, skip: Body | None, left: list) -> None:
        """A leaves its support or carrier at t (E leave, its state: world
        velocity kept, free acceleration), then what A carries, depth-first
        (release); each appended to left with the body its prediction
        skips (predict_released)."""
        self.stats.leaves += 1
        self.rebase(A, t)
        sup, edge = A.sup, A.sup_edge
        self.end_support(A)
        A.stamp += 1
        self.out.write(f"E leave {_fmt(t)} {A.idx} {sup} -1 -1 {edge} 0 0 0 0 0\n")
        self.emit_state(A)
        left.append((A, skip))
        self.release(A, t, left)

    def release(self, B: Body, t: float, left: list) -> None:
        """B's motion changes at t: every body B carries leaves (by index,
        each with what it carries: leave), skipping B in its prediction."""
        if B.carry == 0:
            return
        for A in self.s.bodies:
            if A.sup == B.idx:
                self.leave(A, t, B, left)

    def predict_released(self, left: list, t: float) -> None:
        """Predict the bodies that left (leave), in the order they left,
        each but against the body it skips (already predicted with it)."""
        for A, skip in left:
            self.predict_body(A, t, skip)

    def support_relative(self, b: Body):
        """Supported b's motion relative to its support B along the edge, at
        b's time: (q, u, a), q the centre's coordinate along the tangent
        from B's centre, u, a its speed and acceleration."""
        B = self.s.bodies[b.sup]
        bx, by, bvx, bvy, _ = self.state_at(B, b.tb)
        q = (b.px - bx) * b.tx + (b.py - by) * b.ty
        u = (b.vx - bvx) * b.tx + (b.vy - bvy) * b.ty
        a = (b.ax - B.ax) * b.tx + (b.ay - B.ay) * b.ty
        return q, u, a

    def schedule_support(self, b: Body, now: float) -> None:
        """A supported body's stop (its tangential speed relative to the
        support reaches zero) and leave (its centre, projected on the
        edge, reaches an end) events."""
        q, u, a = self.support_relative(b)
        if u != 0.0 and a != 0.0 and (u > 0.0) != (a > 0.0):
            self.push(StopEvent(b.tb + -u / a, b.idx, b.stamp))
        ed = self.s.bodies[b.sup].verts[b.sup_edge]
        hi = self.s.end - b.tb
        s2 = self.first_crossing(q - ed.s2, u, a, 1, 0.0, hi)
        s1 = self.first_crossing(q - ed.s1, u, a, -1, 0.0, hi)
        if s1 is not None and (s2 is None or s1 < s2):
            s2 = s1
        if s2 is not None:
            self.push(LeaveEvent(b.tb + s2, b.idx, b.stamp))

    @staticmethod
    def first_crossing(p: float, v: float, a: float, direction: int, lo: float, hi: float) -> float | None:
        """The first u in [lo, hi] where p + v u + a u^2 / 2 crosses zero
        moving in the direction (+1 up, -1 down)."""
        c = [p, v, 0.5 * a]
        for _ in range(3):
            u = smallest_root(c, lo, hi)
            if u is None:
                return None
            if (v + a * u) * direction > 0.0:
                return u
            lo = u
        return None

    def contact_impulse(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                        feature: int, i: int, j: int) -> float:
        """The impulse of a contact of the feature (feature, i, j) at (cx, cy)
        with normal (nx, ny) from A to B (both advanced to the contact time):
        0.0 when the material points do not approach and are not pressed
        together, else the normal impulse j (velocities changed).  A fast
        contact is frictionless and leaves at sep = max(e |vn|, min(|vn|,
        rest_speed)); a slow pressed one hops (`hop`).  When the material
        points do not approach, the centres' accelerations do not press them
        and a body of the pair turns, the feature's gap polynomial decides
        whether they are pressed (`closing`: the turn closes the gap, which
        would otherwise predict the same contact again at once).  Never adds
        energy (docs/simulator.md, Impulse)."""
        vn = self.normal_speed(A, B, cx, cy, nx, ny)
        rest = self.s.rest_speed
        press = self.pressed(A, B, nx, ny)
        if not press and not (vn < 0.0) and (self.turn_rate(A) > 0.0 or self.turn_rate(B) > 0.0):
            press = self.closing(A, B, feature, i, j)
        if press and -vn < rest:
            return self.hop(A, B, cx, cy, nx, ny, vn)
        imp = 0.0
        if vn < 0.0:
            ran = (cx - A.px) * ny - (cy - A.py) * nx
            rbn = (cx - B.px) * ny - (cy - B.py) * nx
            k = A.inv_m + B.inv_m + A.inv_i * ran * ran + B.inv_i * rbn * rbn
            e = A.e * B.e
            sep = max(e * -vn, min(-vn, rest))
            imp = (sep - vn) / k
            A.vx = A.vx - imp * A.inv_m * nx
            A.vy = A.vy - imp * A.inv_m * ny
            A.om = A.om - imp * A.inv_i * ran
            B.vx = B.vx + imp * B.inv_m * nx
            B.vy = B.vy + imp * B.inv_m * ny
            B.om = B.om + imp * B.inv_i * rbn
        return imp

    def hop(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float, vn: float) -> float:
        """A slow pressed contact (pressed, -vn < rest_speed): the bodies
        separate at hop along n, paid from their relative motion at the
        contact, so the pair's energy stays what it was: hop = rest_speed
        when kn Q pays it, else sqrt(kn Q), but at least rest_speed / 32 (a
        pair nearly at rest on each other: the energy that adds is paid from
        the pair's common motion, `pay_floor`, else the hop sets `unpaid`).  With u = (vn, vt) the relative velocity of the material points
        in the frame (n, t), t = (-ny, nx), and K the contact's 2x2 inverse
        mass matrix (kn, knt; knt, kt), the pair's energy relative to its
        centre is Q / 2, Q = u . K^-1 u; the new relative velocity is
        (hop, x) with the same Q (x on vt's side of knt hop / kn), through
        the impulse P = K^-1 (u' - u) (normal part jn, tangential jt).
        Returns jn."""
        tx, ty = -ny, nx
        uax = A.vx - A.om * (cy - A.py)
        uay = A.vy + A.om * (cx - A.px)
        ubx = B.vx - B.om * (cy - B.py)
        uby = B.vy + B.om * (cx - B.px)
        vt = (ubx - uax) * tx + (uby - uay) * ty
        ran = (cx - A.px) * ny - (cy - A.py) * nx
        rbn = (cx - B.px) * ny - (cy - B.py) * nx
        rat = (cx - A.px) * ty - (cy - A.py) * tx
        rbt = (cx - B.px) * ty - (cy - B.py) * tx
        m = A.inv_m + B.inv_m
        kn = m + A.inv_i * ran * ran + B.inv_i * rbn * rbn
        kt = m + A.inv_i * rat * rat + B.inv_i * rbt * rbt
        knt = A.inv_i * ran * rat + B.inv_i * rbn * rbt
        det = kn * kt - knt * knt
        q = (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det
        cap = kn * q
        rest = self.s.rest_speed
        floor = 0.03125 * rest
        if cap >= rest * rest:
            hop = rest
        elif cap >= floor * floor:
            hop = math.sqrt(cap)
        else:
            hop = floor
        d = det * (cap - hop * hop)
        root = math.sqrt(d) if d > 0.0 else 0.0
        mid = knt * hop
        if vt * kn >= mid:
            x = (mid + root) / kn
        else:
            x = (mid - root) / kn
        dn = hop - vn
        dt = x - vt
        jn = (kt * dn - knt * dt) / det
        jt = (kn * dt - knt * dn) / det
        px = jn * nx + jt * tx
        py = jn * ny + jt * ty
        A.vx = A.vx - px * A.inv_m
        A.vy = A.vy - py * A.inv_m
        A.om = A.om - (jn * ran + jt * rat) * A.inv_i
        B.vx = B.vx + px * B.inv_m
        B.vy = B.vy + py * B.inv_m
        B.om = B.om + (jn * rbn + jt * rbt) * B.inv_i
        if cap < floor * floor and not self.pay_floor(A, B, (floor * floor - cap) / kn):
            self.unpaid = True
        return jn

    @staticmethod
    def pay_floor(A: Body, B: Body, need: float) -> bool:
        """A hop at the floor speed adds dE = need / 2 to the pair's energy
        (need = (floor^2 - cap) / kn): it is paid from the pair's common
        motion, the velocity V of its centre of mass (mass M), which an
        equal change of both velocities scales by f = sqrt(1 - need / (M
        V^2)) (M V^2 f^2 / 2 = M V^2 / 2 - dE) and which leaves their relative
        motion, hence the hop, untouched.  Not when a body of the pair is
        held (fixed, or a sleeper held as fixed) or the common motion cannot
        pay it (M V^2 <= need): False, the hop then adds dE (`unpaid`)."""
        if A.inv_m == 0.0 or B.inv_m == 0.0:
            return False
        ma = 1.0 / A.inv_m
        mb = 1.0 / B.inv_m
        mass = ma + mb
        vx = (ma * A.vx + mb * B.vx) / mass
        vy = (ma * A.vy + mb * B.vy) / mass
        e2 = mass * (vx * vx + vy * vy)
        if not (e2 > need):
            return False
        f = math.sqrt(1.0 - need / e2)
        dx = vx * f - vx
        dy = vy * f - vy
        A.vx = A.vx + dx
        A.vy = A.vy + dy
        B.vx = B.vx + dx
        B.vy = B.vy + dy
        return True

    @staticmethod
    def along(b: Body, nx: float, ny: float) -> float:
        """n . t of a supported body's edge tangent t (0 for a fixed body)."""
        if b.sup < 0:
            return 0.0
        return nx * b.tx + ny * b.ty

    def held(self, A: Body, B: Body, nx: float, ny: float, vn: float) -> bool:
        """A slow contact of bodies held on their supports: each supported
        (on a fixed body: a carried body is not) or fixed, approaching (vn < 0) slower than rest_speed, not pressed,
        and an impulse along their edges can change vn (kh > 0)."""
        bodies = self.s.bodies
        if not ((A.fixed or (A.sup >= 0 and bodies[A.sup].fixed)) and (B.fixed or (B.sup >= 0 and bodies[B.sup].fixed))):
            return False
        if not (vn < 0.0) or not (-vn < self.s.rest_speed) or self.pressed(A, B, nx, ny):
            return False
        ka = self.along(A, nx, ny)
        kb = self.along(B, nx, ny)
        return A.inv_m * ka * ka + B.inv_m * kb * kb > 0.0

    def held_impulse(self, A: Body, B: Body, nx: float, ny: float, vn: float) -> float:
        """The normal impulse j of a held contact (held): each supported body
        takes only its part along its support's edge, dv = -+ j (n . t) t / m,
        and keeps its support (the support's reaction takes the rest and does
        no work); the normal speed leaves at sep = max(e |vn|, min(|vn|,
        rest_speed)) = |vn| (slow), through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.
        The friction of each is set again for its new speed relative to its
        support (slide_accel; support_relative: the support may move)."""
        ka = self.along(A, nx, ny)
        kb = self.along(B, nx, ny)
        k = A.inv_m * ka * ka + B.inv_m * kb * kb
        e = A.e * B.e
        sep = max(e * -vn, min(-vn, self.s.rest_speed))
        imp = (sep - vn) / k
        if A.sup >= 0:
            d = imp * A.inv_m * ka
            A.vx = A.vx - d * A.tx
            A.vy = A.vy - d * A.ty
            self.slide_accel(A, self.support_relative(A)[1])
        if B.sup >= 0:
            d = imp * B.inv_m * kb
            B.vx = B.vx + d * B.tx
            B.vy = B.vy + d * B.ty
            self.slide_accel(B, self.support_relative(B)[1])
        return imp

    # ---- sleeping islands ---------------------------------------------------
    def grounded(self, G: Body) -> bool:
        """A body others can fall asleep on: asleep, or fixed and unmoving."""
        return G.asleep or (G.fixed and self.static(G))

    def at_rest(self, A: Body) -> bool:
        """A body supported by an unmoving body, slower than rest_speed along
        its edge, that static friction would hold there (|at| <= mu load, as
        in slide_accel at u = 0; on a level frictionless edge at = 0): it
        stays where it is.  On a moving support: never (it does not sleep);
        nor on a movable one (carried: grounded is false while it carries)."""
        B = self.s.bodies[A.sup]
        if not self.grounded(B):
            return False
        u = A.vx * A.tx + A.vy * A.ty
        if not (u * u < self.s.rest_speed * self.s.rest_speed):
            return False
        f = A.mu * B.mu * A.load
        return not (A.at > f) and not (A.at < -f)

    def can_sleep(self, M: Body, G: Body, ev: CollisionEvent, nx: float, ny: float, vn: float) -> bool:
        """Awake movable M, one body of the collision ev with grounded G (both
        advanced; (nx, ny) the contact's unit normal from ev.a to ev.b, vn its
        normal speed), falls asleep on G: M's free acceleration presses it
        onto G (load > 0), the contact is slow (vn < rest_speed and
        eM eG (-vn) < rest_speed), M's speed across the normal is below
        rest_speed, and a polygon M turns slower than rest_speed / bound and
        lies on a face: a vertex-edge contact with a neighbour of the vertex
        on the edge's line (`flat`, whichever body has the vertex)."""
        if M.fixed or M.asleep or not self.grounded(G):
            return False
        if M.idx == ev.a:
            mx, my = nx, ny
        else:
            mx, my = -nx, -ny
        rest = self.s.rest_speed
        load = M.fax * mx + M.fay * my
        if not (load > 0.0) or vn >= rest or M.e * G.e * -vn >= rest:
            return False
        ut = M.vy * mx - M.vx * my
        if ut * ut >= rest * rest:
            return False
        if M.polygon:
            if math.fabs(M.om) * M.bound >= rest or ev.feature != PE or ev.i < 0:
                return False
            bodies = self.s.bodies
            return self.flat(bodies[ev.a], bodies[ev.b], ev.i, ev.j, -nx, -ny, load)
        return True

    def sleeper_impulse(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                        feature: int, i: int, j: int) -> float:
        """The impulse of a contact of A and B, one of them (S) asleep: first
        with S held as if fixed (its 1/m and 1/I zero); when that impulse
        would change the normal speed of S's material point by less than
        rest_speed, j (1/mS + (rS x n)^2 / IS) < rest_speed, it stands (S
        stays asleep, unchanged: a gentle touch); else the other body's
        velocity is restored and the full impulse is applied (S moves:
        `jolted`, its island wakes).  When the other body is fixed (it moves
        or turns: a sleeper is never predicted against an unmoving one) S
        cannot be held (the pair would have no mass): the full impulse at
        once.  Returns the impulse applied."""
        S = A if A.asleep else B
        M = B if A.asleep else A
        if M.fixed:
            return self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)
        vx, vy, om = M.vx, M.vy, M.om
        inv_m, inv_i = S.inv_m, S.inv_i
        S.inv_m = 0.0
        S.inv_i = 0.0
        self.unpaid = False
        imp = self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)
        S.inv_m = inv_m
        S.inv_i = inv_i
        rsn = (cx - S.px) * ny - (cy - S.py) * nx
        if imp * (S.inv_m + S.inv_i * rsn * rsn) < self.s.rest_speed and not self.unpaid:
            return imp
        M.vx, M.vy, M.om = vx, vy, om
        return self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)

    @staticmethod
    def jolted(S: Body) -> bool:
        """A sleeper an impulse has set moving."""
        return S.vx != 0.0 or S.vy != 0.0 or S.om != 0.0

    def handle_sleep(self, A: Body, G: Body, t: float) -> None:
        """A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0)
        in G's island, or in a new one numbered A's index when G is fixed.
        Its awake neighbours are predicted against it again."""
        self.stats.sleeps += 1
        if A.sup >= 0:
            self.end_support(A)
        A.vx = 0.0
        A.vy = 0.0
        A.om = 0.0
        A.ax = 0.0
        A.ay = 0.0
        A.asleep = True
        A.island = G.island if G.asleep else A.idx
        A.stamp += 1
        self.out.write(f"E sleep {_fmt(t)} {A.idx} {G.idx} -1 -1 {A.island} 0 0 0 0 0\n")
        self.emit_state(A)
        left = []
        self.release(A, t, left)
        self.predict_body(A, t, None)
        self.predict_released(left, t)

    def handle_wake(self, S: Body, t: float) -> None:
        """S's island wakes at t: every member (by index) gets its free
        acceleration back, then fresh predictions (a pair of members once)."""
        self.stats.wakes += 1
        island = S.island
        self.out.write(f"E wake {_fmt(t)} {S.idx} -1 -1 -1 {island} 0 0 0 0 0\n")
        bodies = self.s.bodies
        for b in bodies:
            if b.asleep and b.island == island:
                self.rebase(b, t)
                b.asleep = False
                b.ax = b.fax
                b.ay = b.fay
                b.stamp += 1
                self.emit_state(b)
        for b in bodies:
            if b.island == island:
                self.predict_woken(b, t, island)
        for b in bodies:
            if b.island == island:
                b.island = -1

    def predict_woken(self, b: Body, now: float, island: int) -> None:
        """predict_body for a member of a waking island: a pair of two
        members is predicted by the one with the smaller index."""
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if not (o.island == island and o.idx < b.idx) and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if not (o.island == island and o.idx < b.idx):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)

    # ---- simultaneous contacts: a contact met again at one instant ---------
    def touch(self, t: float, a: int, b: int, feature: int, i: int, j: int) -> None:
        """Count a contact handled at t (an E collision or E support line)."""
        if t != self.touched_t:
            self.touched_t = t
            self.touched = []
        for c in self.touched:
            if c[0] == a and c[1] == b and c[2] == feature and c[3] == i and c[4] == j:
                c[5] += 1
                return
        self.touched.append([a, b, feature, i, j, 1])

    def repeated(self, ev: CollisionEvent) -> bool:
        """The collision's contact (a, b, feature, i, j) was handled
        CLUSTER_REPEATS times already at this instant: other contacts keep
        undoing its impulse (a settling pile meets one contact up to 32
        times at one instant and goes on: ball-pit.json)."""
        if ev.t != self.touched_t:
            return False
        for c in self.touched:
            if c[0] == ev.a and c[1] == ev.b and c[2] == ev.feature and c[3] == ev.i and c[4] == ev.j:
                return c[5] >= CLUSTER_REPEATS
        return False

    @staticmethod
    def joins(b: Body) -> bool:
        """A body that links a cluster's contacts: movable and awake (fixed
        bodies and sleepers are held: the cluster ends at them)."""
        return not b.fixed and not b.asleep

    def cluster(self, ev: CollisionEvent) -> list:
        """The contacts handled at this instant (touched, in the order first
        handled) that reach the collision's bodies through bodies that join,
        each as (A, B, feature, i, j)."""
        bodies = self.s.bodies
        inside = []
        for x in (ev.a, ev.b):
            if self.joins(bodies[x]):
                inside.append(x)
        grow = True
        while grow:
            grow = False
            for c in self.touched:
                if c[0] in inside or c[1] in inside:
                    for x in (c[0], c[1]):
                        if x not in inside and self.joins(bodies[x]):
                            inside.append(x)
                            grow = True
        out = []
        for c in self.touched:
            if c[0] in inside or c[1] in inside:
                out.append((bodies[c[0]], bodies[c[1]], c[2], c[3], c[4]))
        return out

    def part(self, b: Body) -> int:
        """b's part in a cluster's solve: HELD (fixed or asleep), SLIDER
        (supported on a fixed body: it moves along the edge only, as in
        held_impulse) or FREE."""
        if b.fixed or b.asleep:
            return HELD
        if b.sup >= 0 and self.s.bodies[b.sup].fixed:
            return SLIDER
        return FREE

    def give(self, b: Body, nx: float, ny: float, rn: float) -> float:
        """How much a unit impulse along n at the contact (rn: the contact's
        arm across n) changes b's normal speed there."""
        part = self.part(b)
        if part == HELD:
            return 0.0
        if part == SLIDER:
            k = nx * b.tx + ny * b.ty
            return b.inv_m * k * k
        return b.inv_m + b.inv_i * rn * rn

    def nudge(self, b: Body, j: float, nx: float, ny: float, rn: float) -> None:
        """An impulse j along n on b at the contact (rn its arm across n)."""
        part = self.part(b)
        if part == HELD:
            return
        if part == SLIDER:
            d = j * b.inv_m * (nx * b.tx + ny * b.ty)
            b.vx = b.vx + d * b.tx
            b.vy = b.vy + d * b.ty
            return
        b.vx = b.vx + j * b.inv_m * nx
        b.vy = b.vy + j * b.inv_m * ny
        b.om = b.om + j * b.inv_i * rn

    def sweeps(self, rows: list, acc: list, target: list) -> None:
        """Sequential impulses over the cluster's contacts (rows, in order):
        each contact's accumulated normal impulse acc[k] moves so that its
        normal speed becomes target[k], but never below zero (a contact only
        pushes); sweep after sweep until no impulse of a sweep changed a
        normal speed by more than CLUSTER_TOL rest_speed, at most
        CLUSTER_SWEEPS sweeps."""
        tol = CLUSTER_TOL * self.s.rest_speed
        for _ in range(CLUSTER_SWEEPS):
            big = 0.0
            for k in range(len(rows)):
                A, B, cx, cy, nx, ny, ran, rbn, kn = rows[k]
                if not (kn > 0.0):
                    continue
                vn = self.normal_speed(A, B, cx, cy, nx, ny)
                new = acc[k] + (target[k] - vn) / kn
                if new < 0.0:
                    new = 0.0
                dj = new - acc[k]
                acc[k] = new
                self.nudge(A, -dj, nx, ny, ran)
                self.nudge(B, dj, nx, ny, rbn)
                ch = math.fabs(dj) * kn
                if ch > big:
                    big = ch
            if big <= tol:
                return

    @staticmethod
    def kinetic(movers: list) -> float:
        """The kinetic energy of the bodies (linear, and turning where 1/I > 0)."""
        e = 0.0
        for b in movers:
            e = e + 0.5 * (b.vx * b.vx + b.vy * b.vy) / b.inv_m
            if b.inv_i > 0.0:
                e = e + 0.5 * b.om * b.om / b.inv_i
        return e

    @staticmethod
    def velocities(movers: list) -> list:
        return [(b.vx, b.vy, b.om) for b in movers]

    @staticmethod
    def set_velocities(movers: list, vs: list) -> None:
        for k in range(len(movers)):
            movers[k].vx, movers[k].vy, movers[k].om = vs[k]

    @staticmethod
    def mix(movers: list, v1: list, budget: float) -> float:
        """The largest mu in [0, 1] for which the bodies' velocities
        v1 + mu (v - v1) (v: theirs now, v1 as given; the kinetic energy
        at v1 at most budget) have a kinetic energy at most budget: with a
        the energy of the change, b the cross term and e1 the energy at v1,
        a mu^2 + b mu <= budget - e1."""
        a = 0.0
        b = 0.0
        e1 = 0.0
        for k in range(len(movers)):
            m = movers[k]
            vx, vy, om = v1[k]
            dx = m.vx - vx
            dy = m.vy - vy
            a = a + 0.5 * (dx * dx + dy * dy) / m.inv_m
            b = b + (vx * dx + vy * dy) / m.inv_m
            e1 = e1 + 0.5 * (vx * vx + vy * vy) / m.inv_m
            if m.inv_i > 0.0:
                dw = m.om - om
                a = a + 0.5 * dw * dw / m.inv_i
                b = b + om * dw / m.inv_i
                e1 = e1 + 0.5 * om * om / m.inv_i
        if not (a > 0.0):
            return 1.0
        spare = budget - e1
        if spare < 0.0:
            spare = 0.0
        root = math.sqrt(b * b + 4.0 * a * spare)
        if b > 0.0:
            mu = 2.0 * spare / (b + root)
        else:
            mu = (root - b) / (2.0 * a)
        return mu if mu < 1.0 else 1.0

    def pressing_contact(self, row: tuple, c: tuple) -> bool:
        """A contact of the cluster that must separate: its bodies' accelerations
        press them together (pressed) or, a body turning, its gap closes now
        (closing), as contact_impulse decides."""
        A, B, cx, cy, nx, ny, ran, rbn, kn = row
        if self.pressed(A, B, nx, ny):
            return True
        if self.turn_rate(A) > 0.0 or self.turn_rate(B) > 0.0:
            return self.closing(A, B, c[2], c[3], c[4])
        return False

    def solve_cluster(self, cs: list, t: float):
        """The cluster's joint impulses (docs/simulator.md, "Contact model:
        simultaneous contacts"): inelastic sequential impulses (target
        normal speed 0: kinetic energy e1); then the pressed contacts
        separate at rest_speed (the others at CLUSTER_APART rest_speed): sequential
        impulses from v1 (v2), taken when they cost no more than e1; else
        the same from the movers at rest (vs, energy es), mixed towards v2
        as far as e1 pays (mix) when es <= e1, else vs scaled to energy e1.
        Returns (rows, acc, movers, saved): each contact's frame and its
        normal impulse, the bodies that move and their velocities before."""
        rows = []
        for A, B, feature, i, j in cs:
            cx, cy, nx, ny = self.contact_frame(t, feature, A, B, i, j)
            ran = (cx - A.px) * ny - (cy - A.py) * nx
            rbn = (cx - B.px) * ny - (cy - B.py) * nx
            kn = self.give(A, nx, ny, ran) + self.give(B, nx, ny, rbn)
            rows.append((A, B, cx, cy, nx, ny, ran, rbn, kn))
        movers = []
        for A, B, _, _, _ in cs:
            for b in (A, B):
                if self.part(b) != HELD and b not in movers:
                    movers.append(b)
        saved = self.velocities(movers)
        n = len(rows)
        acc = [0.0] * n
        self.sweeps(rows, acc, [0.0] * n)
        e1 = self.kinetic(movers)
        target = [0.0] * n
        for k in range(n):
            if self.pressing_contact(rows[k], cs[k]):
                target[k] = self.s.rest_speed
            else:
                target[k] = CLUSTER_APART * self.s.rest_speed
        self.sweeps(rows, acc, target)
        if self.kinetic(movers) <= e1:
            return rows, acc, movers, saved
        v2 = self.velocities(movers)
        acc2 = acc
        for b in movers:
            if b.sup >= 0 and self.s.bodies[b.sup].fixed:
                u = self.support_relative(b)[1]
                b.vx = b.vx - u * b.tx
                b.vy = b.vy - u * b.ty
            else:
                b.vx = 0.0
                b.vy = 0.0
            b.om = 0.0
        acc = [0.0] * n
        self.sweeps(rows, acc, target)
        es = self.kinetic(movers)
        if es <= e1:
            vs = self.velocities(movers)
            self.set_velocities(movers, v2)
            mu = self.mix(movers, vs, e1)
            for k in range(len(movers)):
                b = movers[k]
                vx, vy, om = vs[k]
                b.vx = vx + mu * (b.vx - vx)
                b.vy = vy + mu * (b.vy - vy)
                b.om = om + mu * (b.om - om)
            for k in range(n):
                acc[k] = acc[k] + mu * (acc2[k] - acc[k])
            return rows, acc, movers, saved
        f = math.sqrt(e1 / es)
        for b in movers:
            b.vx = f * b.vx
            b.vy = f * b.vy
            b.om = f * b.om
        for k in range(n):
            acc[k] = f * acc[k]
        return rows, acc, movers, saved

    def jolted_sleeper(self, rows: list, acc: list) -> Body | None:
        """The first sleeper (in the contacts' order) whose held impulses,
        summed, would change its material points' normal speed by at least
        rest_speed (as a touch that is not gentle, sleeper_impulse); None."""
        for k in range(len(rows)):
            for S in (rows[k][0], rows[k][1]):
                if not S.asleep:
                    continue
                total = 0.0
                for q in range(len(rows)):
                    A, B, cx, cy, nx, ny, ran, rbn, kn = rows[q]
                    if A is S or B is S:
                        rsn = ran if A is S else rbn
                        total = total + acc[q] * (S.inv_m + S.inv_i * rsn * rsn)
                if total >= self.s.rest_speed:
                    return S
        return None

    def wedged(self, M: Body, rows: list) -> Body | None:
        """The grounded body awake M falls asleep on after its cluster's
        solve, or None: M slower than rest_speed (a polygon also turning
        slower than rest_speed / bound) and its free acceleration held by
        what it rests on (holds): the outward normal of its support when it
        is supported on an unmoving fixed body, and each contact of the
        cluster with a grounded body (pushing M along -m, m the contact's
        normal from M).  It falls asleep on its support, else on the first
        grounded body of those contacts."""
        rest = self.s.rest_speed
        if not (M.vx * M.vx + M.vy * M.vy < rest * rest):
            return None
        if M.polygon and not (math.fabs(M.om) * M.bound < rest):
            return None
        pushes = []
        G = None
        if M.sup >= 0:
            S = self.s.bodies[M.sup]
            if not (S.fixed and self.grounded(S)):
                return None
            _, _, ox, oy = self.support_frame(S, M.sup_edge)
            pushes.append((ox, oy))
            G = S
        for A, B, cx, cy, nx, ny, ran, rbn, kn in rows:
            if A is M and self.grounded(B):
                pushes.append((-nx, -ny))
                if G is None:
                    G = B
            if B is M and self.grounded(A):
                pushes.append((nx, ny))
                if G is None:
                    G = A
        if G is None or not self.holds(pushes, -M.fax, -M.fay):
            return None
        return G

    @staticmethod
    def holds(pushes: list, dx: float, dy: float) -> bool:
        """The pushes (unit directions) can make (dx, dy) with non-negative
        weights through one push (its direction within HOLD_TOL rad of d) or
        two: d = a p + b q, a >= 0, b >= 0 (Cramer, p x q != 0), pairs in
        order.  (dx, dy) = (0, 0) needs nothing."""
        if dx == 0.0 and dy == 0.0:
            return True
        for px, py in pushes:
            dot = px * dx + py * dy
            if dot > 0.0 and math.fabs(px * dy - py * dx) <= HOLD_TOL * dot:
                return True
        n = len(pushes)
        for k in range(n):
            px, py = pushes[k]
            for q in range(k + 1, n):
                qx, qy = pushes[q]
                det = px * qy - py * qx
                if det == 0.0:
                    continue
                a = (dx * qy - dy * qx) / det
                b = (px * dy - py * dx) / det
                if a >= 0.0 and b >= 0.0:
                    return True
        return False

    def handle_cluster(self, ev: CollisionEvent) -> None:
        """A contact met again at the instant it was handled (repeated):
        the contacts handled at this instant that reach it (cluster) are
        solved together (solve_cluster); a sleeper the solve would jolt
        wakes and the solve is made again with it moving.  Then an E
        collision line per contact (its normal impulse), each followed by
        the states of its moving bodies not written yet (settle); what a
        body whose velocity changed carries leaves; those slow enough fall
        asleep (wedged), and the others are predicted again."""
        t = ev.t
        self.touch(t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        while True:
            cs = self.cluster(ev)
            for A, B, _, _, _ in cs:
                self.rebase(A, t)
                self.rebase(B, t)
            rows, acc, movers, saved = self.solve_cluster(cs, t)
            S = self.jolted_sleeper(rows, acc)
            if S is None:
                break
            for k in range(len(movers)):
                movers[k].vx, movers[k].vy, movers[k].om = saved[k]
            self.handle_wake(S, t)
        written = []
        for k in range(len(rows)):
            A, B, cx, cy, nx, ny, ran, rbn, kn = rows[k]
            _, _, feature, i, j = cs[k]
            self.stats.collisions += 1
            self.out.write(f"E collision {_fmt(t)} {A.idx} {B.idx} {feature} {i} {j} {_fmt(cx)} {_fmt(cy)} "
                           f"{_fmt(nx)} {_fmt(ny)} {_fmt(acc[k])}\n")
            self.contacts.append(Contact(t, A.idx, B.idx, feature, i, j, cx, cy, nx, ny, acc[k], False))
            for b in (A, B):
                if b in movers and b not in written:
                    written.append(b)
                    self.settle(b)
        left = []
        for k in range(len(movers)):
            b = movers[k]
            if b.vx != saved[k][0] or b.vy != saved[k][1] or b.om != saved[k][2]:
                self.release(b, t, left)
        done = []
        grow = True
        while grow:
            grow = False
            for b in movers:
                if not b.asleep:
                    G = self.wedged(b, rows)
                    if G is not None:
                        self.handle_sleep(b, G, t)
                        done.append(b)
                        grow = True
        for b in movers:
            if not b.asleep:
                self.predict_apart(b, t, done)
                done.append(b)
        self.predict_released(left, t)

    def settle(self, b: Body) -> None:
        """A body of a solved cluster after its impulses: one sliding on a
        fixed body gets its friction again for its new speed (as
        held_impulse), a carried one leaves its base's motion (end_support:
        it is not held); a new stamp, its state."""
        if b.sup >= 0:
            if self.s.bodies[b.sup].fixed:
                self.slide_accel(b, self.support_relative(b)[1])
            else:
                self.end_support(b)
        b.stamp += 1
        self.emit_state(b)

    def predict_apart(self, b: Body, now: float, done: list) -> None:
        """predict_body for a body of a solved cluster, but against the
        bodies in done (predicted already, or fallen asleep and predicted
        against it by handle_sleep)."""
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if o not in done and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if o not in done and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)
        if b.sup >= 0 and self.s.bodies[b.sup].fixed:
            self.schedule_support(b, now)

    # ---- event handlers: one per kind -------------------------------------
    def handle_collision(self, ev: CollisionEvent) -> None:
        t = ev.t
        A = self.s.bodies[ev.a]
        B = self.s.bodies[ev.b]
        if self.repeated(ev):
            self.handle_cluster(ev)
            return
        self.rebase(A, t)
        self.rebase(B, t)
        cx, cy, nx, ny = self.contact_frame(t, ev.feature, A, B, ev.i, ev.j)
        vn = self.normal_speed(A, B, cx, cy, nx, ny)
        if self.can_support(A, B, ev.feature, ev.i, ev.j, vn) or self.can_carry(A, B, ev.feature, ev.i, ev.j, vn):
            self.handle_support(ev, A, B, cx, cy, nx, ny, vn)
            return
        if self.can_sleep(A, B, ev, nx, ny, vn):
            self.handle_sleep(A, B, t)
            return
        if self.can_sleep(B, A, ev, nx, ny, vn):
            self.handle_sleep(B, A, t)
            return
        self.stats.collisions += 1
        # a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
        # on it); a gentle touch leaves it asleep, a real impulse wakes its island;
        # a slow contact of bodies held on their supports keeps them there
        held = self.held(A, B, nx, ny, vn)
        if held:
            imp = self.held_impulse(A, B, nx, ny, vn)
        elif A.asleep or B.asleep:
            imp = self.sleeper_impulse(A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
        else:
            imp = self.contact_impulse(A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
        if imp != 0.0 and not held:
            if A.asleep and self.jolted(A):
                self.handle_wake(A, t)
            if B.asleep and self.jolted(B):
                self.handle_wake(B, t)
            if A.sup >= 0:
                self.end_support(A)
            if B.sup >= 0:
                self.end_support(B)
        self.out.write(f"E collision {_fmt(t)} {A.idx} {B.idx} {ev.feature} {ev.i} {ev.j} {_fmt(cx)} {_fmt(cy)} "
                       f"{_fmt(nx)} {_fmt(ny)} {_fmt(imp)}\n")
        self.contacts.append(Contact(t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, False))
        self.touch(t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        # a sleeper still asleep is unchanged; the other is predicted again,
        # against it too unless they only grazed (zero impulse: the graze
        # would be found again at once; a later change of the other's motion
        # predicts the pair again).  After a gentle touch (an impulse that
        # left the sleeper asleep) the other leaves and may fall back onto
        # it: that pair must stay predicted, or it passes through the sleeper
        for b in (A, B):
            if not b.fixed and not b.asleep:
                b.stamp += 1
                self.emit_state(b)
        # an impulse changes the motion of what it hit: what they carried leaves
        left = []
        if imp != 0.0:
            for b in (A, B):
                if not b.fixed:
                    self.release(b, t, left)
        if not A.fixed and not A.asleep:
            self.predict_body(A, t, B if (B.asleep and imp == 0.0) else None)
        if not B.fixed and not B.asleep:
            self.predict_body(B, t, A if ((not A.fixed and not A.asleep) or (A.asleep and imp == 0.0)) else None)
        self.predict_released(left, t)

    def handle_support(self, ev: CollisionEvent, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                       vn: float) -> None:
        """A collision that ends in support (called by handle_collision)."""
        self.stats.supports += 1
        imp = -vn / A.inv_m
        if B.fixed:
            self.enter_support(A, B, ev.j)
        else:
            self.enter_carried(A, B, ev.j)
        self.out.write(f"E support {_fmt(ev.t)} {A.idx} {B.idx} {ev.feature} {ev.i} {ev.j} {_fmt(cx)} {_fmt(cy)} "
                       f"{_fmt(nx)} {_fmt(ny)} {_fmt(imp)}\n")
        self.contacts.append(Contact(ev.t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, True))
        self.touch(ev.t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        if self.at_rest(A):
            self.handle_sleep(A, B, ev.t)
            return
        A.stamp += 1
        self.emit_state(A)
        left = []
        self.release(A, ev.t, left)
        self.predict_body(A, ev.t, None)
        self.predict_released(left, ev.t)

    def handle_stop(self, ev: StopEvent) -> None:
        """Sliding stops: velocity exactly the support's (zero when it does
        not move), then rest or slide back."""
        self.stats.stops += 1
        A = self.s.bodies[ev.body]
        self.rebase(A, ev.t)
        B = self.s.bodies[A.sup]
        if self.static(B):
            A.vx = 0.0
            A.vy = 0.0
        else:
            _, _, A.vx, A.vy, _ = self.state_at(B, ev.t)
        self.slide_accel(A, 0.0)
        self.out.write(f"E stop {_fmt(ev.t)} {A.idx} {A.sup} -1 -1 {A.sup_edge} 0 0 0 0 0\n")
        if self.at_rest(A):
            self.handle_sleep(A, self.s.bodies[A.sup], ev.t)
            return
        A.stamp += 1
        self.emit_state(A)
        left = []
        self.release(A, ev.t, left)
        self.predict_body(A, ev.t, None)
        self.predict_released(left, ev.t)

    def handle_leave(self, ev: LeaveEvent) -> None:
        """The support's edge ends under the body: free motion again."""
        left = []
        self.leave(self.s.bodies[ev.body], ev.t, None, left)
        self.predict_released(left, ev.t)

    def handle_input(self, ev: InputEvent) -> None:
        self.stats.inputs += 1
        t = ev.t
        inp = self.s.inputs[ev.k]
        body = self.s.bodies[inp.body]
        if body.gone:
            raise SimError(f"input {ev.k}: body {body.idx} was removed before t = {_fmt(t)}")
        if body.asleep:
            self.handle_wake(body, t)      # any input on a sleeper wakes its island first
        self.rebase(body, t)
        if inp.mode == REMOVE:
            self.remove(body, ev.k, t)
            return
        if body.fixed:
            self.drive(body, ev.k, t, inp.vx, inp.vy)
            return
        if inp.mode == TELEPORT:
            o = self.overlapping(body, inp.vx, inp.vy, t)
            if o >= 0:
                raise SimError(f"input {ev.k}: body {body.idx} teleported to ({_fmt(inp.vx)}, {_fmt(inp.vy)}) at "
                               f"t = {_fmt(t)} would overlap body {o}")
        if body.sup >= 0:
            self.end_support(body)
        if inp.mode == SET_VELOCITY:
            body.vx, body.vy = inp.vx, inp.vy
        elif inp.mode == ADD_VELOCITY:
            body.vx, body.vy = body.vx + inp.vx, body.vy + inp.vy
        elif inp.mode == IMPULSE:
            body.vx, body.vy = body.vx + inp.vx * body.inv_m, body.vy + inp.vy * body.inv_m
        else:
            body.px, body.py = inp.vx, inp.vy
            if not body.large:          # a large body is in no cell: every body checks it
                self.cell_remove(body)
                body.cx, body.cy = self.cell_of(body.px, body.py)
                self.cell_add(body)
        body.stamp += 1
        self.out.write(f"E input {_fmt(t)} {body.idx} -1 -1 {ev.k} -1 0 0 0 0 0\n")
        self.emit_state(body)
        left = []
        self.release(body, t, left)
        self.predict_body(body, t, None)
        self.predict_released(left, t)

    def remove(self, body: Body, k: int, t: float) -> None:
        """Input k removes the body (based at t): it stops where it is (v, a,
        w zero), leaves the grid, its stamp changes (its queued events go
        stale) and it is never predicted again; bodies it supported leave."""
        body.vx = body.vy = body.ax = body.ay = body.fax = body.fay = body.om = 0.0
        if body.sup >= 0:
            self.end_support(body)
        body.gone = True
        body.stamp += 1
        if body.large:
            self.unplace_large(body)
        else:
            self.cell_remove(body)
        self.out.write(f"E input {_fmt(t)} {body.idx} -1 -1 {k} -1 0 0 0 0 0\n")
        for A in self.s.bodies:
            if A.sup == body.idx:
                left = []
                self.leave(A, t, None, left)
                self.predict_released(left, t)
        self.wake_touching(body, t)

    def drive(self, B: Body, k: int, t: float, vx: float, vy: float) -> None:
        """Input k sets the velocity of fixed polygon B (based at t, it does
        not turn): a large one placed in grid cells moves to the large list
        for good; every body it supported leaves (E leave, free motion: it
        meets B again at once and is supported again relative to B's new
        motion, or bounces, or falls); B is predicted against every body
        again (a large B: each small one that is not fixed or removed, in
        index order; a small one: predict_body), the bodies that left
        against the others; last the islands touching B wake (wake_touching:
        B may have held them, or carries them into others)."""
        B.vx = vx
        B.vy = vy
        B.stamp += 1
        if B.wcells is not None:
            self.unplace_large(B)
            B.wcells = None
            self.large.append(B)
        self.out.write(f"E input {_fmt(t)} {B.idx} -1 -1 {k} -1 0 0 0 0 0\n")
        self.emit_state(B)
        bodies = self.s.bodies
        left = []
        for A in bodies:
            if A.sup == B.idx:
                self.leave(A, t, B, left)
        if B.large:
            for o in bodies:
                if not o.large and not o.gone and not o.fixed:
                    self.predict_pair(o, B, t)
        else:
            self.predict_body(B, t, None)
        self.predict_released(left, t)
        self.wake_touching(B, t)

    def wake_touching(self, body: Body, t: float) -> None:
        """The islands of the sleepers whose bounding circles reach the
        body's (within the tolerance; a body removed, or a fixed one whose
        velocity an input set) wake: it may have held them (by index; a
        woken island's other members are awake already)."""
        tol = self.s.tol
        for o in self.s.bodies:
            if o.asleep:
                dx = o.px - body.px
                dy = o.py - body.py
                reach = o.bound + body.bound + tol
                if dx * dx + dy * dy <= reach * reach:
                    self.handle_wake(o, t)

    # ---- overlap (a teleport's check) ----------------------------------------
    def overlapping(self, A: Body, x: float, y: float, t: float) -> int:
        """The first body (by index) that A, with its centre moved to (x, y)
        at time t, would overlap by more than the tolerance; -1 when none."""
        tol = self.s.tol
        saved = (A.px, A.py, A.vx, A.vy, A.ang, A.tb)
        _, _, vx, vy, ang = self.state_at(A, t)
        A.px, A.py, A.vx, A.vy, A.ang, A.tb = x, y, vx, vy, ang, t     # A at t, moved (restored below)
        found = -1
        for B in self.s.bodies:
            if B is A or B.gone:
                continue
            bx, by, _, _, _ = self.state_at(B, t)
            dx, dy = bx - x, by - y
            reach = A.bound + B.bound + tol
            if dx * dx + dy * dy > reach * reach:
                continue
            if self.separation(A, B, t) < -tol:
                found = B.idx
                break
        A.px, A.py, A.vx, A.vy, A.ang, A.tb = saved
        return found

    def separation(self, A: Body, B: Body, t: float) -> float:
        """The largest gap between A and B at t along a separating axis:
        negative by the depth they overlap (edge normals of either polygon,
        and for a circle the line from the nearest vertex; circles: the
        distance of the centres less the radii)."""
        if not A.polygon and not B.polygon:
            ax, ay = self.point_at(A, None, t)
            bx, by = self.point_at(B, None, t)
            return math.sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A.r + B.r)
        if not A.polygon:
            return self.circle_separation(A, B, t)
        if not B.polygon:
            return self.circle_separation(B, A, t)
        return max(self.edges_separation(A, B, t), self.edges_separation(B, A, t))

    def edge_line(self, P: Body, j: int, t: float):
        """Outward unit normal (ox, oy) of edge j of P at t and the offset
        of its line, (ox, oy) . point = off."""
        ed = P.verts[j]
        px, py, _, _, ang = self.state_at(P, t)
        c = math.cos(ang)
        s = math.sin(ang)
        ox = c * ed.nx - s * ed.ny
        oy = s * ed.nx + c * ed.ny
        return ox, oy, ox * px + oy * py + ed.h

    def edges_separation(self, P: Body, Q: Body, t: float) -> float:
        """Along the edge normals of P: the largest over P's edges of the
        smallest distance of Q's vertices beyond the edge's line."""
        best = -math.inf
        pts = [self.point_at(Q, v, t) for v in Q.verts]
        for j in range(len(P.verts)):
            ox, oy, off = self.edge_line(P, j, t)
            lo = math.inf
            for qx, qy in pts:
                lo = min(lo, ox * qx + oy * qy - off)
            best = max(best, lo)
        return best

    def circle_separation(self, C: Body, P: Body, t: float) -> float:
        cx, cy = self.point_at(C, None, t)
        best = -math.inf
        for j in range(len(P.verts)):
            ox, oy, off = self.edge_line(P, j, t)
            best = max(best, ox * cx + oy * cy - off - C.r)
        pts = [self.point_at(P, v, t) for v in P.verts]
        near, d2 = 0, math.inf
        for k, (qx, qy) in enumerate(pts):
            e2 = (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy)
            if e2 < d2:
                near, d2 = k, e2
        if d2 > 0.0:
            d = math.sqrt(d2)
            ux, uy = (cx - pts[near][0]) / d, (cy - pts[near][1]) / d
            hi = -math.inf
            for qx, qy in pts:
                hi = max(hi, ux * qx + uy * qy)
            best = max(best, ux * cx + uy * cy - C.r - hi)
        return best

    def handle_cell(self, ev: CellEvent) -> None:
        """The body's centre went the grid's margin past its cell's edge along
        an axis: move it to the next cell and predict it against the row or
        column it now neighbours."""
        self.stats.cells += 1
        body = self.s.bodies[ev.body]
        d = ev.direction
        self.cell_remove(body)
        if ev.axis == 0:
            body.cx += d
            col = body.cx + d
            x_lo, x_hi, y_lo, y_hi = col, col, body.cy - 1, body.cy + 1
        else:
            body.cy += d
            row = body.cy + d
            x_lo, x_hi, y_lo, y_hi = body.cx - 1, body.cx + 1, row, row
        self.cell_add(body)
        for o in self.candidates(body, x_lo, x_hi, y_lo, y_hi):
            if not (body.fixed and o.fixed):
                self.predict_pair(body, o, ev.t)
        # the walls of the new row or column but those also listed in the
        # two it shares with the old neighbourhood (predicted at its last change)
        self.mark += 1
        news: list[Body] = []
        if ev.axis == 0:
            lo = body.cx - 1 if d > 0 else body.cx
            self.walls_in(body, lo, lo + 1, body.cy - 1, body.cy + 1, [])
        else:
            lo = body.cy - 1 if d > 0 else body.cy
            self.walls_in(body, body.cx - 1, body.cx + 1, lo, lo + 1, [])
        self.walls_in(body, x_lo, x_hi, y_lo, y_hi, news)
        news.sort(key=lambda o: o.idx)
        if not body.fixed:
            for o in news:
                self.predict_pair(body, o, ev.t)
        self.schedule_cell(body, ev.t)

    def handle_horizon(self, ev: HorizonEvent) -> None:
        self.stats.horizons += 1
        self.predict_pair(self.s.bodies[ev.a], self.s.bodies[ev.b], ev.t)

    def handle_frame(self, ev: FrameEvent) -> None:
        self.stats.frames += 1
        self.out.write(f"E frame {_fmt(ev.t)} -1 -1 -1 -1 -1 0 0 0 0 0\n")
        nxt = (ev.k + 1) * self.s.frame_dt
        if nxt <= self.s.end:
            self.push(FrameEvent(nxt, ev.k + 1))

    # ---- the run ------------------------------------------------------------
    def start(self) -> None:
        """Cells, inputs, the first frame and every pair's first prediction."""
        s = self.s
        bodies = s.bodies
        for b in bodies:
            if not b.large:
                b.cx, b.cy = self.cell_of(b.px, b.py)
                self.cell_add(b)
        for k, inp in enumerate(s.inputs):
            self.push(InputEvent(inp.t, k))
        if s.frame_dt > 0.0 and s.frame_dt <= s.end:
            self.push(FrameEvent(s.frame_dt, 1))
        for b in bodies:
            if b.large:
                continue
            for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
                if o.idx > b.idx and not (b.fixed and o.fixed):
                    self.predict_pair(b, o, 0.0)
            for o in self.large_near(b):
                if not (b.fixed and o.fixed):
                    self.predict_pair(b, o, 0.0)
            self.schedule_cell(b, 0.0)

    def dispatch(self, ev) -> None:
        """Handle one event popped from the queue: drop it when stale, count
        the events at one instant (max_same_time), call its kind's handler."""
        if self.is_stale(ev):
            self.stats.stale += 1
            return
        if ev.t == self.last_t:
            self.same += 1
            if self.same > self.s.max_same:
                raise SimError(f"more than {self.s.max_same} events at t = {_fmt(ev.t)}: the scene is stuck")
        else:
            self.last_t, self.same = ev.t, 0
        self.handlers[ev.kind](ev)

    def process(self, t: float, inclusive: bool) -> None:
        """Handle every queued event before t (inclusive: at t too), in
        (t, kind, seq) order, events that handling schedules included."""
        heap = self.heap
        while heap:
            top = heap[0][0]
            if top > t or (top == t and not inclusive):
                return
            self.dispatch(heapq.heappop(heap)[3])

    # ---- the live API (docs/engine-api.md) ------------------------------------
    def advance(self, t: float) -> list[Contact]:
        """Handle every event at a time before t, move the world's time to t
        and return the contacts handled since the last call.  Events at
        exactly t stay queued: an input made at t comes before them, as a
        scripted input at t does.  No body is re-based but by its events."""
        if not (t >= self.time and t <= self.s.end):
            raise SimError(f"advance: t = {_fmt(t)} is outside [{_fmt(self.time)}, {_fmt(self.s.end)}] "
                           f"(the world's time .. the scene's end)")
        self.process(t, False)
        self.time = t
        return self.take_contacts()

    def take_contacts(self) -> list[Contact]:
        got = self.contacts
        self.contacts = []
        return got

    def next_event_time(self) -> float:
        """The time of the next event that is not stale (stale ones at the
        top of the queue are dropped and counted as the run would); inf when
        none comes before the end."""
        heap = self.heap
        while heap:
            top = heap[0]
            if top[0] > self.s.end:
                break
            if not self.is_stale(top[3]):
                return top[0]
            heapq.heappop(heap)
            self.stats.stale += 1
        return math.inf

    def state(self, body: int, t: float) -> tuple[float, float, float, float, float, float]:
        """(px, py, vx, vy, angle, omega) of a body at t, exact, for t from
        the world's time to the next event's (a removed body: where it was
        removed, at rest)."""
        b = self.body(body)
        nxt = self.next_event_time()
        if not (t >= self.time and t <= nxt and t <= self.s.end):
            raise SimError(f"state: t = {_fmt(t)} is outside [{_fmt(self.time)}, {_fmt(nxt)}] "
                           f"(the world's time .. the next event)")
        px, py, vx, vy, ang = self.state_at(b, t)
        return px, py, vx, vy, ang, b.om

    def states(self, t: float) -> list[tuple[float, float, float, float, float, float]]:
        """Every body's state at t at once (what a frame draws): entry k is
        body k's, as state() gives it; the same error when t is outside."""
        bodies = self.s.bodies
        if not bodies:
            return []
        out = [self.state(0, t)]
        for b in bodies[1:]:
            px, py, vx, vy, ang = self.state_at(b, t)
            out.append((px, py, vx, vy, ang, b.om))
        return out

    def body(self, k: int) -> Body:
        if not (0 <= k < len(self.s.bodies)):
            raise SimError(f"no body {k} (the world has {len(self.s.bodies)})")
        return self.s.bodies[k]

    def remove_body(self, body: int) -> None:
        """Take a body (movable or fixed) out of the world now: input MODE 4
        (docs/engine-api.md)."""
        self.live_input(body, REMOVE, 0.0, 0.0)

    def add_body(self, text: str) -> int:
        """A body from its flat lines (`body ...` and its `v` lines, the
        state at the world's time) added now; its index, or -1 (the world
        unchanged) when it would overlap a body by more than the tolerance.
        Not an input: a recording refuses a session that added bodies."""
        tk = Tokens(text, "add_body")
        s = self.s
        b = read_body(tk, len(s.bodies))
        if tk.pos != len(tk.tok):
            raise SimError(f"add_body: unexpected '{tk.tok[tk.pos]}' after the body")
        b.large = 2.0 * b.bound > min(s.cw, s.ch)
        if b.large and not b.fixed:
            raise SimError(f"add_body: a movable body of bound {_fmt(b.bound)} m does not fit the grid's cells "
                           f"({_fmt(s.cw)} x {_fmt(s.ch)} m): put such a body in the scene")
        t = self.time
        b.tb = t
        self.inputs_now()
        if self.overlapping(b, b.px, b.py, t) >= 0:
            return -1
        s.bodies.append(b)
        self.added += 1
        self.out.write(f"E add {_fmt(t)} {b.idx} -1 -1 -1 -1 0 0 0 0 0\n")
        if b.large:
            self.place_large(b)
            for o in s.bodies:
                if not o.large and not o.gone and not (o.fixed and b.fixed):
                    self.predict_pair(o, b, t)
        else:
            b.cx, b.cy = self.cell_of(b.px, b.py)
            self.cell_add(b)
            if not b.fixed:
                self.emit_state(b)
            self.predict_body(b, t, None)
        return b.idx

    # ---- live inputs: at the world's time, recorded in the input list --------
    def set_velocity(self, body: int, vx: float, vy: float) -> None:
        self.live_input(body, SET_VELOCITY, vx, vy)

    def add_velocity(self, body: int, dvx: float, dvy: float) -> None:
        self.live_input(body, ADD_VELOCITY, dvx, dvy)

    def apply_impulse(self, body: int, jx: float, jy: float) -> None:
        """An impulse (N s) through the centre: dv = J inv_mass."""
        self.live_input(body, IMPULSE, jx, jy)

    def teleport(self, body: int, x: float, y: float) -> bool:
        """Move the body's centre to (x, y) now, keeping its velocity; False
        (the world unchanged) when it would overlap another body by more
        than the tolerance there."""
        return self.live_input(body, TELEPORT, x, y)

    def live_input(self, body: int, mode: int, x: float, y: float) -> bool:
        """An input at the world's time T, handled as the same input scripted
        at T and listed after the scene's would be: the scene's inputs at T
        are handled first, then this one, before any other event at T
        (docs/engine-api.md, "Live inputs").  It is appended to the input
        list (s.inputs), which is the recording."""
        b = self.body(body)
        if b.gone:
            raise SimError(f"body {body} was removed")
        if not drivable(b, mode):
            raise SimError(f"body {body} is fixed: inputs move movable bodies only (or set the velocity of a "
                           f"fixed polygon that does not turn, or remove a fixed body)")
        if not (math.isfinite(x) and math.isfinite(y)):
            raise SimError(f"input on body {body}: ({_fmt(x)}, {_fmt(y)}) is not finite")
        t = self.time
        self.inputs_now()
        if mode == TELEPORT:
            if self.overlapping(b, x, y, t) >= 0:
                return False
        self.s.inputs.append(Input(t, body, mode, x, y))
        self.push(InputEvent(t, len(self.s.inputs) - 1))
        self.inputs_now()
        return True

    def input_log(self) -> list[tuple[float, int, int, float, float]]:
        """Every input, (t, body, mode, x, y): the scene's, then the live ones
        in the order they were made (what a recording writes)."""
        return [(e.t, e.body, e.mode, e.vx, e.vy) for e in self.s.inputs]

    def inputs_now(self) -> None:
        """Handle the input events queued at exactly the world's time."""
        heap = self.heap
        while heap and heap[0][0] == self.time and heap[0][1] == INPUT:
            self.dispatch(heapq.heappop(heap)[3])

    def finish(self) -> list[Contact]:
        """Handle the events at the end time, then write every body at the
        end, the counters and the variants served; returns the contacts
        handled since the last advance."""
        s = self.s
        self.process(s.end, True)
        self.time = s.end
        for b in s.bodies:
            self.rebase(b, s.end)
        for b in s.bodies:
            self.out.write(f"F {b.idx} {_fmt(b.px)} {_fmt(b.py)} {_fmt(b.vx)} {_fmt(b.vy)} "
                           f"{_fmt(b.ang)} {_fmt(b.om)}\n")
        for name in STAT_NAMES:
            self.out.write(f"N {name} {getattr(self.stats, name)}\n")
        for k, c in enumerate(self.cc_counts):
            self.out.write(f"V circle_circle {k} {c}\n")
        for k, c in enumerate(self.pe_counts):
            self.out.write(f"V point_edge {k} {c}\n")
        return self.take_contacts()

    def run(self) -> None:
        """The batch simulator: every event to the end, then the final lines."""
        self.advance(self.s.end)
        self.finish()


def simulate(scene_text: str, cc, pe, out) -> None:
    """Run a compiled scene; raises SimError with a message on a stuck or bad scene."""
    World(scene_text, cc, pe, out).run()
