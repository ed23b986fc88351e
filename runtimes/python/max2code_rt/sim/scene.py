"""The compiled scene (docs/simulator.md, "Flat scene"): the bodies and
their vertices, the inputs, the grid and the run's constants, read from
the flat text that `max2code simulate` makes from a JSON scene."""
from __future__ import annotations

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
                 "carry")


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
