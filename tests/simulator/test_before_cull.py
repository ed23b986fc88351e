"""first_contact's `before` (docs/simulator.md, "Features that cannot come
first"): a feature's search told the pair's earliest contact so far may
answer none instead of its contact, but only where that contact would not
be kept (the pair keeps the earliest, the first found on a tie: t < before).
So for every gap and every before, the answer kept with before is the
answer kept by the full search.  Checked on the Python reference (C, Rust
and Modula-2 write the same bytes: the crosscheck and the trace digests)
on circle gaps with a relative acceleration (degree 4, the Bernstein test's
case), circles touching now and pressed together (contact now must win over
the test), and random polynomials of degrees 3 to 8 (the Bernstein tests'
degrees), with before at, just before and just after their roots."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from sim_scenes import two_circles_world  # noqa: E402

WINDOW = 10.0       # s: a long window, so that the test's interval [0, before] lies inside it


@pytest.fixture(scope="module")
def world():
    return two_circles_world()


def kept(t, before):
    """What the pair keeps of a feature's answer t, given its earliest so far."""
    return t if t is not None and t < before else None


def befores(t):
    """before values around a full answer t (and some far from it)."""
    out = [math.inf, 0.0, 1e-300, 0.5 * WINDOW, 2.0 * WINDOW, 1e-3]
    if t is not None:
        for x in (t, 0.5 * t, 2.0 * t, t * (1.0 - 2.0 ** -12), t * (1.0 + 2.0 ** -12),
                  t * (1.0 - 2.0 ** -8), t * (1.0 + 2.0 ** -8)):
            out.append(x)
        out.append(math.nextafter(t, math.inf))
        out.append(math.nextafter(t, -math.inf))
    return [b for b in out if b >= 0.0]


def agree(w, coef, kappa, check=lambda s: True):
    """The full search and the search told each before keep the same answer.
    Returns the full answer."""
    deg = len(coef) - 1
    full = w.first_contact(coef, deg, WINDOW, kappa, check)
    for before in befores(full):
        got = w.first_contact(coef, deg, WINDOW, kappa, check, before)
        assert kept(got, before) == kept(full, before), (coef, kappa, before, full, got)
    return full


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(0.05, 3.0), min_size=1, max_size=4), st.floats(0.1, 10.0), st.booleans(),
       st.integers(5, 8))
def test_products_of_roots(world, roots, scale, pressed, deg):
    """Polynomials of degree 5 to 8 with known roots in the window (one of
    them double when pressed: a touching), the rest of the degree made up of
    a factor without real roots."""
    coef = [scale]
    def times(q):
        out = [0.0] * (len(coef) + len(q) - 1)
        for i, a in enumerate(coef):
            for k, b in enumerate(q):
                out[i + k] += a * b
        return out
    rs = roots + [roots[0]] if pressed else roots
    for r in rs:
        if len(coef) - 1 < deg:
            coef = times([-r, 1.0])
    while len(coef) - 1 < deg:
        coef = times([1.0, 0.0, 1.0]) if deg - (len(coef) - 1) >= 2 else times([1.0, 1.0])
    full = agree(world, coef, 0.0)
    assert full is None or full > 0.0


def circle_gap(w, x, y, vx, vy, ax, ay, ra, rb):
    """circle_circle's polynomial of a circle at (x, y) moving (vx, vy) with
    acceleration (ax, ay) relative to one at rest at the origin, and kappa."""
    pa = (x, vx, ax, 0.0, 0.0, math.pi / 2, y, vy, ay, 0.0, 0.0)
    pb = (0.0, 0.0, 0.0, 0.0, 0.0, math.pi / 2, 0.0, 0.0, 0.0, 0.0, 0.0)
    coef = w.cc_coef(*w.cc_args(pa, ra, pb, rb))
    tol = w.s.tol
    return coef, tol * (2.0 * (ra + rb) + tol)


def test_known_cases(world):
    """A circle falling onto one at rest hits it; a search told an earlier
    contact answers none, one told a later contact finds the same time."""
    coef, kappa = circle_gap(world, 0.0, 1.0, 0.0, 0.0, 0.0, -9.81, 0.1, 0.1)
    assert len(coef) - 1 == 4
    full = agree(world, coef, kappa)
    assert full is not None and 0.3 < full < 0.5
    assert world.first_contact(coef, 4, WINDOW, kappa, lambda s: True, 0.5 * full) is None
    assert world.first_contact(coef, 4, WINDOW, kappa, lambda s: True, 2.0 * full) == full
    # resting on it, pressed by the acceleration: contact now, whatever before is (but 0)
    coef, kappa = circle_gap(world, 0.0, 0.2, 0.0, 0.0, 0.0, -9.81, 0.1, 0.1)
    assert world.first_contact(coef, 4, WINDOW, kappa, lambda s: True, 1e-9) == 0.0
    assert world.first_contact(coef, 4, WINDOW, kappa, lambda s: True, 0.0) is None


coord = st.floats(-3.0, 3.0, allow_nan=False)
speed = st.floats(-5.0, 5.0, allow_nan=False)
accel = st.floats(-20.0, 20.0, allow_nan=False).filter(lambda a: a != 0.0)
radius = st.floats(0.01, 0.5, allow_nan=False)


@settings(max_examples=400, deadline=None)
@given(coord, coord, speed, speed, accel, accel, radius, radius)
def test_accelerating_circles(world, x, y, vx, vy, ax, ay, ra, rb):
    coef, kappa = circle_gap(world, x, y, vx, vy, ax, ay, ra, rb)
    agree(world, coef, kappa)


@settings(max_examples=300, deadline=None)
@given(st.floats(0.0, 2.0 * math.pi), st.floats(-1e-9, 1e-9), speed, speed, accel, accel, radius, radius)
def test_touching_circles(world, phi, gap, vx, vy, ax, ay, ra, rb):
    """Circles touching now (within the tolerance), moving and accelerating
    any way: the contact now, when there is one, is kept whatever before is."""
    d = ra + rb + gap
    coef, kappa = circle_gap(world, d * math.cos(phi), d * math.sin(phi), vx, vy, ax, ay, ra, rb)
    agree(world, coef, kappa)


coefficient = st.floats(-100.0, 100.0, allow_nan=False)


@settings(max_examples=600, deadline=None)
@given(st.lists(coefficient, min_size=4, max_size=9), st.sampled_from([0.0, 1e-9, 1e-3]))
def test_polynomials(world, coef, kappa):
    """Any polynomial of degree 3 to 8 (roots anywhere in the window, several
    of them, touching or not), with the check refusing some roots."""
    if coef[-1] == 0.0:
        coef[-1] = 1.0
    agree(world, coef, kappa)
    agree(world, coef, kappa, lambda s: math.sin(7.0 * s) > -0.5)
