"""circles_apart (docs/simulator.md, "Pairs that stay apart"): the test that
answers a circle pair's prediction without its polynomial must never say
"apart" for a pair whose full prediction (the generated coefficients, then
first_contact) finds a contact.  Checked on the Python reference, whose
generated coefficients are the same expressions as the C, Rust and
Modula-2 ones (the crosscheck and the trace digests hold the runtimes to
the same bytes)."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from sim_scenes import two_circles_world  # noqa: E402

WINDOW = 10.0       # s: a long window, so that a missed root would show


@pytest.fixture(scope="module")
def world():
    return two_circles_world()


def full(w, pa, ra, pb, rb):
    """The prediction without circles_apart: coefficients and first_contact."""
    args = w.cc_args(pa, ra, pb, rb)
    coef = w.cc_coef(*args)
    tol = w.s.tol
    kappa = tol * (2.0 * (ra + rb) + tol)
    return args, kappa, w.first_contact(coef, len(coef) - 1, WINDOW, kappa, lambda s: True)


def params(x, y, vx, vy, ax=0.0, ay=-9.81):
    """circle_params of a circle without orbit."""
    return (x, vx, ax, 0.0, 0.0, math.pi / 2, y, vy, ay, 0.0, 0.0)


def check(w, x, y, vx, vy, ra, rb):
    """Body a at (x, y) moving (vx, vy) relative to b at the origin, at rest
    (both under the same gravity): apart only when the full prediction finds
    nothing.  Returns circles_apart's answer."""
    args, kappa, t = full(w, params(x, y, vx, vy), ra, params(0.0, 0.0, 0.0, 0.0), rb)
    apart = w.circles_apart(args, kappa)
    if apart:
        assert t is None, (x, y, vx, vy, ra, rb, t)
    return apart


def test_clear_cases(world):
    """It answers the cases it is for, and leaves the others to the polynomial."""
    assert check(world, 1.0, 0.0, 1.0, 0.0, 0.1, 0.1)        # separating
    assert check(world, 1.0, 0.0, -1.0, 1.0, 0.1, 0.1)       # approaching, passes 0.71 m away
    assert not check(world, 1.0, 0.0, -1.0, 0.1, 0.1, 0.1)   # approaching, meets
    assert not check(world, 0.2, 0.0, 0.0, 1.0, 0.1, 0.1)    # touching now, sliding past: c1 = 0
    args, kappa, _ = full(world, params(1.0, 0.0, -1.0, 1.0, ay=0.0), 0.1, params(0.0, 0.0, 0.0, 0.0), 0.1)
    assert not world.circles_apart(args, kappa)               # relative acceleration: left to the polynomial


def test_underflow(world):
    """Touching now and approaching at 1e-162 m/s: |v|^2 underflows to 0
    while (p x v)^2 does not, so without the bounds on the sizes the miss
    test said apart; the full prediction finds the contact now."""
    args, kappa, t = full(world, params(10.0, 0.0, -1e-162, 1e-162), 5.0, params(0.0, 0.0, 0.0, 0.0), 5.0)
    assert t == 0.0
    assert not world.circles_apart(args, kappa)


finite = st.floats(min_value=-10.0, max_value=10.0, allow_nan=False, allow_infinity=False)
radius = st.floats(min_value=0.0, max_value=1.0, allow_nan=False, allow_infinity=False)


@pytest.mark.slow
@settings(max_examples=3000, deadline=None)
@given(x=finite, y=finite, vx=finite, vy=finite, ra=radius, rb=radius)
def test_random_pairs(world, x, y, vx, vy, ra, rb):
    check(world, x, y, vx, vy, ra, rb)


@pytest.mark.slow
@settings(max_examples=3000, deadline=None)
@given(ang=st.floats(min_value=0.0, max_value=2 * math.pi), gap=st.floats(min_value=-1e-6, max_value=1e-6),
       speed=st.floats(min_value=1e-6, max_value=100.0), slant=st.floats(min_value=-1e-9, max_value=1e-9),
       r=st.floats(min_value=1e-4, max_value=1.0))
def test_touching_and_sliding_past(world, ang, gap, speed, slant, r):
    """At a distance of about R, moving nearly along the tangent: p . v is
    within rounding of zero, and the gap within the tolerance."""
    d = 2.0 * r + gap
    x, y = d * math.cos(ang), d * math.sin(ang)
    vx, vy = -speed * math.sin(ang) + slant * math.cos(ang), speed * math.cos(ang) + slant * math.sin(ang)
    check(world, x, y, vx, vy, r, r)


@pytest.mark.slow
@settings(max_examples=3000, deadline=None)
@given(ang=st.floats(min_value=0.0, max_value=2 * math.pi), miss=st.floats(min_value=-1e-7, max_value=1e-7),
       far=st.floats(min_value=1.0, max_value=1000.0), speed=st.floats(min_value=1e-6, max_value=100.0),
       r=st.floats(min_value=1e-4, max_value=1.0))
def test_grazing_approach(world, ang, miss, far, speed, r):
    """Far away, approaching on a line that passes within a hair of R =
    2 r: the closest approach is R (1 + miss), so the discriminant is near
    zero."""
    R = 2.0 * r
    b = R * (1.0 + miss)                    # closest approach
    ux, uy = math.cos(ang), math.sin(ang)   # direction of motion
    x, y = -far * R * ux - b * uy, -far * R * uy + b * ux
    check(world, x, y, speed * ux, speed * uy, r, r)


magnitude = st.integers(min_value=-600, max_value=600)
mantissa = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False, allow_infinity=False)


@pytest.mark.slow
@settings(max_examples=3000, deadline=None)
@given(x=mantissa, y=mantissa, vx=mantissa, vy=mantissa, ex=magnitude, ev=magnitude, r=magnitude)
def test_extreme_magnitudes(world, x, y, vx, vy, ex, ev, r):
    """Positions, speeds and radii from 2^-600 to 2^600 (underflow and
    overflow in the products): apart only when the full prediction finds
    nothing."""
    s, v = math.ldexp(1.0, ex), math.ldexp(1.0, ev)
    check(world, x * s, y * s, vx * v, vy * v, math.ldexp(0.5, r), math.ldexp(0.5, r))
