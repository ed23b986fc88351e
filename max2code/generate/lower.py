"""Lower a Polynomial to language-neutral code: a FunctionIR.

Constants are folded (%pi included, with mpmath at 50 digits, rounded once
to a double).  Calls such as sin(f) and reciprocals 1/x become inputs
computed once.  Each coefficient is put in greedy multivariate Horner form;
the nodes are hash-consed, so a subexpression used twice (within or across
coefficients) becomes one temporary.
"""
from __future__ import annotations

from dataclasses import dataclass
import math
from fractions import Fraction

import mpmath

from max2code.generate.collect import Polynomial
from max2code.errors import Span
from max2code.generate.expr import Call, Expr, Poly, Sym, to_maxima

# Nodes are plain tuples, so equal subexpressions are equal values:
#   ("lit", float, exact)  ("ref", name)  ("neg", a)  ("call", func, a)
#   ("+", a, b)  ("-", a, b)  ("*", a, b)  ("/", a, b)
# A literal carries the double that is printed and the exact constant it was
# rounded from (a Fraction, or a PiSum when %pi was folded in), so that the
# printed code can be checked in exact arithmetic (verify.py).
Node = tuple

# an element of Q[pi]: ((power of %pi, rational factor), ...), powers ascending
PiSum = tuple


class Folded(float):
    """A double folded from an exact constant that involves %pi, carrying that
    constant (a PiSum) for the checker; arithmetic on it gives plain floats."""
    exact: PiSum

    def __new__(cls, value: float, exact: PiSum):
        self = super().__new__(cls, value)
        self.exact = exact
        return self


PI = Folded(math.pi, ((1, Fraction(1)),))


def exact_value(v) -> "Fraction | PiSum":
    """The exact constant a number passed to lit() stands for."""
    if isinstance(v, Folded):
        return v.exact
    return Fraction(v)


def _negated(e: "Fraction | PiSum") -> "Fraction | PiSum":
    return tuple((k, -c) for k, c in e) if isinstance(e, tuple) else -e


@dataclass(frozen=True)
class Assign:
    name: str
    node: Node


@dataclass(frozen=True)
class FunctionIR:
    """What a target prints: inputs, derived inputs, temporaries, coefficients."""
    name: str
    doc: str
    params: tuple[str, ...]
    param_docs: tuple[str, ...]
    derived: tuple[Assign, ...]       # sin(f), 1/x ...: computed once from the inputs
    temps: tuple[Assign, ...]         # shared subexpressions, in dependency order
    coefficients: tuple[Node, ...]    # one per power of t, ascending
    origin: Span                      # the .mxm statement that produced the polynomial
    multiplications: int              # in this code (a division counts as one)
    naive_multiplications: int        # in the plain expansion of every term

    @property
    def degree(self) -> int:
        return len(self.coefficients) - 1

    @property
    def unused_params(self) -> tuple[str, ...]:
        used: set[str] = set()
        for a in self.derived + self.temps:
            refs(a.node, used)
        for c in self.coefficients:
            refs(c, used)
        return tuple(p for p in self.params if p not in used)


def refs(n: Node, out: set[str]) -> None:
    """Add to `out` the name of every ('ref', name) node in the tree `n`."""
    if n[0] == "ref":
        out.add(n[1])
    elif n[0] != "lit":
        for c in n[1:]:
            if isinstance(c, tuple):
                refs(c, out)


# ---- node constructors with local simplification -----------------------
def lit(v: Fraction | float) -> Node:
    """A constant, rounded once to the nearest double (a Folded one is rounded
    already), with the exact value it stands for."""
    exact, v = exact_value(v), float(v)
    return ("neg", ("lit", -v, _negated(exact))) if v < 0 else ("lit", v, exact)


ZERO = lit(0)
ONE = lit(1)


def is_lit(n: Node, v: float) -> bool:
    return n[0] == "lit" and n[1] == v


def neg(a: Node) -> Node:
    if a[0] == "neg":
        return a[1]
    if is_lit(a, 0.0):
        return a
    return ("neg", a)


def add(a: Node, b: Node) -> Node:
    if is_lit(a, 0.0):
        return b
    if is_lit(b, 0.0):
        return a
    if b[0] == "neg":
        return ("-", a, b[1])
    if a[0] == "neg":
        return ("-", b, a[1])
    return ("+", a, b)


def mul(a: Node, b: Node) -> Node:
    """a * b, with a negation of either factor moved outside the product: the
    signs multiply, so two negated factors give a product without one."""
    if is_lit(a, 1.0):
        return b
    if is_lit(b, 1.0):
        return a
    if a[0] == "neg" or b[0] == "neg":
        product = mul(a[1] if a[0] == "neg" else a, b[1] if b[0] == "neg" else b)
        return product if a[0] == "neg" and b[0] == "neg" else neg(product)
    return ("*", a, b)


# ---- constants ---------------------------------------------------------
def _const_value(c: Fraction, pi_power: int) -> Fraction | float:
    """Exact while no %pi is involved; otherwise rounded once from 50 digits."""
    if pi_power == 0:
        return c
    with mpmath.workdps(50):
        return Folded(float(mpmath.mpf(c.numerator) / c.denominator * mpmath.pi ** pi_power), ((pi_power, c),))


def _const_sum(a: Fraction | float, b: Fraction | float) -> Fraction | float:
    """a + b: exact for two rationals; with %pi in either, the double sum of
    their doubles, carrying the exact sum."""
    if not isinstance(a, Folded) and not isinstance(b, Folded):
        return a + b
    terms: dict[int, Fraction] = {}
    for x in (a, b):
        for k, c in (x.exact if isinstance(x, Folded) else ((0, x),)):
            terms[k] = terms.get(k, Fraction(0)) + c
    return Folded(float(a) + float(b), tuple(sorted((k, c) for k, c in terms.items() if c != 0)))


def _safe(name: str) -> str:
    return "".join(ch if ch.isalnum() else "_" for ch in name).strip("_")


# numeric polynomial: {((var, exp), ...): constant}, the constant exact
# (Fraction) unless %pi was folded into it (float)
NumPoly = dict[tuple[tuple[str, int], ...], "Fraction | float"]


def _common_factor(p: NumPoly) -> Fraction | None:
    """gcd of the numerators over lcm of the denominators, signed like the
    first term, when every constant is exact and it is not 1."""
    vals = list(p.values())
    if len(vals) < 2 or not all(isinstance(v, Fraction) for v in vals):
        return None
    num, den = 0, 1
    for v in vals:
        num = math.gcd(num, v.numerator)
        den = den * v.denominator // math.gcd(den, v.denominator)
    g = Fraction(num, den)
    if vals[0] < 0:
        g = -g
    return None if g == 1 else g


class Lowering:
    def __init__(self, params: tuple[str, ...]):
        self.params = params
        self.taken = set(params)
        self.derived: dict[str, tuple[str, Node]] = {}   # atom key -> (name, node)

    def _fresh(self, base: str) -> str:
        name, i = base, 2
        while name in self.taken:
            name, i = f"{base}_{i}", i + 1
        self.taken.add(name)
        return name

    def atom_var(self, key: str, atom: Expr, power: int) -> tuple[str, int]:
        """Map an atom (and a negative power) to a variable name and a positive power."""
        if isinstance(atom, Sym):
            if power > 0:
                return atom.name, power
            if key + "^-1" not in self.derived:
                self.derived[key + "^-1"] = (self._fresh("inv_" + _safe(atom.name)), ("/", ONE, ("ref", atom.name)))
            return self.derived[key + "^-1"][0], -power
        if isinstance(atom, Call) and len(atom.args) == 1 and isinstance(atom.args[0], Sym):
            if key not in self.derived:
                arg = atom.args[0].name
                self.derived[key] = (self._fresh(f"{atom.func}_{_safe(arg)}"), ("call", atom.func, ("ref", arg)))
            name = self.derived[key][0]
            if power > 0:
                return name, power
            if key + "^-1" not in self.derived:
                self.derived[key + "^-1"] = (self._fresh("inv_" + name), ("/", ONE, ("ref", name)))
            return self.derived[key + "^-1"][0], -power
        raise ValueError(f"cannot lower the atom {to_maxima(atom)}: only symbols and calls of a symbol are supported")

    def numeric(self, p: Poly) -> NumPoly:
        atoms = dict(p.atoms)
        out: NumPoly = {}
        for mono, c in p.terms:
            pi_power = 0
            vs: dict[str, int] = {}
            for key, e in mono:
                if key == "%pi":
                    pi_power += e
                    continue
                v, k = self.atom_var(key, atoms[key], e)
                vs[v] = vs.get(v, 0) + k
            m = tuple(sorted(vs.items()))
            val = _const_value(c, pi_power)
            out[m] = _const_sum(out[m], val) if m in out else val
        return {m: v for m, v in out.items() if v != 0}


def _monomial_node(mono, c: Fraction | float) -> Node:
    node: Node | None = None
    for v, e in mono:
        for _ in range(e):
            node = ("ref", v) if node is None else mul(node, ("ref", v))
    if node is None:
        return lit(c)
    return mul(lit(c), node) if c != 1 else node


def horner(p: NumPoly, order: dict[str, int]) -> Node:
    """Greedy multivariate Horner: factor out the variable in most terms."""
    if not p:
        return ZERO
    if len(p) == 1:
        (m, c), = p.items()
        return _monomial_node(m, c)
    g = _common_factor(dict(sorted(p.items())))
    if g is not None:
        return mul(lit(g), horner({m: c / g for m, c in p.items()}, order))
    counts: dict[str, int] = {}
    for m in p:
        for v, _ in m:
            counts[v] = counts.get(v, 0) + 1
    if not counts:
        return lit(next(iter(p.values())))   # the constant term alone
    v = min(counts, key=lambda x: (-counts[x], order.get(x, 0), x))
    if counts[v] == 1:   # no sharing left: print the terms as they are
        node = None
        for m, c in sorted(p.items()):
            t = _monomial_node(m, c)
            node = t if node is None else add(node, t)
        return node
    q: NumPoly = {}
    r: NumPoly = {}
    for m, c in p.items():
        d = dict(m)
        if v in d:
            d[v] -= 1
            if d[v] == 0:
                del d[v]
            q[tuple(sorted(d.items()))] = c
        else:
            r[m] = c
    return add(horner(r, order), mul(("ref", v), horner(q, order)))


def naive_multiplications(p: NumPoly) -> int:
    n = 0
    for m, c in p.items():
        factors = sum(e for _, e in m)
        n += max(factors - 1, 0) + (1 if abs(c) != 1 and factors else 0)
    return n


def count_multiplications(roots: list[Node]) -> int:
    """Multiplications and divisions as printed: each statement is a tree."""
    total, stack = 0, list(roots)
    while stack:
        n = stack.pop()
        if n[0] in ("lit", "ref"):
            continue
        total += n[0] in ("*", "/")
        stack.extend(c for c in n[1:] if isinstance(c, tuple))
    return total


def share(roots: list[Node], reserved: set[str], prefix: str = "w") -> tuple[list[Assign], list[Node]]:
    """Hash-consed DAG -> temporaries for nodes used more than once."""
    uses: dict[Node, int] = {}

    def count(n: Node) -> None:
        uses[n] = uses.get(n, 0) + 1
        if uses[n] == 1 and n[0] not in ("lit", "ref"):
            for c in n[1:]:
                if isinstance(c, tuple):
                    count(c)

    for r in roots:
        count(r)
    names: dict[Node, str] = {}
    temps: list[Assign] = []
    counter = [0]

    def fresh() -> str:
        while True:
            counter[0] += 1
            name = f"{prefix}{counter[0]}"
            if name not in reserved:
                return name

    def emit(n: Node) -> Node:
        if n in names:
            return ("ref", names[n])
        if n[0] in ("lit", "ref"):
            return n
        kids = tuple(emit(c) if isinstance(c, tuple) else c for c in n[1:])
        new = (n[0],) + kids
        if uses.get(n, 0) > 1 and n[0] != "neg":
            name = fresh()
            names[n] = name
            temps.append(Assign(name, new))
            return ("ref", name)
        return new

    out = [emit(r) for r in roots]
    return temps, out


def lower(poly: Polynomial, name: str, doc: str, params: tuple[str, ...], param_docs: tuple[str, ...],
          origin: Span, shared: bool = True) -> FunctionIR:
    lw = Lowering(params)
    nums = [lw.numeric(c) for c in poly.coefficients]
    order = {p: i for i, p in enumerate(params)}
    naive = sum(naive_multiplications(p) for p in nums)
    if shared:
        roots = [horner(p, order) for p in nums]
    else:
        roots = []
        for p in nums:
            node: Node = ZERO
            for m, c in sorted(p.items()):
                node = add(node, _monomial_node(m, c))
            roots.append(node)
    derived = [Assign(n, node) for n, node in lw.derived.values()]  # creation order: dependencies first
    if shared:
        temps, coeffs = share(roots, lw.taken | {a.name for a in derived})
    else:
        temps, coeffs = [], roots
    mults = count_multiplications([a.node for a in derived] + [a.node for a in temps] + coeffs)
    return FunctionIR(name, doc, params, param_docs, tuple(derived), tuple(temps), tuple(coeffs),
                      origin, mults, naive)
