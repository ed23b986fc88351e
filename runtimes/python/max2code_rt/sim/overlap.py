"""Overlap: whether a body moved to a new place would overlap another by
more than the tolerance (a teleport's check and an added body's,
docs/engine-api.md "Live inputs"), by separating axes."""
from __future__ import annotations

import math

from max2code_rt.sim.scene import Body


class OverlapMixin:
    """Separations of two bodies at a time."""

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
        return self.polygons_separation(A, B, t, self.vertices(A, t), self.vertices(B, t))

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

    def vertices(self, Q: Body, t: float) -> list[tuple[float, float]]:
        """Q's vertices at t."""
        return [self.point_at(Q, v, t) for v in Q.verts]

    def edges_separation(self, P: Body, pts, t: float) -> float:
        """Along the edge normals of P: the largest over P's edges of the
        smallest distance of Q's vertices (pts, at t) beyond the edge's
        line.  P's lines are edge_line's, with the cos and sin of P's angle
        taken once."""
        px, py, _, _, ang = self.state_at(P, t)
        c = math.cos(ang)
        s = math.sin(ang)
        best = -math.inf
        for ed in P.verts:
            ox = c * ed.nx - s * ed.ny
            oy = s * ed.nx + c * ed.ny
            off = ox * px + oy * py + ed.h
            lo = math.inf
            for qx, qy in pts:
                lo = min(lo, ox * qx + oy * qy - off)
            best = max(best, lo)
        return best

    def polygons_separation(self, A: Body, B: Body, t: float, pa, pb) -> float:
        """separation of two polygons whose vertices at t are pa and pb."""
        return max(self.edges_separation(A, pb, t), self.edges_separation(B, pa, t))

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
