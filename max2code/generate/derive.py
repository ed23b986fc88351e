"""Stage 2-4 of the generator: a parsed .mxm module through Maxima, its
output read as an expression, collected by powers of t and proved equal to
Maxima's polynomial (a second run).  The result is a Derivation."""
from __future__ import annotations

import math
import re
import sys
from dataclasses import dataclass
from fractions import Fraction

from max2code.errors import SourceError, Span, UsageError
from max2code.generate.collect import Polynomial, collect
from max2code.generate.expr import Call, NotPolynomial, Sym, to_maxima
from max2code.generate.maxima import DEFAULT_TIMEOUT, MaximaResult, Statement, _advance, is_quit, run_maxima, split_statements
from max2code.generate.mxm import MxmModule
from max2code.generate.names import check_symbols, use_of
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
    declared = {o.name: o for o in mod.options}
    for name, raw in overrides.items():
        if name not in values:
            known = ", ".join(sorted(values)) or "none"
            raise UsageError(f"max2code: error: -D {name}={raw}: {mod.path} declares no option '{name}' "
                             f"(its options: {known})")
        opt = declared[name]
        try:
            v = Fraction(raw)
        except (ValueError, ZeroDivisionError, OverflowError):
            raise SourceError(opt.span, f"-D {name}={raw}: not a number") from None
        why = opt.check(v)
        if why:
            raise SourceError(opt.span, f"-D {name}={raw}: {why}")
        values[name] = v
    return values


def note(req_progress: bool, msg: str) -> None:
    if req_progress:
        print(f"max2code: {msg}", file=sys.stderr, flush=True)


def derive(mod: MxmModule, overrides: dict[str, str] | None = None, *, use_cache: bool = True,
           timeout: float = DEFAULT_TIMEOUT, progress: bool = False) -> Derivation:
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
    if re.search(r"#<|\binf\b|\bnan\b", text):
        raise SourceError(origin, "Maxima's result has an infinite or undefined number (a float overflowed): "
                                  f"{text[:60]}; use exact numbers or scale the equation")
    try:
        expr = read_expr(text)
        poly = collect(expr, mod.variable)
    except MaximaOutputError as exc:
        raise SourceError(origin, f"the result is not a polynomial max2code can read: {exc}") from None
    except NotPolynomial as exc:
        raise SourceError(origin, str(exc)) from None
    _check_atoms(mod, poly, origin)
    if poly.degree == 0:   # collect() has taken every power of t out, so: no t at all
        raise SourceError(origin, f"the result does not depend on {mod.variable}: nothing to solve ({text[:60]})")
    if mod.terms is not None and mod.terms != poly.degree + 1:
        raise SourceError(mod.terms_span, f"'polynomial terms {mod.terms}' disagrees with Maxima: the polynomial has "
                                          f"degree {poly.degree}, so {poly.degree + 1} terms ({mod.variable}^0 to {mod.variable}^{poly.degree})")
    note(progress, f"{mod.path}: Maxima checks the collected coefficients ...")
    # Maxima's ratsimp turns a float into a nearby rational (ratepsilon), so a
    # float in the result is checked in the exact value the reader gave it
    checked = to_maxima(expr) if _FLOAT.search(text) else text
    check = run_maxima([], [Statement(f"({checked}) - ({poly.to_maxima()});", origin)], {"d": "ratsimp(__m2c_p)"},
                       fallback=origin, timeout=timeout, use_cache=use_cache)
    if check.items["d"].strip() != "0":
        raise SourceError(origin, "internal error: the collected coefficients differ from Maxima's polynomial "
                                  f"(difference {check.items['d'][:80]}); please report this")
    return Derivation(mod, poly, text, res, check, options, tuple(stmts), tuple(prelude), origin)


_FLOAT = re.compile(r"(?<![A-Za-z_%])[0-9]+\.[0-9]*|(?<![A-Za-z_%])[0-9]+[eEbBdD][+-]?[0-9]")

# the functions every target prints (each printer's `calls`); Maxima spells them in lower case
FUNCTIONS = ("abs", "cos", "sin", "sqrt")


def _check_atoms(mod: MxmModule, poly: Polynomial, origin: Span) -> None:
    """Every atom of the coefficients must be printable: a symbol, or a known
    function of one symbol.  A mistake is reported where the Maxima text
    names the function (else at the polynomial's statement)."""
    for k, c in enumerate(poly.coefficients):
        for _, v in c.terms:
            try:
                f = float(v)
            except OverflowError:
                f = math.inf
            if math.isinf(f) or f == 0.0:
                raise SourceError(origin, f"the coefficient of {poly.variable}^{k} has the constant "
                                          f"{_short(v)}, which a double cannot hold ({'over' if f else 'under'}flow); "
                                          "scale the equation")
        for _, atom in c.atoms:
            if isinstance(atom, Sym):
                if atom.name.startswith("%") and atom.name != "%pi":
                    raise SourceError(origin, f"the result contains Maxima's constant {atom.name}: only %pi can be "
                                              "printed (write the number, or make it a parameter)")
                continue
            if isinstance(atom, Call) and atom.func not in FUNCTIONS:
                raise SourceError(_find_call(mod, atom.func) or origin,
                                  f"unknown function '{atom.func}' (Maxima leaves it unevaluated): the generated code "
                                  f"can call only {', '.join(FUNCTIONS)}")
            if not (isinstance(atom, Call) and len(atom.args) == 1 and isinstance(atom.args[0], Sym)):
                raise SourceError(origin, f"the coefficients contain {to_maxima(atom)}: only a parameter or a "
                                          f"function ({', '.join(FUNCTIONS)}) of one parameter can be printed; "
                                          "give the argument a parameter of its own")


def _short(v: Fraction) -> str:
    text = str(v)
    return text if len(text) <= 40 else f"{text[:20]}...{text[-12:]} ({len(text)} characters)"


def _find_call(mod: MxmModule, func: str) -> Span | None:
    m = re.search(rf"(?<![A-Za-z0-9_%]){re.escape(func)}\s*\(", mod.maxima_text)
    return _advance(mod.maxima_span, mod.maxima_text[:m.start()]) if m else None


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
        check_symbols(names, d.origin, mod)
        return names, tuple("" for _ in names)
    declared = [p.name for p in mod.parameters]
    missing = sorted(found - set(declared))
    if missing:
        # at the first use in the text of the first undeclared name used
        uses = sorted((s.line, s.column, m) for m in missing if (s := use_of(mod, m)) is not None)
        where = Span(mod.maxima_span.file, uses[0][0], uses[0][1]) if uses else d.origin
        raise SourceError(where, f"the polynomial uses {', '.join(repr(m) for m in missing)}, "
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


