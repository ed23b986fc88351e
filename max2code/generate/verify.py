"""Verified output: every function the generator is about to print is
checked, in exact arithmetic, against the polynomial Maxima gave.

derive.py proves that the collected coefficients equal Maxima's polynomial
(a second Maxima run); this module proves that what lowering made of them
(Horner forms, shared temporaries, folded constants, derived inputs such as
sin(f) and 1/x) still computes those coefficients, for every function that is
printed:

* each variant's coefficient function, against the full equation's
  polynomial with the variant's conditions (its parameters set to 0)
  substituted, coefficient by coefficient;
* the selection entry: every switch mask is mapped to a variant whose
  conditions that mask makes true (so its coefficients are exact there);
* a fragment's coefficient expressions (the paper's form);
* with --exact: the exact gap, its derivative and the shift, against
  Maxima's expressions for them.

How: both sides are evaluated at random points in the integers modulo a
large prime p (2^61 - 1).  Rationals map into that field exactly (a/b is a
times the inverse of b), so this is exact rational evaluation carried out
with small integers.  A literal is evaluated as the exact constant it was
rounded from (lower.py keeps it in the node) and is separately checked to
round to the double that is printed.  %pi is a random field element of its
own, and a call such as sin(f) or sin(w*t + phi) takes a pseudo-random value
determined by the function and the exact value of its argument (so sin and
cos are independent unknowns, as they are to the lowering), except at 0,
where Maxima folds sin(0) = 0, cos(0) = 1.  By the Schwartz-Zippel lemma a
coefficient that differs as a polynomial (a flipped sign, a dropped or
misplaced term) agrees at a random point with probability at most
degree / p, about 10^-17 here, and two points are used.  The points come from
a fixed seed, so a run is reproducible; the check never changes the output.

A mismatch is an InternalError naming the function and the power of the
variable, raised before anything is rendered or written.
"""
from __future__ import annotations

import hashlib
from fractions import Fraction

import mpmath

from max2code.errors import InternalError, Span
from max2code.generate.expr import Add, Call, Eq, Expr, Mul, Num, Pow, Poly, Sym

PRIMES = (2 ** 61 - 1, 2 ** 89 - 1, 2 ** 107 - 1)   # the next one is used when a denominator vanishes modulo p
POINTS = 2                                           # random points per function
SEED = "max2code-verify-1"
# values Maxima folds at an argument of 0 (a variant's zero may be a call's argument)
AT_ZERO = {"sin": 0, "cos": 1, "abs": 0, "sqrt": 0}


class _Unlucky(Exception):
    """A denominator or divisor is 0 modulo p: evaluate with the next prime."""


class Mismatch(Exception):
    def __init__(self, what: str):
        super().__init__(what)
        self.what = what


class Field:
    """Evaluation modulo the prime p at point number `k`."""

    def __init__(self, p: int, k: int):
        self.p = p
        self.k = k
        self.calls: dict[tuple[str, int], int] = {}
        self.consts: dict[object, int] = {}
        self.pi = self.draw("%pi")

    def draw(self, what: str) -> int:
        """A pseudo-random non-zero element, fixed by the seed, p, k and `what`."""
        h = hashlib.blake2b(f"{SEED}:{self.p}:{self.k}:{what}".encode(), digest_size=24).digest()
        return int.from_bytes(h, "little") % (self.p - 1) + 1

    def inv(self, x: int) -> int:
        if x % self.p == 0:
            raise _Unlucky
        return pow(x, -1, self.p)

    def const(self, e) -> int:
        """A Fraction, or a PiSum ((power of %pi, Fraction), ...)."""
        got = self.consts.get(e)
        if got is None:
            if isinstance(e, tuple):
                got = sum(self.const(c) * pow(self.pi, k, self.p) for k, c in e) % self.p
            else:
                e = Fraction(e)
                got = e.numerator * self.inv(e.denominator) % self.p
            self.consts[e] = got
        return got

    def call(self, func: str, x: int) -> int:
        if x == 0 and func in AT_ZERO:
            return AT_ZERO[func]
        key = (func, x)
        if key not in self.calls:
            self.calls[key] = self.draw(f"{func}({x})")
        return self.calls[key]


# ---------------------------------------------------------------- literals
def check_literal(n: tuple) -> str | None:
    """Why the literal node `n` does not print its exact value, or None."""
    if len(n) < 3:
        return None
    value, exact = n[1], n[2]
    if isinstance(exact, tuple):          # with %pi: each part rounded from 50 digits, then summed in doubles
        with mpmath.workdps(50):
            parts = [mpmath.mpf(c.numerator) / c.denominator * mpmath.pi ** k for k, c in exact]
            ok = abs(sum(parts) - value) <= sum(abs(x) for x in parts) * len(parts) * mpmath.mpf(2) ** -52
    else:
        ok = float(exact) == value
    return None if ok else f"the literal {value!r} is not the double nearest {exact}"


# ---------------------------------------------------------------- evaluation
def eval_nodes(roots, env: dict[str, int], F: Field, literals: dict | None = None) -> list[int]:
    """The value of each node of `roots` (language-neutral code, lower.py's
    Node), the references read from `env`.  Subexpressions used more than
    once are temporaries of their own (lowering shares them), evaluated once
    through `env`.  With `literals` (a dict), every literal is also checked
    (check_literal): its complaint, or None, is stored under (double, exact)."""
    p = F.p

    def ev(n) -> int:
        op = n[0]
        if op == "ref":
            return env[n[1]]
        if op == "*":
            return ev(n[1]) * ev(n[2]) % p
        if op == "+" or op == "-":
            spine = []               # a long sum is a left-leaning chain: walk it without recursion
            while n[0] == "+" or n[0] == "-":
                spine.append(n)
                n = n[1]
            v = ev(n)
            for s in reversed(spine):
                v = v + ev(s[2]) if s[0] == "+" else v - ev(s[2])
            return v % p
        if op == "lit":
            exact = n[2] if len(n) > 2 else Fraction(n[1])
            if literals is not None:
                key = (n[1], exact)
                if key not in literals:
                    literals[key] = check_literal(n)
            return F.const(exact)
        if op == "neg":
            return -ev(n[1]) % p
        if op == "call":
            return F.call(n[1], ev(n[2]))
        if op == "/":
            return ev(n[1]) * F.inv(ev(n[2])) % p
        raise TypeError(f"unknown node {op!r}")

    return [ev(r) for r in roots]


def eval_assigned(assigns, roots, env: dict[str, int], F: Field, literals: dict | None = None) -> list[int]:
    """Statements `name = node` in order (derived inputs, temporaries), then `roots`."""
    env = dict(env)
    for a in assigns:
        env[a.name] = eval_nodes([a.node], env, F, literals)[0]
    return eval_nodes(roots, env, F, literals)


def eval_expr(e: Expr, env: dict[str, int], F: Field) -> int:
    """Maxima's expression `e` (expr.py) modulo p."""
    p = F.p
    if isinstance(e, Num):
        return F.const(e.value)
    if isinstance(e, Sym):
        return F.pi if e.name == "%pi" else env[e.name]
    if isinstance(e, Call):
        if len(e.args) != 1:
            raise Mismatch(f"cannot evaluate the call {e.func} of {len(e.args)} arguments")
        return F.call(e.func, eval_expr(e.args[0], env, F))
    if isinstance(e, Add):
        return sum(eval_expr(x, env, F) for x in e.terms) % p
    if isinstance(e, Mul):
        v = 1
        for x in e.factors:
            v = v * eval_expr(x, env, F) % p
        return v
    if isinstance(e, Pow):
        if not (isinstance(e.exp, Num) and e.exp.value.denominator == 1):
            raise Mismatch("a non-integer power")
        n = int(e.exp.value)
        b = eval_expr(e.base, env, F)
        return pow(b, n, p) if n >= 0 else pow(F.inv(b), -n, p)
    if isinstance(e, Eq):
        return (eval_expr(e.lhs, env, F) - eval_expr(e.rhs, env, F)) % p
    raise TypeError(e)


def _atom_value(atom: Expr, env: dict[str, int], F: Field) -> int:
    if isinstance(atom, Sym):
        return F.pi if atom.name == "%pi" else env[atom.name]
    return eval_expr(atom, env, F)


class PolyPoint:
    """The coefficients of a polynomial at one point, and at that point with
    any set of parameters set to 0, without evaluating every monomial again:
    a monomial holding a zeroed parameter vanishes, the rest keep their value
    (unless a zeroed parameter is the argument of one of their calls)."""

    def __init__(self, coefficients: tuple[Poly, ...], env: dict[str, int], F: Field):
        self.F = F
        self.env = env
        self.terms: list[list[tuple[frozenset, frozenset, int, tuple, Fraction, dict]]] = []
        for c in coefficients:
            atoms = dict(c.atoms)
            vals = {k: _atom_value(a, env, F) for k, a in atoms.items()}
            syms = {k: a.name for k, a in atoms.items() if isinstance(a, Sym)}
            inner = {k: _symbols_of(a) for k, a in atoms.items() if not isinstance(a, Sym)}
            row = []
            for mono, coef in c.terms:
                v = F.const(coef)
                for k, e in mono:
                    v = v * (pow(vals[k], e, F.p) if e >= 0 else pow(F.inv(vals[k]), -e, F.p)) % F.p
                pos = frozenset(syms[k] for k, e in mono if k in syms and e > 0)
                neg = frozenset(syms[k] for k, e in mono if k in syms and e < 0)
                in_calls = frozenset(s for k, _ in mono if k in inner for s in inner[k])
                row.append((pos, neg | in_calls, v, mono, coef, atoms))
            self.terms.append(row)

    def coefficients(self, zeros: frozenset = frozenset()) -> list[int] | None:
        """The coefficients with `zeros` set to 0; None where that divides by 0."""
        F, out = self.F, []
        env = None
        for row in self.terms:
            total = 0
            for pos, other, v, mono, coef, atoms in row:
                if zeros and pos & zeros:
                    continue
                if zeros and other & zeros:
                    if env is None:
                        env = {**self.env, **{z: 0 for z in zeros}}
                    try:
                        v = F.const(coef)
                        for k, e in mono:
                            x = _atom_value(atoms[k], env, F)
                            v = v * (pow(x, e, F.p) if e >= 0 else pow(F.inv(x), -e, F.p)) % F.p
                    except _Unlucky:
                        return None
                total += v
            out.append(total % F.p)
        return out


def _symbols_of(e: Expr) -> set[str]:
    if isinstance(e, Sym):
        return {e.name}
    out: set[str] = set()
    for x in getattr(e, "args", ()) or getattr(e, "terms", ()) or getattr(e, "factors", ()):
        out |= _symbols_of(x)
    if isinstance(e, Pow):
        out |= _symbols_of(e.base) | _symbols_of(e.exp)
    return out


# ---------------------------------------------------------------- the checks
def _point(params, F: Field) -> dict[str, int]:
    return {name: F.draw("param:" + name) for name in params}


def _trimmed(values: list[int]) -> list[int]:
    values = list(values)
    while values and values[-1] == 0:
        values.pop()
    return values


class Verifier:
    """Checks for one generated file; raise_first() reports the first failure."""

    def __init__(self, polynomial, params: tuple[str, ...], variable: str, origin: Span):
        self.polynomial = polynomial
        self.params = tuple(params)
        self.variable = variable
        self.origin = origin

    def _fail(self, what: str):
        raise InternalError(f"{self.origin}: internal error: {what}; no file was written (please report this: "
                            "max2code checks every function it prints against Maxima's polynomial)")

    def _with_prime(self, job):
        for p in PRIMES:
            try:
                return job(p)
            except _Unlucky:
                continue
        self._fail("the generated code could not be checked: it divides by zero, or a denominator vanishes "
                   "modulo every prime tried")

    def coefficient_functions(self, functions) -> None:
        """`functions`: (FunctionIR, zeros, own polynomial or None).  Each must
        equal the full polynomial with its zeros substituted (or its own
        polynomial where that substitution divides by zero)."""
        def job(p):
            for k in range(POINTS):
                F = Field(p, k)
                env = _point(self.params, F)
                full = PolyPoint(self.polynomial.coefficients, env, F)
                for fn, zeros, own in functions:
                    zs = frozenset(zeros)
                    expected = full.coefficients(zs)
                    if expected is None and own is not None:
                        expected = PolyPoint(own.coefficients, {**env, **{z: 0 for z in zs}}, F).coefficients()
                    if expected is None:
                        self._fail(f"{fn.name}: Maxima's polynomial is undefined where {', '.join(sorted(zs))} = 0")
                    literals = {} if k == 0 else None
                    got = eval_assigned(fn.derived + fn.temps, fn.coefficients, {**env, **{z: 0 for z in zs}}, F,
                                        literals)
                    self._compare(fn.name, got, expected, zs)
                    self._literals(fn.name, literals)
        self._with_prime(job)

    def _compare(self, name: str, got: list[int], expected: list[int], zeros: frozenset) -> None:
        where = f" (where {' = '.join(sorted(zeros))} = 0)" if zeros else ""
        for k in range(max(len(got), len(expected))):
            g = got[k] if k < len(got) else 0
            e = expected[k] if k < len(expected) else 0
            if g != e:
                if k >= len(got):
                    self._fail(f"the generated function {name} has degree {len(got) - 1} but Maxima's polynomial"
                               f"{where} has a non-zero coefficient of {self.variable}^{k}")
                self._fail(f"the generated function {name} differs from Maxima's polynomial{where} in the "
                           f"coefficient of {self.variable}^{k}")

    def _literals(self, name: str, literals: dict | None) -> None:
        for why in (literals or {}).values():
            if why:
                self._fail(f"the generated function {name}: {why}")

    def fragment(self, nodes) -> None:
        """A fragment's coefficient expressions (derived inputs inlined)."""
        def job(p):
            for k in range(POINTS):
                F = Field(p, k)
                env = _point(self.params, F)
                expected = PolyPoint(self.polynomial.coefficients, env, F).coefficients()
                literals = {} if k == 0 else None
                self._compare("(the fragment's terms)", eval_nodes(list(nodes), env, F, literals), expected,
                              frozenset())
                self._literals("(the fragment's terms)", literals)
        self._with_prime(job)

    def selection(self, selection, variants) -> None:
        """Each mask's variant must be exact for it: its conditions are among
        the parameters that mask sets to 0 (the variant itself is checked by
        coefficient_functions), and the entry reports that variant's degree."""
        by_name = {v.name: v for v in variants}
        for case in selection.cases:
            v = by_name.get(case.name)
            if v is None:
                self._fail(f"{selection.name} selects {case.name}, which is not generated")
            if case.degree != v.function.degree:
                self._fail(f"{selection.name} reports degree {case.degree} for {case.name}, which has degree "
                           f"{v.function.degree}")
            for mask in case.masks:
                zero = {q for i, (_, ps) in enumerate(selection.switches) if mask >> i & 1 for q in ps}
                missing = sorted(set(v.zeros) - zero)
                if missing:
                    on = [label for i, (label, _) in enumerate(selection.switches) if mask >> i & 1] or ["none"]
                    self._fail(f"{selection.name} selects {case.name} for the switches {'+'.join(on)}, but it is "
                               f"exact only when {', '.join(missing)} = 0 too")
            if case.degree > selection.max_degree:
                self._fail(f"{selection.name}: degree {case.degree} of {case.name} exceeds its maximum "
                           f"{selection.max_degree}")

    def exact_section(self, section) -> None:
        """The exact gap, its derivative and the shift against Maxima's expressions."""
        if section.gap_expr is None:
            self._fail(f"{section.name}: the exact section carries no expressions to check")
        t = section.variable
        checks = [(section.gap, [section.gap_expr]), (section.gap_dt, [section.gap_dt_expr]),
                  (section.shift, [e if e is not None else Sym(p) for p, e in zip(section.params, section.shift_exprs)])]
        checks = [(fn, exprs) for fn, exprs in checks if fn is not None]    # a polynomial gap has no shift

        def job(p):
            for k in range(POINTS):
                F = Field(p, k)
                env = _point(tuple(section.params) + (t,), F)
                for fn, exprs in checks:
                    literals = {} if k == 0 else None
                    got = eval_assigned(fn.temps, fn.outputs, env, F, literals)
                    for i, (g, e) in enumerate(zip(got, exprs)):
                        if g != eval_expr(e, env, F):
                            part = f"the value for {section.params[i]}" if fn.kind == "vector" else "its value"
                            self._fail(f"the generated function {fn.name} differs from Maxima's expression in {part}")
                    if len(got) != len(exprs):
                        self._fail(f"the generated function {fn.name} has {len(got)} outputs, not {len(exprs)}")
                    self._literals(fn.name, literals)
        self._with_prime(job)
