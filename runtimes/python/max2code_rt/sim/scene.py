"""The compiled scene (docs/simulator.md, "Flat scene"): the bodies and
their vertices, the inputs, the grid and the run's constants, read from
the flat text that `max2code simulate` makes from a JSON scene."""
from __future__ import annotations

import math
import re

from max2code_rt.sim.out import SimError, _fmt


# input modes (the flat scene's MODE; docs/simulator.md)
SET_VELOCITY, ADD_VELOCITY, IMPULSE, TELEPORT, REMOVE = 0, 1, 2, 3, 4


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
                 "carry", "rest", "on")


class Input:
    """A scripted or live input."""
    __slots__ = ("t", "body", "mode", "vx", "vy")
    # t s; body index; mode SET_VELOCITY, ADD_VELOCITY (vx, vy m/s), IMPULSE
    # (vx, vy: the impulse, N s, through the centre), TELEPORT (vx, vy: the
    # new centre, m), REMOVE (vx, vy unused, 0)

    def __init__(self, t: float, body: int, mode: int, vx: float, vy: float):
        self.t, self.body, self.mode, self.vx, self.vy = t, body, mode, vx, vy


# The limits of a flat text (docs/simulator.md, "Flat scene checks"): every
# runtime uses these names and values.
MAX_BODIES = 1000000            # bodies in a scene
MAX_VERTICES = 1024             # vertices of one polygon
MAX_INPUTS = 10000000           # scripted inputs in a scene
LENGTH_MAX = 1e150              # m or s: lengths, times and positions at most this
LENGTH_MIN = 1e-150             # m: tolerances and grid cells at least this
MAX_TEXT = 1073741824           # bytes in one flat text

_BAD_BYTE = re.compile(r"[^\x21-\x7e \t\n\r]")
_NUMBER = re.compile(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")
_INTEGER = re.compile(r"-?[0-9]{1,18}")


def _cut(w: str) -> str:
    """A word as a message quotes it: its first 32 characters, then `...`."""
    return w if len(w) <= 32 else w[:32] + "..."


def check_text(text: str, what: str) -> None:
    """Rules 1 and 2 of a flat text (docs/simulator.md, "Flat scene
    checks"): at most MAX_TEXT bytes, printable ASCII and whitespace.
    Every character before the first bad one is ASCII, so its index is the
    byte offset."""
    if len(text) > MAX_TEXT:
        raise SimError(f"{what}: longer than {MAX_TEXT} bytes")
    bad = _BAD_BYTE.search(text)
    if bad:
        raise SimError(f"{what}: byte {bad.start()}: not printable ASCII")


class Tokens:
    """The whitespace-separated words of a flat text, read in order.  The
    text (str, or bytes read as latin-1) must be printable ASCII and
    whitespace, at most MAX_TEXT bytes; numbers and integers are read by
    the flat format's own grammar, never by float()'s or int()'s wider one."""

    def __init__(self, text: str | bytes, what: str):
        self.what = what
        if isinstance(text, (bytes, bytearray)):
            text = bytes(text).decode("latin-1")
        check_text(text, what)
        self.tok = text.split()
        self.pos = 0

    def fail(self, message: str):
        raise SimError(f"{self.what}: {message}")

    def word(self, expect=None) -> str:
        if self.pos >= len(self.tok):
            self.fail("ends early" + (f" (expected '{expect}')" if expect else ""))
        w = self.tok[self.pos]
        self.pos += 1
        if expect is not None and w != expect:
            self.fail(f"expected '{expect}', found '{_cut(w)}'")
        return w

    def num(self) -> float:
        """A finite double: the nearest to a decimal word of at most 64 characters."""
        w = self.word()
        if len(w) > 64 or not _NUMBER.fullmatch(w):
            self.fail(f"expected a number, found '{_cut(w)}'")
        x = float(w)
        if math.isinf(x):
            self.fail(f"number '{_cut(w)}' is beyond a double's range")
        return x

    def integer(self) -> int:
        """An integer of at most 18 digits, optionally negative."""
        w = self.word()
        if not _INTEGER.fullmatch(w):
            self.fail(f"expected an integer, found '{_cut(w)}'")
        return int(w)

    def at_end(self) -> bool:
        return self.pos >= len(self.tok)


def read_body(tk: Tokens, i: int, tol: float, end: float, n: int) -> Body:
    """A `body ...` line and its `v` lines (docs/simulator.md, Flat scene),
    checked as read ("Flat scene checks"): tol the scene's tolerance, end
    its end time (for the body's reach), n the bodies a cover may name."""
    num, integer = tk.num, tk.integer
    tk.word("body")
    b = Body()
    b.idx = i
    poly, fixed = integer(), integer()
    b.inv_m, b.inv_i, b.e, b.mu = num(), num(), num(), num()
    b.px, b.py, b.vx, b.vy, b.ax, b.ay = num(), num(), num(), num(), num(), num()
    b.ang, b.om = num(), num()
    b.r, b.orbit, b.ophase, b.bound, b.window = num(), num(), num(), num(), num()
    large = integer()
    nv = integer()
    _check_body(tk, i, poly, fixed, large, nv, b, tol, end)
    b.polygon, b.fixed, b.large = poly == 1, fixed == 1, large == 1
    b.fax, b.fay = b.ax, b.ay
    b.sup, b.sup_edge = -1, -1
    b.tx = b.ty = b.load = b.at = 0.0
    b.verts = []
    for j in range(nv):
        tk.word("v")
        v = Vertex([num() for _ in range(10)], integer())
        where = f"body {i} vertex {j}"
        # lx, ly and rho (the vertex), h, s1 and s2 (its edge's line and extent: each at most a vertex's
        # distance, twice the bound leaving room for their rounding)
        if not (abs(v.lx) <= b.bound and abs(v.ly) <= b.bound and 0.0 <= v.rho <= b.bound
                and abs(v.h) <= 2.0 * b.bound and abs(v.s1) <= 2.0 * b.bound and abs(v.s2) <= 2.0 * b.bound):
            tk.fail(f"{where}: outside the bound")
        if not abs(v.nx * v.nx + v.ny * v.ny - 1.0) <= 1e-9:
            tk.fail(f"{where}: the normal is not a unit vector")
        if not (v.cover == -1 or (0 <= v.cover < n and v.cover != i)):
            tk.fail(f"{where}: cover {v.cover} is not a body")
        b.verts.append(v)
    if b.polygon:
        _check_polygon(tk, i, b.verts, tol)
    b.tb = 0.0
    b.stamp = 0
    b.cx = b.cy = 0
    b.gone = False
    b.asleep = False
    b.island = -1
    b.on = []
    b.wcells = None
    b.seen = 0
    b.carry = 0
    b.rest = -1
    return b


def _check_body(tk: Tokens, k: int, poly: int, fixed: int, large: int, nv: int, b: Body, tol: float,
                end: float) -> None:
    """The checks of a body line, in the specification's order."""
    at = f"body {k}"
    for name, flag in (("poly", poly), ("fixed", fixed), ("large", large)):
        if flag not in (0, 1):
            tk.fail(f"{at}: {name} must be 0 or 1")
    if fixed:
        if not (b.inv_m == 0.0 and b.inv_i == 0.0):
            tk.fail(f"{at}: a fixed body has inverse mass 0")
    else:
        if not b.inv_m > 0.0:
            tk.fail(f"{at}: inverse mass {_fmt(b.inv_m)} must be positive")
        if poly and not b.inv_i > 0.0:
            tk.fail(f"{at}: inverse inertia {_fmt(b.inv_i)} must be positive")
        if not poly and b.inv_i != 0.0:
            tk.fail(f"{at}: a circle has inverse inertia 0")
    if not 0.0 <= b.e <= 1.0:
        tk.fail(f"{at}: restitution {_fmt(b.e)} outside [0, 1]")
    if not b.mu >= 0.0:
        tk.fail(f"{at}: friction {_fmt(b.mu)} is negative")
    if not poly:
        if not tol <= b.r <= LENGTH_MAX:
            tk.fail(f"{at}: radius {_fmt(b.r)} outside [tolerance, 1e150]")
        if nv != 0:
            tk.fail(f"{at}: a circle has no vertices")
        if b.orbit != 0.0:
            if not tol <= b.orbit <= LENGTH_MAX:
                tk.fail(f"{at}: orbit radius {_fmt(b.orbit)} outside [tolerance, 1e150]")
            if not fixed:
                tk.fail(f"{at}: an orbiting circle must be fixed")
        if b.om != 0.0 and not b.orbit > 0.0:
            tk.fail(f"{at}: a circle turns only about an orbit")
    else:
        if b.r != 0.0 or b.orbit != 0.0:
            tk.fail(f"{at}: a polygon has no radius or orbit")
        if not 3 <= nv <= MAX_VERTICES:
            tk.fail(f"{at}: {nv} vertices (3 to {MAX_VERTICES})")
    if not 0.0 <= b.window <= 0.5:
        tk.fail(f"{at}: window {_fmt(b.window)} outside [0, 0.5]")
    # a polygon's radius and orbit are 0 here, so this is bound >= 0 for it
    if not b.r + b.orbit <= b.bound <= LENGTH_MAX:
        tk.fail(f"{at}: bound {_fmt(b.bound)} is too small or too large")
    reach = ((abs(b.px) + abs(b.py)) + (abs(b.vx) + abs(b.vy)) * end + (abs(b.ax) + abs(b.ay)) * end * end / 2
             + b.bound)
    if not reach <= 2 * LENGTH_MAX:
        tk.fail(f"{at}: reaches more than 2e150 m from the origin by the end")


def _check_polygon(tk: Tokens, k: int, vs: list[Vertex], tol: float) -> None:
    """A polygon is strictly convex, counter-clockwise, winds once, and its
    normals point outward; each rule over every vertex before the next."""
    n = len(vs)
    ex = [vs[(j + 1) % n].lx - vs[j].lx for j in range(n)]
    ey = [vs[(j + 1) % n].ly - vs[j].ly for j in range(n)]
    for j in range(n):
        if not abs(ex[j]) + abs(ey[j]) >= tol:
            tk.fail(f"body {k} vertex {j}: edge shorter than the tolerance")
    for j in range(n):
        if not ex[j - 1] * ey[j] - ey[j - 1] * ex[j] > 0.0:
            tk.fail(f"body {k} vertex {j}: not strictly convex (counter-clockwise)")
    signs = [y > 0.0 for y in ey if y != 0.0]
    changes = sum(1 for j in range(len(signs)) if signs[j] != signs[j - 1])
    if changes != 2:
        tk.fail(f"body {k}: the polygon winds {changes // 2} times")
    for j in range(n):
        if not vs[j].nx * ey[j] - vs[j].ny * ex[j] > 0.0:
            tk.fail(f"body {k} vertex {j}: the normal does not point outward")


def drivable(b: Body, mode: int) -> bool:
    """An input of this mode may act on b: any on a movable body; on a fixed
    one, removal, or set_velocity when it is a polygon that does not turn
    (its edges then translate: docs/simulator.md, Contact model)."""
    if not b.fixed or mode == REMOVE:
        return True
    return mode == SET_VELOCITY and b.polygon and b.om == 0.0


def after_input(b: Body, mode: int, x: float, y: float, px: float, py: float, vx: float, vy: float
                ) -> tuple[float, float, float, float]:
    """A body's position and velocity (px, py, vx, vy) just after an input
    of `mode` with values (x, y), from its state (px, py, vx, vy) then: the
    velocity set, added to or changed by an impulse through the centre, or
    the centre moved; a removal changes nothing."""
    if mode == SET_VELOCITY:
        return px, py, x, y
    if mode == ADD_VELOCITY:
        return px, py, vx + x, vy + y
    if mode == IMPULSE:
        return px, py, vx + x * b.inv_m, vy + y * b.inv_m
    if mode == TELEPORT:
        return x, y, vx, vy
    return px, py, vx, vy


def live_reach(b: Body, px: float, py: float, vx: float, vy: float, end: float) -> float:
    """A body's reach by the end time `end` from position (px, py) and
    velocity (vx, vy) after an input (live or scripted), with its own
    acceleration and bound: the scene's rule for a body (docs/simulator.md,
    "Flat scene checks", rule 8), left to right in doubles."""
    return ((abs(px) + abs(py)) + (abs(vx) + abs(vy)) * end + (abs(b.ax) + abs(b.ay)) * end * end / 2
            + b.bound)


class Scene:
    """A compiled scene, read from the flat format and checked as it is read
    (docs/simulator.md, "Flat scene checks"): the first fault stops it."""

    def __init__(self, text: str | bytes):
        tk = Tokens(text, "scene")
        word, num, integer, fail = tk.word, tk.num, tk.integer, tk.fail
        word("m2c-scene")
        version = integer()
        if version != 1:
            fail(f"unknown version {version}")
        word("end"); self.end = end = num()
        if not 0.0 < end <= LENGTH_MAX:
            fail(f"end {_fmt(end)} outside (0, 1e150]")
        word("frame"); self.frame_dt = dt = num()
        if not (dt == 0.0 or (dt > 0.0 and end / dt <= 1e12)):
            fail(f"frame {_fmt(dt)} gives more than 1e12 frames" if dt > 0.0 else f"frame {_fmt(dt)} is negative")
        word("tolerance"); self.tol = tol = num()
        if not LENGTH_MIN <= tol <= LENGTH_MAX:
            fail(f"tolerance {_fmt(tol)} outside [1e-150, 1e150]")
        word("rest_speed"); self.rest_speed = num()
        if not self.rest_speed >= 0.0:
            fail(f"rest_speed {_fmt(self.rest_speed)} is negative")
        if not self.rest_speed <= LENGTH_MAX:          # its square must not overflow
            fail(f"rest_speed {_fmt(self.rest_speed)} beyond 1e150")
        word("window_angle"); self.alpha = num()
        if not 0.0 < self.alpha <= 0.5:
            fail(f"window_angle {_fmt(self.alpha)} outside (0, 0.5]")
        word("max_same_time"); self.max_same = integer()
        if self.max_same < 1:
            fail(f"max_same_time {self.max_same} is less than 1")
        word("max_events"); self.max_events = integer()
        if self.max_events < 1:
            fail(f"max_events {self.max_events} is less than 1")
        word("grid"); self.x0 = num(); self.y0 = num()
        if not (abs(self.x0) <= LENGTH_MAX and abs(self.y0) <= LENGTH_MAX):
            fail("grid origin beyond 1e150")
        self.cw = num(); self.ch = num()
        for c in (self.cw, self.ch):
            if not LENGTH_MIN <= c <= LENGTH_MAX:
                fail(f"grid cell {_fmt(c)} outside [1e-150, 1e150]")
        self.nx = integer(); self.ny = integer()
        if self.nx < 1 or self.ny < 1:
            fail(f"grid of {self.nx} x {self.ny} cells")
        self.margin = num()
        self.half_cell = 0.5 * min(self.cw, self.ch)
        if not 0.0 <= self.margin < self.half_cell:
            fail(f"grid margin {_fmt(self.margin)} m outside [0, half a cell)")
        word("bodies"); n = integer()
        if not 1 <= n <= MAX_BODIES:
            fail(f"{n} bodies (1 to {MAX_BODIES})")
        cells = max(16, 4 * n)
        if self.nx > cells or self.nx * self.ny > cells:
            fail(f"grid of {self.nx} x {self.ny} cells for {n} bodies (at most max(16, 4 x bodies) cells)")
        self.bodies: list[Body] = [read_body(tk, i, tol, end, n) for i in range(n)]
        for b in self.bodies:
            for j, v in enumerate(b.verts):
                if v.cover >= 0 and not self.bodies[v.cover].fixed:
                    fail(f"body {b.idx} vertex {j}: cover {v.cover} is not a fixed body")
        word("inputs"); k = integer()
        if not 0 <= k <= MAX_INPUTS:
            fail(f"{k} inputs (0 to {MAX_INPUTS})")
        self.inputs = []
        removed_by: dict[int, int] = {}         # body -> the input that removed it
        for i in range(k):
            word("input")
            inp = Input(num(), integer(), integer(), num(), num())
            if not 0.0 <= inp.t <= end:
                fail(f"input {i}: time {_fmt(inp.t)} outside [0, end]")
            if not 0 <= inp.body < n:
                fail(f"input on body {inp.body}, which does not exist")
            if not 0 <= inp.mode <= 4:
                fail(f"unknown input mode {inp.mode}")
            if not drivable(self.bodies[inp.body], inp.mode):
                fail(f"input {i} on fixed body {inp.body}: only set_velocity "
                     f"(on a polygon that does not turn) or remove")
            if inp.body in removed_by:
                fail(f"input {i}: body {inp.body} was removed by input {removed_by[inp.body]}")
            if inp.mode == REMOVE:
                if inp.vx != 0.0 or inp.vy != 0.0:
                    fail(f"input {i}: a removal has no vector")
                removed_by[inp.body] = i
            if inp.mode == TELEPORT and not abs(inp.vx) + abs(inp.vy) <= LENGTH_MAX:
                fail(f"input {i}: teleport beyond 1e150 m")
            self.inputs.append(inp)
        word("end")
        if not tk.at_end():
            fail(f"unexpected '{_cut(tk.word())}' after the end")
