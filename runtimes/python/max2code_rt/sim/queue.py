"""The event queue: the event kinds (in the order they are handled at
equal times), one record per kind with the fields that kind needs, and
QueueMixin, which pushes them on the World's heap (Python's heapq on
(t, kind, seq), seq the scheduling counter)."""
from __future__ import annotations

import heapq

from max2code_rt.sim.scene import Body

# event kinds, in the order they are handled at equal times
INPUT, COLLISION, STOP, LEAVE, CELL, HORIZON, FRAME = 0, 1, 2, 3, 4, 5, 6
KIND_NAMES = ("input", "collision", "stop", "leave", "cell", "horizon", "frame")

# event records: one per kind, with the fields that kind needs; stamp_a,
# stamp_b, stamp: the bodies' stamps when the event was scheduled


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


class QueueMixin:
    """Scheduling: an event record onto self.heap."""

    def push(self, ev) -> None:
        """Queue an event record; the queue orders by (t, kind, seq)."""
        heapq.heappush(self.heap, (ev.t, ev.kind, self.seq, ev))
        self.seq += 1

    def push_collision(self, t: float, feature: int, A: Body, B: Body, i: int, j: int) -> None:
        self.push(CollisionEvent(t, A.idx, B.idx, feature, i, j, A.stamp, B.stamp))

    def push_horizon(self, t: float, A: Body, B: Body) -> None:
        self.push(HorizonEvent(t, A.idx, B.idx, A.stamp, B.stamp))
