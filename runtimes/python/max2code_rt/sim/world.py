"""What the World holds: the scene, the generated entries and their
variant counters, the queue and the scheduling counter, the grid's lists,
the trace's counters (Stats), the instant being handled and the contacts
that the next advance() reports (Contact); WorldState makes them and
tells an event whose bodies' motion changed since it was scheduled."""
from __future__ import annotations

from max2code_rt.sim.out import NoTrace
from max2code_rt.sim.queue import CELL, COLLISION, HORIZON, LEAVE, STOP
from max2code_rt.sim.scene import Body

# the trace's N lines, in this order (the fields of Stats)
STAT_NAMES = ("collisions", "inputs", "frames", "cells", "horizons", "stale", "pairs", "features",
              "supports", "stops", "leaves", "sleeps", "wakes")


class Stats:
    """The counters written as the trace's N lines (STAT_NAMES order)."""
    __slots__ = STAT_NAMES

    def __init__(self):
        for name in STAT_NAMES:
            setattr(self, name, 0)


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


class WorldState:
    """The World's state; its methods are the mixins' (live.World)."""

    def __init__(self, scene, cc, pe, out):
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
        self.time = 0.0             # s: the world's current time
        self.last_t = -1.0          # the instant of the last event handled, and how many came at it
        self.same = 0
        self.handled = 0            # events handled (stale ones not): at most the scene's max_events
        self.contacts: list[Contact] = []    # reported by the next advance()
        self.added = 0              # bodies added by add_body (a recording refuses them)
        self.unpaid = False         # a hop since sleeper_impulse cleared it added energy (pay_floor could not pay)
        self.touched_t = -1.0       # the instant of the contacts in touched
        self.touched: list[list[int]] = []   # [a, b, feature, i, j, times] of each contact handled at touched_t
        self.jammed_t = -1.0        # the instant of the bodies in jammed
        self.jammed: list[int] = []  # the bodies a jam put to sleep at jammed_t (held_now)
        # per body: its last REST_SLOTS slow contacts, the last first (note_rest: (other, feature, i, j,
        # side, px, py, mx, my, gx, gy, gang, bx, by, bang))
        self.restc: dict[int, list] = {}

    def is_stale(self, ev) -> bool:
        """An event whose bodies' motion changed since it was scheduled.
        Inputs are scripted, not predicted, and frames have no bodies: never."""
        bodies = self.s.bodies
        if ev.kind == COLLISION or ev.kind == HORIZON:
            return bodies[ev.a].stamp != ev.stamp_a or bodies[ev.b].stamp != ev.stamp_b
        if ev.kind == CELL or ev.kind == STOP or ev.kind == LEAVE:
            return bodies[ev.body].stamp != ev.stamp
        return False
