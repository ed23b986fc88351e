"""Exact expression trees and multivariate polynomials.

`Expr` nodes are what Maxima's output parses into (rationals exact, %pi
symbolic).  `Poly` is a polynomial over atoms (symbols, %pi, calls such as
sin(f)) with Fraction coefficients: the form in which coefficients are
collected by power of t and checked.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Union


# ---- expression tree ---------------------------------------------------
@dataclass(frozen=True)
class Num:
    value: Fraction


@dataclass(frozen=True)
class Sym:
    name: str            # Maxima's name, e.g. "a", "%pi"


@dataclass(frozen=True)
class Call:
    func: str
    args: tuple["Expr", ...]


@dataclass(frozen=True)
class Add:
    terms: tuple["Expr", ...]


@dataclass(frozen=True)
class Mul:
    factors: tuple["Expr", ...]


@dataclass(frozen=True)
class Pow:
    base: "Expr"
    exp: "Expr"


@dataclass(frozen=True)
class Eq:
    lhs: "Expr"
    rhs: "Expr"


Expr = Union[Num, Sym, Call, Add, Mul, Pow, Eq]


def to_maxima(e: Expr) -> str:
    """Print an Expr back as Maxima input (fully parenthesised, exact)."""
    if isinstance(e, Num):
        v = e.value
        return f"({v.numerator}/{v.denominator})" if v.denominator != 1 else f"({v.numerator})"
    if isinstance(e, Sym):
        return e.name
    if isinstance(e, Call):
        return f"{e.func}({', '.join(to_maxima(a) for a in e.args)})"
    if isinstance(e, Add):
        return "(" + " + ".join(to_maxima(t) for t in e.terms) + ")"
    if isinstance(e, Mul):
        return "(" + "*".join(to_maxima(f) for f in e.factors) + ")"
    if isinstance(e, Pow):
        return f"({to_maxima(e.base)})^({to_maxima(e.exp)})"
    if isinstance(e, Eq):
        return f"{to_maxima(e.lhs)} = {to_maxima(e.rhs)}"
    raise TypeError(e)


# ---- polynomials over atoms -------------------------------------------
# An atom is a Sym or a Call; a monomial is a sorted tuple of (atom_key, exponent).
Monomial = tuple[tuple[str, int], ...]


class NotPolynomial(ValueError):
    """The expression is not a polynomial in its atoms (e.g. 1/t, t^(1/2), sin(t))."""


def atom_key(e: Expr) -> str:
    """A canonical, sortable key for an atom: its Maxima text."""
    return to_maxima(e)


@dataclass(frozen=True)
class Poly:
    """sum(coef * prod(atom^exp)) with Fraction coefficients; `atoms` maps keys to Exprs."""
    terms: tuple[tuple[Monomial, Fraction], ...]   # sorted by monomial, no zero coefficients
    atoms: tuple[tuple[str, Expr], ...]            # sorted by key

    @staticmethod
    def build(terms: dict[Monomial, Fraction], atoms: dict[str, Expr]) -> "Poly":
        kept = tuple(sorted((m, c) for m, c in terms.items() if c != 0))
        used = {k for m, _ in kept for k, _ in m}
        return Poly(kept, tuple(sorted((k, v) for k, v in atoms.items() if k in used)))

    def degree_in(self, key: str) -> int:
        return max((dict(m).get(key, 0) for m, _ in self.terms), default=0)

    def is_zero(self) -> bool:
        return not self.terms


def _mul_terms(a: dict[Monomial, Fraction], b: dict[Monomial, Fraction]) -> dict[Monomial, Fraction]:
    out: dict[Monomial, Fraction] = {}
    for ma, ca in a.items():
        for mb, cb in b.items():
            d = dict(ma)
            for k, e in mb:
                d[k] = d.get(k, 0) + e
            m = tuple(sorted((k, e) for k, e in d.items() if e != 0))
            out[m] = out.get(m, Fraction(0)) + ca * cb
    return {m: c for m, c in out.items() if c != 0}


MAX_POWER = 1000   # a larger power of an atom cannot be a useful polynomial (the solvers take degree 16)


def to_poly(e: Expr, atoms: dict[str, Expr] | None = None) -> tuple[dict[Monomial, Fraction], dict[str, Expr]]:
    """Expand `e` into polynomial terms over its atoms.  Integer powers only;
    a negative power is allowed for an atom (a parameter in a denominator)."""
    atoms = {} if atoms is None else atoms

    def go(x: Expr) -> dict[Monomial, Fraction]:
        if isinstance(x, Num):
            return {(): x.value} if x.value != 0 else {}
        if isinstance(x, (Sym, Call)):
            k = atom_key(x)
            atoms[k] = x
            return {((k, 1),): Fraction(1)}
        if isinstance(x, Add):
            out: dict[Monomial, Fraction] = {}
            for t in x.terms:
                for m, c in go(t).items():
                    out[m] = out.get(m, Fraction(0)) + c
            return {m: c for m, c in out.items() if c != 0}
        if isinstance(x, Mul):
            acc: dict[Monomial, Fraction] = {(): Fraction(1)}
            for f in x.factors:
                acc = _mul_terms(acc, go(f))
            return acc
        if isinstance(x, Pow):
            exp = go(x.exp)
            if not exp:
                return {(): Fraction(1)}
            if list(exp) != [()] or exp[()].denominator != 1:
                raise NotPolynomial(f"non-integer power {to_maxima(x)}")
            n = int(exp[()])
            if abs(n) > MAX_POWER:
                raise NotPolynomial(f"the power {to_maxima(x)} is above {MAX_POWER}")
            base = go(x.base)
            if len(base) == 1:              # a monomial: its exponents times n
                (m, c), = base.items()
                return {tuple((k, e * n) for k, e in m): c ** n}
            if n < 0:
                raise NotPolynomial(f"division by a sum: {to_maxima(x)}")
            acc = {(): Fraction(1)}
            for _ in range(n):
                acc = _mul_terms(acc, base)
            return acc
        if isinstance(x, Eq):
            raise NotPolynomial("an equation inside an expression")
        raise TypeError(x)

    return go(e), atoms
