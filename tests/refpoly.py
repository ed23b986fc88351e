"""Exact multivariate polynomials in Fractions, for references written
directly in Python (no Maxima, nothing of max2code's pipeline), and the
comparison of generated coefficient functions with exact values.

A polynomial is a dict {monomial: Fraction}, a monomial a sorted tuple of
(variable, exponent).  sin and cos of a phase are variables of their own
("sin(f)", "cos(f)"), as they are to the generated code.
"""
import math
from fractions import Fraction
from math import factorial


class P:
    def __init__(self, terms=None):
        self.terms = {m: c for m, c in (terms or {}).items() if c != 0}

    @staticmethod
    def const(c):
        return P({(): Fraction(c)})

    @staticmethod
    def var(name):
        return P({((name, 1),): Fraction(1)})

    def __add__(self, other):
        other = other if isinstance(other, P) else P.const(other)
        out = dict(self.terms)
        for m, c in other.terms.items():
            out[m] = out.get(m, Fraction(0)) + c
        return P(out)

    __radd__ = __add__

    def __neg__(self):
        return P({m: -c for m, c in self.terms.items()})

    def __sub__(self, other):
        return self + (-(other if isinstance(other, P) else P.const(other)))

    def __rsub__(self, other):
        return P.const(other) - self

    def __mul__(self, other):
        other = other if isinstance(other, P) else P.const(other)
        out = {}
        for ma, ca in self.terms.items():
            for mb, cb in other.terms.items():
                d = dict(ma)
                for v, e in mb:
                    d[v] = d.get(v, 0) + e
                m = tuple(sorted(d.items()))
                out[m] = out.get(m, Fraction(0)) + ca * cb
        return P(out)

    __rmul__ = __mul__

    def __pow__(self, n):
        out = P.const(1)
        for _ in range(n):
            out = out * self
        return out

    def by_power(self, t="t"):
        """{k: P} the coefficient of t^k."""
        out = {}
        for m, c in self.terms.items():
            d = dict(m)
            k = d.pop(t, 0)
            out.setdefault(k, {})[tuple(sorted(d.items()))] = c
        return {k: P(v) for k, v in out.items()}

    def values(self, env):
        """(exact value, sum of the magnitudes of its monomials) at `env`."""
        total, size = Fraction(0), Fraction(0)
        for m, c in self.terms.items():
            v = c
            for name, e in m:
                v *= env[name] ** e
            total += v
            size += abs(v)
        return total, size


def V(name):
    return P.var(name)


def taylor_cos(x, n):
    return sum((P.const(Fraction((-1) ** k, factorial(2 * k))) * x ** (2 * k) for k in range(n // 2 + 1)), P())


def taylor_sin(x, n):
    return sum((P.const(Fraction((-1) ** k, factorial(2 * k + 1))) * x ** (2 * k + 1) for k in range((n - 1) // 2 + 1)),
               P())


def cos_of(w, phase, n, t="t"):
    """cos(phase + w t) expanded about the phase, sin and cos of it as variables."""
    x = V(w) * V(t)
    return V(f"cos({phase})") * taylor_cos(x, n) - V(f"sin({phase})") * taylor_sin(x, n)


def sin_of(w, phase, n, t="t"):
    x = V(w) * V(t)
    return V(f"sin({phase})") * taylor_cos(x, n) + V(f"cos({phase})") * taylor_sin(x, n)


def trig_env(values):
    """Parameter values (Fractions that are doubles) plus the exact doubles the
    generated code computes for sin and cos of each."""
    env = dict(values)
    for name, v in values.items():
        env[f"sin({name})"] = Fraction(math.sin(float(v)))
        env[f"cos({name})"] = Fraction(math.cos(float(v)))
    return env


def close(got, exact, size, rel=1e-11):
    """The double `got` is `exact` up to rounding: each operation of a
    coefficient's evaluation errs by at most 2^-53 of a partial sum of its
    monomials, so by far less than `rel` times the sum of their magnitudes."""
    return abs(Fraction(got) - exact) <= rel * size + Fraction(1, 10 ** 300)


def compare(coefficients, expected_by_power, env):
    """Where the generated `coefficients` (doubles, ascending powers) differ
    from the exact polynomial {k: P}: a list of (k, got, exact)."""
    bad = []
    degree = max(list(expected_by_power) + [len(coefficients) - 1])
    for k in range(degree + 1):
        exact, size = expected_by_power[k].values(env) if k in expected_by_power else (Fraction(0), Fraction(0))
        got = coefficients[k] if k < len(coefficients) else 0.0
        if not close(got, exact, size):
            bad.append((k, got, float(exact)))
    return bad


def poly_by_power(polynomial):
    """max2code's collected Polynomial (collect.py) as {k: P}, its atoms
    (symbols, sin and cos of a symbol) as variables named like trig_env's."""
    out = {}
    for k, c in enumerate(polynomial.coefficients):
        atoms = dict(c.atoms)
        names = {}
        for key, atom in atoms.items():
            if hasattr(atom, "func"):
                names[key] = f"{atom.func}({atom.args[0].name})"
            else:
                names[key] = atom.name
        terms = {}
        for mono, coef in c.terms:
            m = tuple(sorted((names[key], e) for key, e in mono))
            terms[m] = coef
        out[k] = P(terms)
    return out


def substitute_zeros(by_power, zeros):
    """{k: P} with the variables `zeros` set to 0 (sin(0) = 0, cos(0) = 1)."""
    zeros = set(zeros)
    out = {}
    for k, p in by_power.items():
        terms = {}
        for m, c in p.terms.items():
            keep = []
            dead = False
            for name, e in m:
                if name in zeros:
                    dead = True
                    break
                if name.startswith(("sin(", "cos(")) and name[4:-1] in zeros:
                    if name.startswith("sin("):
                        dead = True
                        break
                    continue
                keep.append((name, e))
            if not dead:
                key = tuple(keep)
                terms[key] = terms.get(key, Fraction(0)) + c
        out[k] = P(terms)
    return out


def run_python(text):
    """The generated Python module's namespace."""
    ns = {"__name__": "generated"}
    exec(compile(text, "<generated>", "exec"), ns)
    return ns
