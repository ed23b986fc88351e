"""The live world (docs/engine-api.md): World, a scene made into a world
that a caller drives with advance(t), asks next_event_time() and
state(body, t), gives inputs now (set_velocity, add_velocity,
apply_impulse, teleport, remove_body, add_body) and ends with finish();
the batch simulator is run() = advance(end) + finish() (simulate).
World combines the concept mixins; each holds its concept's methods."""
from __future__ import annotations

import heapq
import math

from max2code_rt.sim.cluster import ClusterMixin
from max2code_rt.sim.contact import ContactMixin
from max2code_rt.sim.grid import GridMixin
from max2code_rt.sim.handlers import HandlersMixin
from max2code_rt.sim.motion import MotionMixin
from max2code_rt.sim.out import OutMixin, SimError, _fmt
from max2code_rt.sim.overlap import OverlapMixin
from max2code_rt.sim.predict import PredictMixin
from max2code_rt.sim.queue import INPUT, InputEvent, QueueMixin
from max2code_rt.sim.scene import (ADD_VELOCITY, IMPULSE, LENGTH_MAX, MAX_BODIES, REMOVE, SET_VELOCITY, TELEPORT, Body,
                                   Input, Scene, Tokens, _cut, after_input, drivable, live_reach, read_body)
from max2code_rt.sim.sleep import SleepMixin
from max2code_rt.sim.support import SupportMixin
from max2code_rt.sim.world import STAT_NAMES, Contact, WorldState


class World(WorldState, MotionMixin, QueueMixin, GridMixin, PredictMixin, ContactMixin, SupportMixin, SleepMixin,
            ClusterMixin, OverlapMixin, HandlersMixin, OutMixin):
    """A live world (docs/engine-api.md): made from a flat scene, driven by
    advance(t); the batch simulator is run() = advance(end) + finish()."""

    def __init__(self, scene_text: str | bytes, cc, pe, out=None):
        scene = Scene(scene_text)
        WorldState.__init__(self, scene, cc, pe, out)
        self.finished = False           # finish() was called: no more inputs or bodies
        for b in scene.bodies:
            if b.large:
                self.place_large(b)
        self.handlers = (self.handle_input, self.handle_collision, self.handle_stop, self.handle_leave,
                         self.handle_cell, self.handle_horizon, self.handle_frame)     # by kind
        self.start()

    @classmethod
    def from_file(cls, path: str, cc, pe, out=None) -> "World":
        with open(path, "rb") as fh:
            return cls(fh.read(), cc, pe, out)

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
        Not an input: a recording refuses a world that added bodies."""
        if self.finished:
            raise SimError("live input: the world is finished")
        if len(self.s.bodies) >= MAX_BODIES:        # a scene's limit holds for a world too
            raise SimError(f"add_body: the world has {len(self.s.bodies)} bodies (at most {MAX_BODIES})")
        tk = Tokens(text, "add_body")
        s = self.s
        b = read_body(tk, len(s.bodies), s.tol, s.end, len(s.bodies))
        if not tk.at_end():
            tk.fail(f"unexpected '{_cut(tk.word())}' after the body")
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
        self.emit_add(t, b.idx)
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
        list (s.inputs), which is the recording.  An input that would make
        the body's velocity or position not finite is refused before it
        changes anything, as is any input after finish()."""
        if self.finished:
            raise SimError("live input: the world is finished")
        if not 0 <= body < len(self.s.bodies):
            raise SimError(f"live input: body {body} does not exist")
        b = self.s.bodies[body]
        if b.gone:
            raise SimError(f"body {body} was removed")
        if not drivable(b, mode):
            raise SimError(f"body {body} is fixed: inputs move movable bodies only (or set the velocity of a "
                           f"fixed polygon that does not turn, or remove a fixed body)")
        t = self.time
        self.inputs_now()
        px, py, vx, vy, _ = self.state_at(b, t)
        px, py, vx, vy = after_input(b, mode, x, y, px, py, vx, vy)
        if mode != TELEPORT and not (math.isfinite(vx) and math.isfinite(vy)):
            raise SimError(f"live input: body {body}: velocity would not be finite")
        if mode == TELEPORT:
            if not (math.isfinite(x) and math.isfinite(y)):
                raise SimError(f"live input: body {body}: position would not be finite")
            if not abs(x) + abs(y) <= LENGTH_MAX:
                raise SimError(f"live input: body {body}: teleport beyond 1e150 m")
        if mode != REMOVE and not live_reach(b, px, py, vx, vy, self.s.end) <= 2 * LENGTH_MAX:
            raise SimError(f"live input: body {body}: reaches more than 2e150 m from the origin by the end")
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
        self.finished = True
        for b in s.bodies:
            self.rebase(b, s.end)
        for b in s.bodies:
            self.emit_final_state(b)
        for name in STAT_NAMES:
            self.emit_stat(name, getattr(self.stats, name))
        for k, c in enumerate(self.cc_counts):
            self.emit_variant("circle_circle", k, c)
        for k, c in enumerate(self.pe_counts):
            self.emit_variant("point_edge", k, c)
        return self.take_contacts()

    def run(self) -> None:
        """The batch simulator: every event to the end, then the final lines."""
        self.advance(self.s.end)
        self.finish()


def simulate(scene_text: str | bytes, cc, pe, out) -> None:
    """Run a compiled scene; raises SimError with a message on a stuck or bad scene."""
    World(scene_text, cc, pe, out).run()
