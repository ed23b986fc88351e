"""The broad phase (docs/simulator.md, "Broad phase"): a uniform grid of
cells holding the small bodies, the large fixed bodies that do not move
listed in the cells their boxes cover (walls), and the list of the other
large bodies that every body checks (GridMixin)."""
from __future__ import annotations

import math

from max2code_rt.sim.scene import Body


class GridMixin:
    """self.cells, self.walls, self.large and the mark of large_near."""

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
