"""The flat trace (docs/simulator.md, "Flat trace"): OutMixin writes one
line per call, one method per kind of line, numbers as `%.17g` (_fmt), to
the World's sink self.out (anything with write(str); NoTrace for a world
without a trace).  SimError is the error that stops a run; the program
(sim_main) writes its message as the trace's X line."""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from max2code_rt.sim.scene import Body


class SimError(Exception):
    """A bad or stuck scene, a bad call of the live API: the message says which."""


def _fmt(x: float) -> str:
    return "%.17g" % x


class NoTrace:
    """The trace sink of a world without a trace."""

    @staticmethod
    def write(text: str) -> None:
        pass


class OutMixin:
    """The World's trace lines, each written to self.out as one string.
    Bodies, features, vertices and edges are written as their indices
    (-1: none); times, positions, normals and impulses as _fmt."""

    def emit_state(self, b: Body) -> None:
        """`S`: a body's state at its time tb, after its motion changed."""
        self.out.write(f"S {b.idx} {_fmt(b.tb)} {_fmt(b.px)} {_fmt(b.py)} {_fmt(b.vx)} {_fmt(b.vy)} "
                       f"{_fmt(b.ang)} {_fmt(b.om)} {_fmt(b.ax)} {_fmt(b.ay)}\n")

    def emit_contact(self, word: str, t: float, a: int, b: int, feature: int, i: int, j: int, cx: float, cy: float,
                     nx: float, ny: float, impulse: float) -> None:
        """`E collision` or `E support`: the contact point, its unit normal
        from a to b and the normal impulse."""
        self.out.write(f"E {word} {_fmt(t)} {a} {b} {feature} {i} {j} {_fmt(cx)} {_fmt(cy)} "
                       f"{_fmt(nx)} {_fmt(ny)} {_fmt(impulse)}\n")

    def emit_support_end(self, word: str, t: float, a: int, sup: int, edge: int) -> None:
        """`E stop` or `E leave` of body a on edge `edge` of its support `sup`."""
        self.out.write(f"E {word} {_fmt(t)} {a} {sup} -1 -1 {edge} 0 0 0 0 0\n")

    def emit_input(self, t: float, body: int, k: int) -> None:
        """`E input`: input k (index in the input list) on the body."""
        self.out.write(f"E input {_fmt(t)} {body} -1 -1 {k} -1 0 0 0 0 0\n")

    def emit_sleep(self, t: float, a: int, g: int, island: int) -> None:
        """`E sleep`: a falls asleep on g, in the island numbered island."""
        self.out.write(f"E sleep {_fmt(t)} {a} {g} -1 -1 {island} 0 0 0 0 0\n")

    def emit_wake(self, t: float, s: int, island: int) -> None:
        """`E wake`: sleeper s (of that island) wakes, with what rests on it."""
        self.out.write(f"E wake {_fmt(t)} {s} -1 -1 -1 {island} 0 0 0 0 0\n")

    def emit_add(self, t: float, body: int) -> None:
        """`E add`: a body added by add_body."""
        self.out.write(f"E add {_fmt(t)} {body} -1 -1 -1 -1 0 0 0 0 0\n")

    def emit_frame(self, t: float) -> None:
        self.out.write(f"E frame {_fmt(t)} -1 -1 -1 -1 -1 0 0 0 0 0\n")

    def emit_final_state(self, b: Body) -> None:
        """`F`: a body at the end (position, velocity, angle, angular velocity)."""
        self.out.write(f"F {b.idx} {_fmt(b.px)} {_fmt(b.py)} {_fmt(b.vx)} {_fmt(b.vy)} "
                       f"{_fmt(b.ang)} {_fmt(b.om)}\n")

    def emit_stat(self, name: str, count: int) -> None:
        """`N`: one of the run's counters (world.STAT_NAMES)."""
        self.out.write(f"N {name} {count}\n")

    def emit_variant(self, equation: str, k: int, count: int) -> None:
        """`V`: how many predictions variant k of the generated equation served."""
        self.out.write(f"V {equation} {k} {count}\n")
