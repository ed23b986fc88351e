"""Collect Maxima's polynomial by powers of the variable into a Polynomial."""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from max2code.facts import MAX_DEGREE as SOLVER_DEGREE
from max2code.generate.expr import Add, Call, Eq, Expr, Monomial, NotPolynomial, Num, Pow, Poly, Sym, to_maxima, to_poly


@dataclass(frozen=True)
class Polynomial:
    """coefficients[k] multiplies variable^k; each is a Poly over the parameters."""
    variable: str
    coefficients: tuple[Poly, ...]

    @property
    def degree(self) -> int:
        return len(self.coefficients) - 1

    def to_maxima(self) -> str:
        """Maxima text of sum(c_k * t^k), exact."""
        parts = []
        for k, c in enumerate(self.coefficients):
            parts.append(f"({poly_to_maxima(c)})*{self.variable}^{k}")
        return " + ".join(parts) if parts else "0"


MAX_DEGREE = 64


def poly_to_maxima(p: Poly) -> str:
    if p.is_zero():
        return "0"
    atoms = dict(p.atoms)
    out = []
    for mono, c in p.terms:
        f = [f"({c.numerator}/{c.denominator})"]
        f += [f"({to_maxima(atoms[k])})^({e})" for k, e in mono]
        out.append("*".join(f))
    return " + ".join(out)


def _mentions(e: Expr, name: str) -> bool:
    """Does `name` occur anywhere in `e` (inside calls, sums, products, powers)?"""
    if isinstance(e, Sym):
        return e.name == name
    if isinstance(e, Num):
        return False
    if isinstance(e, Pow):
        return _mentions(e.base, name) or _mentions(e.exp, name)
    if isinstance(e, Eq):
        return _mentions(e.lhs, name) or _mentions(e.rhs, name)
    kids = e.args if isinstance(e, Call) else e.terms if isinstance(e, Add) else e.factors
    return any(_mentions(c, name) for c in kids)


def collect(expr: Expr, variable: str) -> Polynomial:
    """Split `expr` into coefficients of variable^k (k = 0 .. degree).

    Raises NotPolynomial when the variable appears other than as a
    non-negative integer power (inside a call, in a denominator).
    """
    terms, atoms = to_poly(expr)
    for key, atom in atoms.items():
        if key != variable and _mentions(atom, variable):
            raise NotPolynomial(f"the result is not a polynomial in {variable}: it contains {to_maxima(atom)}")
    by_power: dict[int, dict[Monomial, Fraction]] = {}
    for mono, c in terms.items():
        k = dict(mono).get(variable, 0)
        if k < 0:
            raise NotPolynomial(f"the result has a negative power of {variable}")
        rest = tuple((a, e) for a, e in mono if a != variable)
        by_power.setdefault(k, {})[rest] = c
    degree = max(by_power, default=0)
    if degree > MAX_DEGREE:
        raise NotPolynomial(f"the result has degree {degree} in {variable}: max2code prints polynomials of degree "
                            f"{MAX_DEGREE} at most (the runtimes' solvers take {SOLVER_DEGREE})")
    coeffs = tuple(Poly.build(by_power.get(k, {}), atoms) for k in range(degree + 1))
    return Polynomial(variable, coeffs)
