"""Independent exact evaluation of the bundled equations, straight from
their definitions (not from Maxima, not from max2code's tree): polynomial
arithmetic on coefficient lists in mpmath at 60 digits."""
from __future__ import annotations

import mpmath

mp = mpmath.mp


def _add(p, q):
    n = max(len(p), len(q))
    return [(p[i] if i < len(p) else 0) + (q[i] if i < len(q) else 0) for i in range(n)]


def _scale(p, s):
    return [s * x for x in p]


def _mul(p, q):
    out = [mpmath.mpf(0)] * (len(p) + len(q) - 1)
    for i, x in enumerate(p):
        for j, y in enumerate(q):
            out[i + j] += x * y
    return out


_ABS = [False]   # when set: every term counted with its absolute value


def _sign(x):
    return abs(x) if _ABS[0] else x


def taylor_cos(w, order):
    """Coefficients in t of sum_{m <= order/2} (-1)^m (w t)^(2m) / (2m)!."""
    out = [mpmath.mpf(0)] * (order + 1)
    for m in range(order // 2 + 1):
        out[2 * m] = _sign((-1) ** m * w ** (2 * m)) / mpmath.factorial(2 * m)
    return out


def taylor_sin(w, order):
    out = [mpmath.mpf(0)] * (order + 1)
    for m in range((order - 1) // 2 + 1):
        out[2 * m + 1] = _sign((-1) ** m * w ** (2 * m + 1)) / mpmath.factorial(2 * m + 1)
    return out


def orbit_sin(radius, w, phase, order):
    """radius * sin(w t + phase), expanded about the phase."""
    return _scale(_add(_scale(taylor_cos(w, order), _sign(mpmath.sin(phase))),
                       _scale(taylor_sin(w, order), _sign(mpmath.cos(phase)))), _sign(radius))


def motion(p0, v, acc, radius, w, phase, order):
    return _add([_sign(p0), _sign(v), _sign(acc) / 2], orbit_sin(radius, w, phase, order))


def _trim(p, degree):
    p = list(p) + [mpmath.mpf(0)] * (degree + 1 - len(p))
    return p[:degree + 1]


def circle_circle(params: dict[str, float], order: int = 4) -> list:
    with mpmath.workdps(60):
        q = {k: mpmath.mpf(v) for k, v in params.items()}
        x1 = motion(q["a"], q["b"], q["c"], q["d"], q["e"], q["f"], order)
        y1 = motion(q["m"], q["n"], q["o"], q["d"], q["p"], q["q"], order)
        x2 = motion(q["g"], q["h"], q["i"], q["j"], q["k"], q["l"], order)
        y2 = motion(q["r"], q["s"], q["u"], q["j"], q["v"], q["w"], order)
        minus = 1 if _ABS[0] else -1
        dx = _add(x1, _scale(x2, minus))
        dy = _add(y1, _scale(y2, minus))
        gap = _add(_add(_mul(dx, dx), _mul(dy, dy)), [minus * (_sign(q["x"]) + _sign(q["z"])) ** 2])
        return _trim(gap, max(4, 2 * order))


def point_line(params: dict[str, float], order: int = 4) -> list:
    with mpmath.workdps(60):
        q = {k: mpmath.mpf(v) for k, v in params.items()}
        line = motion(q["a"], q["b"], q["c"], q["d"], q["e"], q["f"], order)
        point = motion(q["g"], q["h"], q["i"], q["j"], q["k"], q["l"], order)
        return _trim(_add(line, _scale(point, 1 if _ABS[0] else -1)), max(2, order))


def scale(equation, params, order: int = 4) -> list:
    """S_k: coefficient k with every term's absolute value (its condition scale)."""
    _ABS[0] = True
    try:
        return EQUATIONS[equation](params, order)
    finally:
        _ABS[0] = False


EQUATIONS = {"circle-circle": circle_circle, "point-line": point_line}
