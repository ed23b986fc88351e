"""The exact motion of a .mxm file: the pieces behind exact-motion contact
times (docs/exact-motion.md), derived by Maxima and checked.

A file declares which Maxima function of its text approximates what
(`exact SIN(w, phi) { sin(w*t + phi) }`) and how each parameter moves when
the clock restarts at time t (`shift a { a + b*t + c*t^2/2 }`).  From that:

* the exact gap G(p, t) (the text's value with SIN replaced by the exact
  expression) and its derivative dG/dt, printed without expanding, so that
  position differences such as a - g are formed first;
* the shift p -> p(t0), checked by Maxima: G(p, t0 + t) - G(p(t0), t) = 0;
* each approximation is checked to be the Taylor polynomial in t of its exact
  expression, of some degree N; its error on [0, h] is then at most
  max|d^(N+1)/dt^(N+1) exact| h^(N+1) / (N+1)!, with the maximum bounded by a
  majorant (|sin|, |cos| <= 1);
* the truncation bound E(p, h) >= |G - P| on [0, h], P the polynomial: Maxima
  expands the text with SIN = its polynomial + an error atom e_i, and
  E = sum over the error monomials of prod(delta_i^k_i) sum_j |c_j| h^j;
* a rounding scale S(p, t) (a majorant of G's evaluation error, in units of
  the unit roundoff) and the orbits' angular rates (window sizing).

A file without `exact` declarations whose Maxima text approximates nothing
(no Taylor sums: `sum`, `taylor`, `powerseries`; no parameter with a
rotation's role: orbit_radius, angular_velocity, phase) has a polynomial that *is*
the exact gap (bodies without rotation: accelerating spheres, a ball in an
arena, a point on a polynomial path).  Then only G, dG/dt and S are derived
(one Maxima run, no shifts needed), and the contact time is the polynomial's
own first root over the whole horizon (the runtimes' poly_toc: no windows,
the same rules at t = 0 as the windowed driver).
"""
from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from max2code.generate.collect import collect
from max2code.errors import SourceError, Span
from max2code.generate.expr import Add, Call, Eq, Expr, Mul, Num, Poly, Pow, Sym, NotPolynomial, to_maxima
from max2code.generate.lower import PI, Assign, Lowering, Node, add, horner, lit, mul, neg, refs, share
from max2code.generate.maxima import DEFAULT_TIMEOUT, Statement, run_maxima
from max2code.generate.reader import MaximaOutputError, read_expr

EPS_PREFIX = "__m2c_eps_"


@dataclass(frozen=True)
class ScalarFn:
    """One generated function of the exact section: the parameters, then
    `extra` real inputs; temporaries; and its outputs.

    kind "value": one output.  kind "vector": one output per parameter (the
    shift).  kind "max": outputs in pairs (weight, rate): the result is the
    largest rate whose weight is not zero (0 when none)."""
    name: str
    doc: str
    kind: str
    extra: tuple[str, ...]
    temps: tuple[Assign, ...]
    outputs: tuple[Node, ...]
    unused_params: tuple[str, ...]


@dataclass(frozen=True)
class ExactSection:
    """What the templates print for the exact motion."""
    name: str                      # the equation
    params: tuple[str, ...]
    variable: str
    gap: ScalarFn
    gap_dt: ScalarFn
    scale: ScalarFn
    shift: ScalarFn | None
    rate: ScalarFn | None
    truncation: ScalarFn | None
    approximations: tuple[str, ...]   # one line per approximation, for the header
    origin: Span
    polynomial: bool = False       # the polynomial is the exact gap: no shift, rate nor truncation (None)
    # Maxima's expressions behind gap, gap_dt and shift (one per parameter, None
    # where the parameter does not move): verify.py checks the printed functions
    # against them, and the polynomial case's references use gap and gap_dt
    gap_expr: Expr | None = None
    gap_dt_expr: Expr | None = None
    shift_exprs: tuple = ()
    # two circles (see circle_layout): the parameters' indices in CIRCLE_ROLES order
    # per body, when Maxima proved the exact gap to be their squared centre distance
    # minus the squared sum of radii; the drivers' whole-horizon bound uses them
    circles: tuple[int, ...] | None = None

    def functions(self) -> tuple[str, ...]:
        """The keys of the generated functions, in the order they are printed."""
        if self.polynomial:
            return ("gap", "gap_dt", "scale")
        return ("gap", "gap_dt", "scale", "truncation", "shift", "rate")


# ---------------------------------------------------------------- two circles
# Per body, in this order: x and y position, x and y velocity, x and y
# acceleration, the orbit radius, the x term's angular velocity and phase,
# the y term's, and the radius (the order of the drivers' index table).
CIRCLE_ROLES = ("position", "position", "velocity", "velocity", "acceleration", "acceleration", "orbit_radius",
                "angular_velocity", "phase", "angular_velocity", "phase", "radius")


def circle_layout(mod, params) -> tuple[tuple[str, ...], str] | None:
    """The parameters of two circles by their roles (`: body K position`
    ...), each body declaring, in order, two positions (x, y), two
    velocities, two accelerations, one orbit radius, two angular velocities
    and two phases (the x term's first) and one radius; with the Maxima
    expression of the gap they must have (the exact text's value is checked
    against it).  None when the roles do not describe two such circles."""
    bodies = sorted({p.body for p in mod.parameters if p.body is not None})
    if bodies != [1, 2] or len(mod.parameters) != len(params):
        return None
    names: list[str] = []
    for b in bodies:
        by_effect: dict[str, list[str]] = {}
        for p in mod.parameters:
            if p.body == b:
                by_effect.setdefault(p.effect, []).append(p.name)
        want = {e: CIRCLE_ROLES.count(e) for e in set(CIRCLE_ROLES)}
        if {e: len(v) for e, v in by_effect.items()} != want:
            return None
        taken = {e: 0 for e in want}
        for e in CIRCLE_ROLES:
            names.append(by_effect[e][taken[e]])
            taken[e] += 1
    t = mod.variable

    def centre(k: int, axis: int) -> str:
        n = names[12 * k:12 * k + 12]
        w, ph = (n[7], n[8]) if axis == 0 else (n[9], n[10])
        return (f"({n[axis]} + {n[2 + axis]}*{t} + {n[4 + axis]}*{t}^2/2 + {n[6]}*sin({w}*{t} + {ph}))")

    gap = (f"({centre(0, 0)} - {centre(1, 0)})^2 + ({centre(0, 1)} - {centre(1, 1)})^2 "
           f"- ({names[11]} + {names[23]})^2")
    return tuple(names), gap


# ---------------------------------------------------------------- Maxima
def _definition_index(stmts: list[Statement], name: str) -> int | None:
    pat = re.compile(rf"\s*{re.escape(name)}\s*\([^)]*\)\s*:=")
    for i, s in enumerate(stmts):
        if pat.match(s.text):
            return i
    return None


def _with_inserted(stmts: list[Statement], inserts: dict[int, list[Statement]]) -> list[Statement]:
    out = []
    for i, s in enumerate(stmts):
        out.append(s)
        out.extend(inserts.get(i, []))
    return out


def _read(text: str, span: Span, what: str) -> Expr:
    try:
        return read_expr(text)
    except MaximaOutputError as exc:
        raise SourceError(span, f"{what}: max2code cannot read Maxima's result: {exc}") from None


def _fresh(k: int) -> list[str]:
    return [f"__m2c_x{i + 1}" for i in range(k)]


def _public(text: str, approximations=()) -> str:
    """Maxima text as a user may read it: the names max2code gives its own
    helper functions and variables (prefix __m2c_) replaced by the file's
    names (an error term of SIN(...) reads SIN(...), a fresh argument the
    formal it stands for, the restart time t0)."""
    for a in approximations:
        text = re.sub(rf"__m2c_(?:eps|approx|exact)_{re.escape(a.name)}\b", a.name, text)
    formals = next((a.formals for a in approximations), ())
    text = re.sub(r"__m2c_x([0-9]+)", lambda m: formals[int(m.group(1)) - 1] if int(m.group(1)) <= len(formals)
                  else f"x{m.group(1)}", text)
    return text.replace("__m2c_t0", "t0").replace("__m2c_p", "the gap")


# Maxima constructs that approximate: a text using one without an `exact`
# declaration does not give the exact gap
ROTATION = ("orbit_radius", "angular_velocity", "phase")   # parameter roles of a rotation
TAYLOR = re.compile(r"(?<![A-Za-z0-9_%])(sum|taylor|powerseries|taytorat|nusum)\s*\(")


@dataclass(frozen=True)
class _Approx:
    name: str
    formals: tuple[str, ...]
    degree: int                 # N: the approximation is the degree-N Taylor polynomial
    dn: Expr                    # d^(N+1)/dt^(N+1) of the exact expression, in __m2c_x1..
    d1: Expr                    # d/dt of the exact expression
    span: Span


def derive_exact(d, progress: bool = False, use_cache: bool = True, timeout: float = DEFAULT_TIMEOUT):
    """Run Maxima for the exact pieces of derivation `d` (pipeline.Derivation)."""
    from max2code.generate.derive import note as _note, parameters_of

    mod = d.module
    if not mod.approximations:
        return _derive_polynomial_gap(d, progress, use_cache, timeout)
    params, _ = parameters_of(d)
    t = mod.variable
    stmts = [s for s in d.statements]
    where: dict[int, list] = {}
    for a in mod.approximations:
        k = _definition_index(stmts, a.name)
        if k is None:
            raise SourceError(a.span, f"the Maxima text defines no function '{a.name}' ('{a.name}(...) := ...')")
        where.setdefault(k, []).append(a)
    known = set(params)
    for sh in mod.shifts:
        if sh.param not in known:
            raise SourceError(sh.span, f"'shift {sh.param}': '{sh.param}' is not a parameter of the equation")
    if not mod.shifts:
        raise SourceError(mod.approximations[0].span, "the exact motion needs 'shift' declarations: how each "
                                                       "parameter moves when the clock restarts at time t")

    def exact_def(a, fn_name: str | None = None) -> Statement:
        return Statement(f"{fn_name or a.name}({', '.join(a.formals)}) := ({a.text})$", a.text_span)

    # run 1: the exact text
    inserts = {k: [exact_def(a) for a in group] for k, group in where.items()}
    shift_subst = ", ".join(f"{sh.param} = subst(__m2c_t0, {t}, ({sh.text}))" for sh in mod.shifts)
    items = {"gap": "__m2c_p", "gap_dt": f"diff(__m2c_p, {t})",
             "shiftcheck": f"expand(psubst([{t} = {t} + __m2c_t0], __m2c_p) - psubst([{shift_subst}], __m2c_p))"}
    for i, sh in enumerate(mod.shifts):
        items[f"shift{i}"] = f"({sh.text})"
    layout = circle_layout(mod, params)
    if layout is not None:
        items["circles"] = f"expand(__m2c_p - ({layout[1]}))"
    _note(progress, f"{mod.path}: Maxima derives the exact gap, its derivative and checks the shift ...")
    r1 = run_maxima(list(d.prelude), _with_inserted(stmts, inserts), items, fallback=mod.approximations[0].span,
                    timeout=timeout, use_cache=use_cache)
    if r1.items["shiftcheck"].strip() != "0":
        again = run_maxima(list(d.prelude), _with_inserted(stmts, inserts),
                           {"c": f"trigsimp(trigexpand({items['shiftcheck']}))"},
                           fallback=mod.shifts[0].span, timeout=timeout, use_cache=use_cache)
        if again.items["c"].strip() != "0":
            raise SourceError(mod.shifts[0].span, "the shifts do not restart the clock: Maxima finds "
                                                  "gap(p, t0 + t) - gap(shift(p, t0), t) = "
                                                  f"{_public(again.items['c'], mod.approximations)[:100]} (not 0)")

    # run 2: each approximation as its polynomial plus an error atom
    inserts = {}
    for k, group in where.items():
        extra = []
        for a in group:
            x = _fresh(len(a.formals))
            extra += [Statement(f"define(__m2c_approx_{a.name}({', '.join(x)}), {a.name}({', '.join(x)}))$", a.span),
                      Statement(f"{a.name}({', '.join(a.formals)}) := __m2c_approx_{a.name}({', '.join(a.formals)}) + "
                                f"{EPS_PREFIX}{a.name}({', '.join(a.formals)})$", a.span),
                      exact_def(a, f"__m2c_exact_{a.name}")]
        inserts[k] = extra
    items2 = {"eps": "expand(__m2c_p)"}
    for i, a in enumerate(mod.approximations):
        x = ", ".join(_fresh(len(a.formals)))
        n = f"hipow(expand(__m2c_approx_{a.name}({x})), {t})"
        items2[f"deg{i}"] = n
        items2[f"chk{i}"] = f"ratsimp(__m2c_approx_{a.name}({x}) - taylor(__m2c_exact_{a.name}({x}), {t}, 0, {n}))"
        items2[f"dn{i}"] = f"diff(__m2c_exact_{a.name}({x}), {t}, {n} + 1)"
        items2[f"d1{i}"] = f"diff(__m2c_exact_{a.name}({x}), {t})"
    _note(progress, f"{mod.path}: Maxima checks the approximations and derives the truncation bound ...")
    r2 = run_maxima(list(d.prelude), _with_inserted(stmts, inserts), items2, fallback=mod.approximations[0].span,
                    timeout=timeout, use_cache=use_cache)
    approx = []
    for i, a in enumerate(mod.approximations):
        if r2.items[f"chk{i}"].strip() != "0":
            raise SourceError(a.span, f"'{a.name}' is not the Taylor polynomial in {t} of {a.text.strip()} "
                                      f"(Maxima finds the difference {_public(r2.items[f'chk{i}'], [a])[:80]})")
        approx.append(_Approx(a.name, a.formals, int(r2.items[f"deg{i}"]), _read(r2.items[f"dn{i}"], a.span, a.name),
                              _read(r2.items[f"d1{i}"], a.span, a.name), a.span))

    origin = mod.approximations[0].span
    gap = _read(r1.items["gap"], origin, "the exact gap")
    gap_dt = _read(r1.items["gap_dt"], origin, "the exact gap's derivative")
    shifts = {sh.param: _read(r1.items[f"shift{i}"], sh.text_span, f"shift {sh.param}") for i, sh in enumerate(mod.shifts)}
    for e, span, what in [(gap, origin, "the exact gap"), (gap_dt, origin, "its derivative")] + \
                         [(shifts[sh.param], sh.text_span, f"shift {sh.param}") for sh in mod.shifts]:
        _check_symbols(e, known | {t}, span, what)
    try:
        eps_poly = collect(_read(r2.items["eps"], origin, "the polynomial with error terms"), t)
    except NotPolynomial as exc:
        raise SourceError(origin, f"with error terms the text is not a polynomial in {t}: "
                                  f"{_public(str(exc), mod.approximations)}") from None
    # at zero error the polynomial must be the one the file generates
    def trimmed(ps):
        ps = list(ps)
        while ps and ps[-1].is_zero():
            ps.pop()
        return tuple(ps)
    if trimmed(_drop_eps(c) for c in eps_poly.coefficients) != trimmed(d.polynomial.coefficients):
        raise SourceError(origin, "internal error: the polynomial with zero error terms differs from the file's "
                                  "polynomial; please report this")
    section = _build(mod, params, t, gap, gap_dt, shifts, eps_poly, approx, origin)
    if layout is not None and r1.items["circles"].strip() == "0":
        section = dataclasses.replace(section, circles=tuple(params.index(n) for n in layout[0]))
    return section


def _derive_polynomial_gap(d, progress: bool, use_cache: bool, timeout: float) -> "ExactSection":
    """The exact pieces of a file whose polynomial is the exact gap (no
    `exact` declarations): G as the text gives it (not expanded), dG/dt and
    the rounding scale.  A text that approximates (a Taylor sum) is refused
    at the statement that does, since its polynomial is not the exact gap."""
    from max2code.generate.derive import note as _note, parameters_of

    mod = d.module
    for prm in mod.parameters:
        if prm.effect in ROTATION:
            raise SourceError(prm.span, f"--exact: '{prm.name}' is an {prm.effect}, so the polynomial approximates a "
                                        "rotation: it needs an 'exact NAME(args) { expression }' declaration of what "
                                        "the approximation stands for and 'shift' declarations "
                                        "(docs/mxm-language.md, 'The exact motion')")
    for st in d.statements:
        m = TAYLOR.search(st.text)
        if m:
            raise SourceError(st.span, f"--exact: this statement approximates with {m.group(1)}(...), so the polynomial "
                                       "is not the exact gap: declare what the approximation stands for with "
                                       "'exact NAME(args) { expression }' and how the parameters move with 'shift' "
                                       "(docs/mxm-language.md, 'The exact motion')")
    params, _ = parameters_of(d)
    t = mod.variable
    _note(progress, f"{mod.path}: Maxima derives the exact gap (the polynomial itself) and its derivative ...")
    r = run_maxima(list(d.prelude), list(d.statements), {"gap": "__m2c_p", "gap_dt": f"diff(__m2c_p, {t})"},
                   fallback=d.origin, timeout=timeout, use_cache=use_cache)
    gap = _read(r.items["gap"], d.origin, "the exact gap")
    gap_dt = _read(r.items["gap_dt"], d.origin, "the exact gap's derivative")
    for e, what in ((gap, "the exact gap"), (gap_dt, "its derivative")):
        _check_symbols(e, set(params) | {t}, d.origin, what)
        if _calls_with(e, t):
            raise SourceError(d.origin, f"--exact: {what} calls sin or cos of {t}: declare the approximation "
                                        "with 'exact NAME(args) { expression }'")
    name = mod.equation

    def one(fname, doc, node):
        return _scalar(fname, doc, "value", params, (t,), [node], [])

    return ExactSection(
        name, tuple(params), t,
        one(f"{name}_gap", "the exact gap at time t (zero at contact)", lower_expr(gap, t)),
        one(f"{name}_gap_dt", "d/dt of the exact gap at time t", lower_expr(gap_dt, t)),
        one(f"{name}_gap_scale", "a majorant of the exact gap's rounding error at time t, in units of the unit "
                                 "roundoff", rounding_scale(gap, t)),
        None, None, None,
        ("the polynomial is the exact gap (no approximated functions)",), d.origin, polynomial=True,
        gap_expr=gap, gap_dt_expr=gap_dt)


def _calls_with(e: Expr, t: str) -> bool:
    """Whether e calls a function of an argument that depends on t."""
    if isinstance(e, Call):
        return any(_mentions(a, t) for a in e.args) or any(_calls_with(a, t) for a in e.args)
    for c in (e.terms if isinstance(e, Add) else e.factors if isinstance(e, Mul) else
              (e.base, e.exp) if isinstance(e, Pow) else ()):
        if _calls_with(c, t):
            return True
    return False


def _drop_eps(p: Poly) -> Poly:
    terms = {m: c for m, c in p.terms if not any(k.startswith(EPS_PREFIX) for k, _ in m)}
    return Poly.build(terms, dict(p.atoms))


def _check_symbols(e: Expr, allowed: set[str], span: Span, what: str) -> None:
    if isinstance(e, Sym):
        if e.name not in allowed and e.name != "%pi":
            raise SourceError(span, f"{what} uses '{e.name}', which is neither a parameter nor the variable")
    elif isinstance(e, Call):
        if e.func not in ("sin", "cos"):
            raise SourceError(span, f"{what} calls '{e.func}': only sin and cos can be printed")
        for a in e.args:
            _check_symbols(a, allowed, span, what)
    elif isinstance(e, Pow):
        if not (isinstance(e.exp, Num) and e.exp.value.denominator == 1):
            raise SourceError(span, f"{what} has a non-integer power {to_maxima(e)}")
        _check_symbols(e.base, allowed, span, what)
    elif isinstance(e, Eq):
        raise SourceError(span, f"{what} is an equation inside an expression")
    elif isinstance(e, (Add, Mul)):
        for c in (e.terms if isinstance(e, Add) else e.factors):
            _check_symbols(c, allowed, span, what)


# ---------------------------------------------------------------- lowering
def _mentions(e: Expr, name: str) -> bool:
    if isinstance(e, Sym):
        return e.name == name
    if isinstance(e, Num):
        return False
    if isinstance(e, Call):
        return any(_mentions(a, name) for a in e.args)
    if isinstance(e, Add):
        return any(_mentions(a, name) for a in e.terms)
    if isinstance(e, Mul):
        return any(_mentions(a, name) for a in e.factors)
    if isinstance(e, Pow):
        return _mentions(e.base, name) or _mentions(e.exp, name)
    return True


def _int_exp(e: Pow) -> int:
    assert isinstance(e.exp, Num) and e.exp.value.denominator == 1
    return int(e.exp.value)


def _power(x: Node, n: int) -> Node:
    node = x
    for _ in range(n - 1):
        node = mul(node, x)
    return node


def _t_monomial(term: Expr, t: str) -> tuple[int, list[Expr]] | None:
    """term = (t-free factors) * t^k: (k, factors), else None."""
    if isinstance(term, Sym) and term.name == t:
        return 1, []
    if isinstance(term, Pow) and isinstance(term.base, Sym) and term.base.name == t and _int_exp(term) > 0:
        return _int_exp(term), []
    if not _mentions(term, t):
        return 0, [term]
    if isinstance(term, Mul):
        k, rest = 0, []
        for f in term.factors:
            sub = _t_monomial(f, t) if _mentions(f, t) else (0, [f])
            if sub is None or (sub[0] > 0 and sub[1]):
                return None
            k += sub[0]
            rest += sub[1]
        return k, rest
    return None


def lower_expr(e: Expr, t: str) -> Node:
    """An expression (sums, products, integer powers, sin, cos) as a Node.
    Sums are grouped by power of t and put in Horner form in t, the t-free
    part first: a - g, b - h are formed before anything large is added."""
    if isinstance(e, Num):
        return lit(e.value)
    if isinstance(e, Sym):
        if e.name == "%pi":
            return lit(PI)
        return ("ref", e.name)
    if isinstance(e, Call):
        return ("call", e.func, lower_expr(e.args[0], t))
    if isinstance(e, Pow):
        n = _int_exp(e)
        base = lower_expr(e.base, t)
        if n == 0:
            return lit(1)
        if n > 0:
            return _power(base, n)
        return ("/", lit(1), _power(base, -n))
    if isinstance(e, Mul):
        nums = [f for f in e.factors if isinstance(f, Num)]
        c = Fraction(1)
        for f in nums:
            c *= f.value
        node: Node | None = None
        for f in e.factors:
            if isinstance(f, Num):
                continue
            x = lower_expr(f, t)
            node = x if node is None else mul(node, x)
        if node is None:
            return lit(c)
        return mul(lit(c), node) if c != 1 else node
    if isinstance(e, Add):
        by_power: dict[int, list[Expr]] = {}
        others: list[Expr] = []
        for term in e.terms:
            m = _t_monomial(term, t)
            if m is None:
                others.append(term)
            else:
                k, factors = m
                coef = factors[0] if len(factors) == 1 else (Mul(tuple(factors)) if factors else Num(Fraction(1)))
                by_power.setdefault(k, []).append(coef)
        node: Node | None = None
        for k in range(max(by_power, default=-1), -1, -1):
            if node is not None:
                node = mul(node, ("ref", t))
            coef: Node | None = None    # the coefficient of t^k, summed before it meets the rest
            for c in by_power.get(k, []):
                x = lower_expr(c, t)
                coef = x if coef is None else add(coef, x)
            if coef is not None:
                node = coef if node is None else add(node, coef)
        for term in others:
            x = lower_expr(term, t)
            node = x if node is None else add(node, x)
        return node if node is not None else lit(0)
    raise TypeError(e)


def _abs(n: Node) -> Node:
    if n[0] == "lit":
        return n
    if n[0] == "neg":
        return _abs(n[1])
    if n[0] == "call" and n[1] == "abs":
        return n
    return ("call", "abs", n)


def rounding_scale(e: Expr, t: str) -> Node:
    """A majorant of the evaluation error of `e` in units of the unit
    roundoff: every sum becomes a sum of magnitudes, sin(u) and cos(u) count
    1 + scale(u) (an error in u moves them by as much)."""
    if isinstance(e, Num):
        return lit(abs(e.value))
    if isinstance(e, Sym):
        return lit(PI) if e.name == "%pi" else _abs(("ref", e.name))
    if isinstance(e, Call):
        return add(lit(1), rounding_scale(e.args[0], t))
    if isinstance(e, (Add, Mul)):       # a sum's scale adds its terms', a product's multiplies its factors'
        parts, join = (e.terms, add) if isinstance(e, Add) else (e.factors, mul)
        node = None
        for x in parts:
            s = rounding_scale(x, t)
            node = s if node is None else join(node, s)
        return node
    if isinstance(e, Pow):
        n = _int_exp(e)
        if n >= 0:
            return _power(rounding_scale(e.base, t), n) if n else lit(1)
        return ("/", lit(1), _abs(_power(lower_expr(e.base, t), -n)))
    raise TypeError(e)


def sup_majorant(e: Expr, t: str, h: str, span: Span, what: str) -> Node:
    """An upper bound of |e| for t in [0, h]: t-free parts by their value,
    |sin|, |cos| <= 1, t <= h."""
    if not _mentions(e, t):
        return _abs(lower_expr(e, t))
    if isinstance(e, Sym):
        return ("ref", h)
    if isinstance(e, Call):
        if e.func in ("sin", "cos"):
            return lit(1)
        raise SourceError(span, f"{what}: cannot bound {to_maxima(e)}")
    if isinstance(e, Add):
        node = None
        for x in e.terms:
            s = sup_majorant(x, t, h, span, what)
            node = s if node is None else add(node, s)
        return node
    if isinstance(e, Mul):
        node = None
        for x in e.factors:
            s = sup_majorant(x, t, h, span, what)
            node = s if node is None else mul(node, s)
        return node
    if isinstance(e, Pow) and _int_exp(e) > 0:
        return _power(sup_majorant(e.base, t, h, span, what), _int_exp(e))
    raise SourceError(span, f"{what}: cannot bound {to_maxima(e)} over a window")


def _substitute(e: Expr, names: dict[str, Expr]) -> Expr:
    if isinstance(e, Sym):
        return names.get(e.name, e)
    if isinstance(e, Num):
        return e
    if isinstance(e, Call):
        return Call(e.func, tuple(_substitute(a, names) for a in e.args))
    if isinstance(e, Add):
        return Add(tuple(_substitute(a, names) for a in e.terms))
    if isinstance(e, Mul):
        return Mul(tuple(_substitute(a, names) for a in e.factors))
    if isinstance(e, Pow):
        return Pow(_substitute(e.base, names), _substitute(e.exp, names))
    raise TypeError(e)


def _scalar(name: str, doc: str, kind: str, params, extra, roots: list[Node], derived: list[Assign]) -> ScalarFn:
    reserved = set(params) | set(extra) | {a.name for a in derived} | {name}
    temps, outs = share([a.node for a in derived] + roots, reserved)
    # derived inputs (sin(f) ...) come first: share() saw them as roots too
    nd = len(derived)
    temps = [Assign(a.name, n) for a, n in zip(derived, outs[:nd])] + temps
    # a derived input that share() itself named stays as computed; keep order by dependency
    temps = _order(temps)
    outs = outs[nd:]
    # keep only the temporaries the outputs need
    need: set[str] = set()
    for o in outs:
        refs(o, need)
    for a in reversed(temps):
        if a.name in need:
            refs(a.node, need)
    temps = [a for a in temps if a.name in need]
    used: set[str] = set()
    for a in temps:
        refs(a.node, used)
    for o in outs:
        refs(o, used)
    return ScalarFn(name, doc, kind, tuple(extra), tuple(temps), tuple(outs),
                    tuple(p for p in params if p not in used))


def _order(temps: list[Assign]) -> list[Assign]:
    """Temporaries in dependency order (each after the ones it uses), stable."""
    names = {a.name for a in temps}
    done: set[str] = set()
    out: list[Assign] = []
    pending = list(temps)
    while pending:
        rest = []
        for a in pending:
            deps: set[str] = set()
            refs(a.node, deps)
            if (deps & names) <= done:
                out.append(a)
                done.add(a.name)
            else:
                rest.append(a)
        if len(rest) == len(pending):
            raise AssertionError("cyclic temporaries")
        pending = rest
    return out


def _build(mod, params, t, gap, gap_dt, shifts, eps_poly, approx, origin) -> ExactSection:
    name = mod.equation
    h = t   # the window length is passed in the variable's name
    by_name = {a.name: a for a in approx}

    def one(fname, doc, node, extra=(t,)):
        return _scalar(fname, doc, "value", params, extra, [node], [])

    gap_fn = one(f"{name}_gap", "the exact gap at time t (zero at contact)", lower_expr(gap, t))
    dt_fn = one(f"{name}_gap_dt", "d/dt of the exact gap at time t", lower_expr(gap_dt, t))
    scale_fn = one(f"{name}_gap_scale", "a majorant of the exact gap's rounding error at time t, in units of the "
                                        "unit roundoff", rounding_scale(gap, t))
    shift_fn = _scalar(f"{name}_shift", "the parameters once the clock restarts at time t", "vector", params, (t,),
                       [lower_expr(shifts[p], t) if p in shifts else ("ref", p) for p in params], [])

    # the error atoms: e_i = EPS_NAME(args); group eps_poly's terms by error monomial and power of t
    lw = Lowering(tuple(params) + (t,))
    groups: dict[tuple, dict[int, dict]] = {}
    atoms_all: dict[str, Expr] = {}
    for k, c in enumerate(eps_poly.coefficients):
        atoms = dict(c.atoms)
        atoms_all.update(atoms)
        for mono, coef in c.terms:
            em = tuple((a, e) for a, e in mono if a.startswith(EPS_PREFIX))
            if not em:
                continue
            rest = tuple((a, e) for a, e in mono if not a.startswith(EPS_PREFIX))
            groups.setdefault(em, {}).setdefault(k, {})[rest] = coef
    eps_atoms = sorted({a for em in groups for a, _ in em})
    delta: dict[str, Node] = {}
    rates: list[tuple[str, Node]] = []
    for key in eps_atoms:
        call = atoms_all[key]
        ap = by_name[call.func[len(EPS_PREFIX):]]
        shown = _public(to_maxima(call), approx)
        if any(_mentions(a, t) for a in call.args):
            raise SourceError(ap.span, f"'{ap.name}' is called with arguments that depend on {t}: {shown}")
        names = dict(zip(_fresh(len(ap.formals)), call.args))
        m = sup_majorant(_substitute(ap.dn, names), t, h, ap.span, f"the error of {shown}")
        n1 = ap.degree + 1
        delta[key] = mul(mul(m, _power(("ref", h), n1)), lit(Fraction(1, math.factorial(n1))))
        if isinstance(ap.dn, Num) and ap.dn.value == 0:
            continue    # the approximation is its exact expression (a polynomial in t): no error, no rate
        rate = _substitute(ap.d1, names)
        rate_node = sup_majorant(rate, t, h, ap.span, f"the rate of {shown}")
        if _mentions(rate, t) and _refers(rate_node, h):
            raise SourceError(ap.span, f"the rate of {shown} depends on {t}: cannot size windows")
        rates.append((key, rate_node))
    order = {p: i for i, p in enumerate(params)}
    bound: Node | None = None
    weights: dict[str, Node | None] = {k: None for k in eps_atoms}
    for em in sorted(groups):
        by_k = groups[em]
        inner: Node | None = None
        for k in range(max(by_k), -1, -1):
            if inner is not None:
                inner = mul(inner, ("ref", h))
            if k in by_k:
                c = _abs(horner(lw.numeric(Poly.build(by_k[k], atoms_all)), order))
                inner = c if inner is None else add(inner, c)
        term = inner
        for a, e in em:
            term = mul(_power(delta[a], e), term)
        bound = term if bound is None else add(bound, term)
        # weight of each error atom: the same coefficient sums at h = 1
        for a, _ in em:
            w = None
            for k in sorted(by_k):
                c = _abs(horner(lw.numeric(Poly.build(by_k[k], atoms_all)), order))
                w = c if w is None else add(w, c)
            weights[a] = w if weights[a] is None else add(weights[a], w)
    derived = [Assign(n, node) for n, node in lw.derived.values()]
    trunc_fn = _scalar(f"{name}_truncation", "a bound on |gap - polynomial| for t in [0, h] (h passed as "
                                             f"{t})", "value", params, (t,), [bound if bound is not None else lit(0)],
                       derived)
    rate_roots: list[Node] = []
    for key, node in rates:
        rate_roots += [weights[key] or lit(0), node]
    rate_fn = _scalar(f"{name}_rate", "the largest angular rate (rad/s) among the approximations that matter",
                      "max", params, (), rate_roots, derived)
    lines = tuple(f"{a.name}(...) is the degree-{a.degree} Taylor polynomial in {t} of "
                  f"{next(x.text.strip() for x in mod.approximations if x.name == a.name)}" for a in approx)
    return ExactSection(name, tuple(params), t, gap_fn, dt_fn, scale_fn, shift_fn, rate_fn, trunc_fn, lines, origin,
                        gap_expr=gap, gap_dt_expr=gap_dt, shift_exprs=tuple(shifts.get(p) for p in params))


def _refs_outside_abs(n: Node, out: set[str]) -> None:
    if n[0] == "ref":
        out.add(n[1])
    elif n[0] == "call" and n[1] == "abs" and n[2][0] == "ref":
        return
    elif n[0] != "lit":
        for c in n[1:]:
            if isinstance(c, tuple):
                _refs_outside_abs(c, out)


def _refers(n: Node, name: str) -> bool:
    s: set[str] = set()
    refs(n, s)
    return name in s


# ---------------------------------------------------------------- rendering
def _unique(base: str, taken: set[str]) -> str:
    name = base
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def _rename(n: Node, names: dict[str, str]) -> Node:
    """The tree `n` with every ('ref', name) in `names` renamed."""
    if n[0] == "ref":
        return ("ref", names.get(n[1], n[1]))
    if n[0] == "lit":
        return n
    return (n[0],) + tuple(_rename(c, names) if isinstance(c, tuple) else c for c in n[1:])


def _is_derived(n: Node, params) -> bool:
    """sin(p), cos(p), 1/p of a parameter p: the inputs a coefficient function
    derives once (lower.Lowering.derived)."""
    return (n[0] == "call" and n[2][0] == "ref" and n[2][1] in params) or \
        (n[0] == "/" and n[1][0] == "lit" and n[1][1] == 1.0 and n[2][0] == "ref" and n[2][1] in params)


def window_context(target, section: ExactSection, variants, selection, taken: set[str]) -> dict | None:
    """What the templates print for NAME_window: the window polynomial (the
    coefficient entry of the shifted parameters: the selection's variants,
    or the one coefficient function) and the truncation bound over [0, h]
    of the same parameters, in one function whose derived inputs (the sines
    and cosines of the shifted phases) are computed once.  The expressions
    are the ones NAME_coefficients and NAME_truncation print, so the values
    are theirs to the bit.  None for single precision (the driver then
    calls the entries one by one), and for a target without the entry
    (`window_entry`)."""
    if section.polynomial or target.single or not variants or not target.window_entry:
        return None
    params = section.params
    pset = set(params)
    tr = section.truncation
    shared: dict[Node, str] = {}            # derived node -> its name in the truncation
    t_temps: list[Assign] = []
    for a in tr.temps:
        if _is_derived(a.node, pset) and a.node not in shared:
            shared[a.node] = a.name
        else:
            t_temps.append(a)
    by_name = {fn.name: fn for fn in variants}
    if selection is not None:
        picks = [(by_name[c.name], list(c.masks), c.degree) for c in selection.cases]
        switches = [list(zs) for _, zs in selection.switches]
    else:
        picks = [(variants[0], [], variants[0].degree)]
        switches = []
    top = set(shared.values())
    cases, nodes = [], [a.node for a in tr.temps] + list(tr.outputs)
    local_names = {a.name for a in t_temps}
    for fn, masks, degree in picks:
        ren: dict[str, str] = {}
        own: list[Assign] = []
        for a in fn.derived:
            if a.node in shared:
                ren[a.name] = shared[a.node]
            else:
                own.append(a)
        for a in list(own) + list(fn.temps):
            if a.name in top:           # a local of the variant named like a shared input: rename it
                ren[a.name] = _unique(a.name + "_", top | local_names | pset | {section.variable})
        body = [Assign(ren.get(a.name, a.name), _rename(a.node, ren)) for a in list(own) + list(fn.temps)]
        coefs = [_rename(c, ren) for c in fn.coefficients]
        local_names |= {a.name for a in body}
        nodes += [a.node for a in body] + coefs
        cases.append({"masks": masks, "degree": degree, "temps": [(a.name, target.expr(a.node)) for a in body],
                      "coefs": [target.expr(c) for c in coefs]})
    if local_names & (pset | {section.variable} | top):
        return None     # a temporary named like an input (a variable named w1 ...): no window entry
    used: set[str] = set()
    plain: set[str] = set()
    for n in nodes:
        refs(n, used)
        _refs_outside_abs(n, plain)
    for zs in switches:
        used |= set(zs)
        plain |= set(zs)
    inputs = list(params) + [section.variable]
    names = set(taken) | local_names | top
    local = {b: _unique(b, names) for b in ("t0", "span", "coef", "bound", "mask", "q", "n")}
    return {"name": f"{section.name}_window", "at": f"{section.name}_window_at",
            "shared": [(name, target.expr(node)) for node, name in shared.items()],
            "trunc_temps": [(a.name, target.expr(a.node)) for a in t_temps],
            "trunc_out": target.expr(tr.outputs[0]),
            "switches": switches, "cases": cases, "selection": selection is not None,
            "unused": [p for p in inputs if p not in used],
            "abs_only": [p for p in inputs if p in used and p not in plain],
            "locals": sorted(local_names), "local": local,
            "max_degree": max(c["degree"] for c in cases)}


def render_context(target, section: ExactSection, coef_entry: str, coef_selection: bool, coef_degree: int,
                   complete: bool = True, variants=(), selection=None) -> dict:
    """What templates/<lang>/exact.j2 prints: every function's lines as text.
    `variants` (the coefficient functions: the selection's variants, or the
    one function) and `selection` give the window entry (window_context)."""
    params = section.params
    taken = set(params) | {section.variable}
    fns = {}
    for key in section.functions():
        fn: ScalarFn = getattr(section, key)
        taken |= {a.name for a in fn.temps}
    for key in section.functions():
        fn = getattr(section, key)
        inputs = list(params) + list(fn.extra)
        printer = target.float_copies(inputs)
        temps = [(a.name, printer.expr(a.node)) for a in fn.temps]
        outs = [printer.expr(o) for o in fn.outputs]
        used = [p for p in inputs if p not in fn.unused_params]
        plain: set[str] = set()     # referenced other than as abs(name) (gm2 counts only these as uses)
        for n in [a.node for a in fn.temps] + list(fn.outputs):
            _refs_outside_abs(n, plain)
        abs_only = [p for p in used if p not in plain]
        atomic = [re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*|[0-9.eE_+f-]+", o) is not None for o in outs]
        fns[key] = {"atomic": atomic, "name": fn.name, "doc": fn.doc, "kind": fn.kind, "extra": list(fn.extra), "temps": temps,
                    "outputs": outs, "unused": list(fn.unused_params), "used": used, "abs_only": abs_only,
                    "pairs": [(outs[i], outs[i + 1]) for i in range(0, len(outs), 2)] if fn.kind == "max" else []}
    local = {b: _unique(b, taken) for b in ("out", "rate", "pv", "mo", "wk", "rk")}
    window = window_context(target, section, list(variants), selection, taken)
    return {"window": window, "section": section, "fns": fns, "params": list(params), "nparams": len(params),
            "variable": section.variable, "coef_entry": coef_entry, "coef_selection": coef_selection,
            "coef_degree": coef_degree, "local": local, "name": section.name, "polynomial": section.polynomial,
            # the circles' bound and polynomial stand in for the generated functions: only in double
            # code whose coefficients take every effect (never -1 for finite parameters)
            "circles": list(section.circles) if section.circles and complete and not target.single else None}
