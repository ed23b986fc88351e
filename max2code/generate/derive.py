"""Stage 2-4 of the generator: a parsed .mxm module through Maxima, its
output read as an expression, collected by powers of t and proved equal to
Maxima's polynomial (a second run).  The result is a Derivation."""
from __future__ import annotations

import sys
from dataclasses import dataclass
from fractions import Fraction

from max2code.errors import SourceError, Span
from max2code.generate.collect import Polynomial, collect
from max2code.generate.expr import NotPolynomial, Sym
from max2code.generate.maxima import MaximaResult, Statement, is_quit, run_maxima, split_statements
from max2code.generate.mxm import MxmModule
from max2code.generate.reader import MaximaOutputError, read_expr


@dataclass(frozen=True)
class Derivation:
    """A .mxm file through Maxima: the checked polynomial and its provenance."""
    module: MxmModule
    polynomial: Polynomial
    maxima_text: str          # Maxima's expanded polynomial, as string() printed it
    maxima: MaximaResult
    check: MaximaResult
    options: dict[str, Fraction]
    statements: tuple[Statement, ...]   # the Maxima text, split
    prelude: tuple[str, ...]            # the options as Maxima assignments
    origin: Span                        # the statement whose value is the polynomial


def _options(mod: MxmModule, overrides: dict[str, str]) -> dict[str, Fraction]:
    values = {o.name: o.value for o in mod.options}
    for name, raw in overrides.items():
        if name not in values:
            known = ", ".join(sorted(values)) or "none"
            raise SourceError(mod.maxima_span, f"--option {name}: the file declares no option '{name}' (declared: {known})")
        try:
            values[name] = Fraction(raw)
        except (ValueError, ZeroDivisionError):
            raise SourceError(mod.maxima_span, f"--option {name}={raw}: not a number") from None
    return values


def note(req_progress: bool, msg: str) -> None:
    if req_progress:
        print(f"max2code: {msg}", file=sys.stderr, flush=True)


def derive(mod: MxmModule, overrides: dict[str, str] | None = None, *, use_cache: bool = True,
           timeout: float = 300.0, progress: bool = False) -> Derivation:
    """Run Maxima on the module, read and collect the polynomial, and prove the
    collection equals Maxima's polynomial (a second Maxima run)."""
    options = _options(mod, overrides or {})
    prelude = [f"{name}: {v.numerator}/{v.denominator}$" for name, v in sorted(options.items())]
    stmts = split_statements(mod.maxima_text, mod.maxima_span)
    real = [s for s in stmts if not s.text.strip().startswith(":lisp") and not is_quit(s)]
    origin = real[-1].span if real else mod.maxima_span
    note(progress, f"{mod.path}: Maxima expands the polynomial ...")
    res = run_maxima(prelude, stmts, {"poly": "expand(__m2c_p)"}, fallback=origin,
                     timeout=timeout, use_cache=use_cache)
    text = res.items["poly"]
    try:
        expr = read_expr(text)
        poly = collect(expr, mod.variable)
    except MaximaOutputError as exc:
        raise SourceError(origin, f"the result is not a polynomial max2code can read: {exc}") from None
    except NotPolynomial as exc:
        raise SourceError(origin, str(exc)) from None
    if poly.degree == 0:   # collect() has taken every power of t out, so: no t at all
        raise SourceError(origin, f"the result does not depend on {mod.variable}: nothing to solve ({text[:60]})")
    if mod.terms is not None and mod.terms != poly.degree + 1:
        raise SourceError(mod.terms_span, f"'polynomial terms {mod.terms}' disagrees with Maxima: the polynomial has "
                                          f"degree {poly.degree}, so {poly.degree + 1} terms ({mod.variable}^0 to {mod.variable}^{poly.degree})")
    note(progress, f"{mod.path}: Maxima checks the collected coefficients ...")
    check = run_maxima([], [Statement(f"({text}) - ({poly.to_maxima()});", origin)], {"d": "ratsimp(__m2c_p)"},
                       fallback=origin, timeout=timeout, use_cache=use_cache)
    if check.items["d"].strip() != "0":
        raise SourceError(origin, "internal error: the collected coefficients differ from Maxima's polynomial "
                                  f"(difference {check.items['d'][:80]}); please report this")
    return Derivation(mod, poly, text, res, check, options, tuple(stmts), tuple(prelude), origin)


def parameters_of(d: Derivation) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Declared parameters in order; undeclared symbols are an error.  Without
    declarations, the polynomial's symbols in alphabetical order."""
    mod = d.module
    found: set[str] = set()
    for c in d.polynomial.coefficients:
        for _, atom in c.atoms:
            _symbols(atom, found)
    found.discard("%pi")
    if not mod.parameters:
        names = tuple(sorted(found))
        return names, tuple("" for _ in names)
    declared = [p.name for p in mod.parameters]
    missing = sorted(found - set(declared))
    if missing:
        raise SourceError(mod.parameters[0].span, f"the polynomial uses {', '.join(repr(m) for m in missing)}, "
                                                  "not declared as parameters")
    return tuple(declared), tuple(p.doc for p in mod.parameters)


def _symbols(e, out: set[str]) -> None:
    if isinstance(e, Sym):
        if not e.name.startswith("%") or e.name == "%pi":
            out.add(e.name)
        else:
            raise ValueError(e.name)
    for a in getattr(e, "args", ()):
        _symbols(a, out)


