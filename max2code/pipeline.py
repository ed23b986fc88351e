"""The generator, stage by stage:

  .mxm text -> MxmModule -> Maxima result -> Expr -> Polynomial (checked)
            -> FunctionIR -> rendered text
"""
from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field
from fractions import Fraction

from max2code import __version__
from max2code.collect import Polynomial, collect
from max2code.errors import Max2CodeError, SourceError
from max2code.expr import NotPolynomial, Sym
from max2code.lower import FunctionIR, Lowering, horner, lower
from max2code.errors import Span
from max2code.maxima import MaximaResult, Statement, is_quit, run_maxima, split_statements
from max2code.mxm import MxmModule, read_mxm
from max2code.reader import MaximaOutputError, read_expr
from max2code.render import FragmentItem, Selection, SelectionCase, inline_derived, render_fragment, render_module
from max2code.targets import target as get_target


@dataclass(frozen=True)
class GenerateRequest:
    path: str
    lang: str
    line_directives: bool = True
    options: dict[str, str] = field(default_factory=dict)
    shared: bool = True
    use_cache: bool = True
    maxima_timeout: float = 300.0
    progress: bool = False
    out_name: str | None = None     # the generated file's name, for #line directives back to it
    variants: bool = True           # with parameter roles: every variant and the selection logic
    effects: tuple[str, ...] | None = None   # the world's effects (None: all); see variants.WORLD_EFFECTS
    exact: bool = False             # also the exact-motion entries (the file's `exact`/`shift`; docs/exact-motion.md)
    real: str = "double"            # "float": the generated arithmetic in single precision (not Python)


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


@dataclass(frozen=True)
class GeneratedFile:
    text: str
    derivation: Derivation
    function: FunctionIR             # the most general function in the file
    variants: tuple = ()             # variants.Variant, cheapest first, when generated
    exact: object = None             # exact.ExactSection, when the exact-motion entries were generated

    @property
    def code_lines(self) -> int:
        return self.text.count("\n")


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


def _note(req_progress: bool, msg: str) -> None:
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
    _note(progress, f"{mod.path}: Maxima expands the polynomial ...")
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
    _note(progress, f"{mod.path}: Maxima checks the collected coefficients ...")
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


def header_lines(d: Derivation, fn: FunctionIR) -> list[str]:
    mod = d.module
    opts = ", ".join(f"{k} = {v}" for k, v in sorted(d.options.items()))
    lines = [f"Generated by max2code {__version__} from {mod.path}: do not edit.",
             f"{d.maxima.version}; degree {fn.degree} in {mod.variable}" + (f"; options: {opts}" if opts else "") + ".",
             f"Multiplications: {fn.multiplications} (plain expansion: {fn.naive_multiplications})."]
    if mod.doc:
        lines.insert(1, mod.doc + ".")
    return lines


def generate(d: Derivation, req: GenerateRequest) -> GeneratedFile:
    mod = d.module
    tgt = get_target(req.lang)
    try:
        tgt.with_real(req.real)
    except ValueError as exc:
        raise Max2CodeError(f"max2code: error: --real={req.real}: {exc}") from None
    params, docs = parameters_of(d)
    # temporaries must not shadow the function's own name
    fn = lower(d.polynomial, mod.equation, mod.doc, params, docs, d.origin, shared=req.shared)
    header = header_lines(d, fn)
    mxm_name = mod.path
    out_name = req.out_name or (os.path.splitext(os.path.basename(mod.path))[0] + tgt.extension)
    blocks = mod.blocks_for(req.lang)
    if any(b.kind == "term" for b in blocks):
        if req.exact or tgt.single:
            raise SourceError(next(b for b in blocks if b.kind == "term").span,
                              "--exact and --real=float need the function form (a file without 'term' blocks)")
        text = _fragment(d, fn, tgt, blocks, header, mxm_name, out_name, req.line_directives)
        return GeneratedFile(text, d, fn)
    if not (req.variants and any(p.body is not None for p in mod.parameters)):
        section, ectx = _exact(d, req, tgt, mod.equation, False, fn.degree)
        text = render_module(tgt, [(fn, "")], None, header, mod.variable, mxm_name, out_name, req.line_directives,
                             exact=ectx)
        return GeneratedFile(text, d, fn, exact=section)
    from max2code.variants import WORLD_EFFECTS, derive_variants, switches_of
    vs = derive_variants(d, effects=req.effects, use_cache=req.use_cache, timeout=req.maxima_timeout,
                         progress=req.progress, shared=req.shared)
    general = max(vs, key=lambda v: (-len(v.zeros), v.cost))
    effects = ", ".join(req.effects if req.effects is not None else WORLD_EFFECTS) or "none"
    header = header_lines(d, general.function) + [
        f"Variants: {len(vs)} for effects: {effects}; {mod.equation}_coefficients picks the cheapest exact one."]
    ordered = [general] + [v for v in vs if v is not general]
    functions = [(v.function, "exact when " + " = ".join(v.zeros) + " = 0" if v.zeros else "") for v in ordered]
    selection = build_selection(f"{mod.equation}_coefficients", vs, switches_of(d), effects)
    section, ectx = _exact(d, req, tgt, selection.name, True, selection.max_degree)
    text = render_module(tgt, functions, selection, header, mod.variable, mxm_name, out_name, req.line_directives,
                         exact=ectx)
    return GeneratedFile(text, d, general.function, tuple(vs), exact=section)


def _exact(d: Derivation, req: GenerateRequest, tgt, coef_entry: str, selection: bool, degree: int):
    """The exact-motion section and its template context, when requested."""
    if not req.exact:
        return None, None
    from max2code.exact import derive_exact, render_context
    section = derive_exact(d, progress=req.progress, use_cache=req.use_cache, timeout=req.maxima_timeout)
    return section, render_context(tgt, section, coef_entry, selection, degree)


def _fragment(d: Derivation, fn: FunctionIR, tgt, blocks, header, mxm_name, out_name, line_directives) -> str:
    """The paper's form: initialise text, `term k` text + coefficient k, finalise text."""
    terms = [b for b in blocks if b.kind == "term"]
    if len(terms) != fn.degree + 1:
        where = d.module.terms_span or terms[0].span
        raise SourceError(where, f"the file has {len(terms)} term blocks but the polynomial has degree {fn.degree} "
                                 f"({fn.degree + 1} terms)")
    # a fragment has no local variables: each coefficient is one Horner expression
    order = {p: i for i, p in enumerate(fn.params)}
    lw = Lowering(fn.params)
    nums = [lw.numeric(c) for c in d.polynomial.coefficients]
    derived = dict(lw.derived.values())
    lw_coeffs = [inline_derived(horner(p, order), derived) for p in nums]
    items: list[FragmentItem] = []

    def origin(b):
        return tgt.origin_line(b.span.line, mxm_name) if line_directives else None

    def placed(b):
        # with directives, pad the first line so that columns match the .mxm too
        return " " * (b.span.column - 1) + b.text if line_directives else b.text.strip("\n")

    for b in blocks:
        if b.kind == "initialise":
            items.append(FragmentItem(placed(b), origin(b)))
    for b in terms:
        expr = tgt.expr(lw_coeffs[b.index])
        items.append(FragmentItem(f"{placed(b).rstrip()} {expr}{tgt.statement_end}", origin(b)))
    for b in blocks:
        if b.kind == "finalise":
            items.append(FragmentItem(placed(b), origin(b)))
    return render_fragment(tgt, items, header, out_name, line_directives)


def build_selection(name: str, variants, switches, effects: str) -> Selection:
    """For every mask of switches, the cheapest variant exact for it (the
    variants come cheapest first)."""
    by_variant: dict[str, list[int]] = {}
    complete = True
    for mask in range(1 << len(switches)):
        zero = {p for i, s in enumerate(switches) if mask >> i & 1 for p in s.params}
        best = next((v for v in variants if set(v.zeros) <= zero), None)
        if best is None:
            complete = False
        else:
            by_variant.setdefault(best.name, []).append(mask)
    cases = tuple(SelectionCase(v.name, v.degree, tuple(by_variant[v.name])) for v in variants if v.name in by_variant)
    return Selection(name, tuple((s.label, s.params) for s in switches), cases,
                     max(v.degree for v in variants), effects, complete)


def generate_file(req: GenerateRequest) -> GeneratedFile:
    t0 = time.perf_counter()
    mod = read_mxm(req.path)
    d = derive(mod, req.options, use_cache=req.use_cache, timeout=req.maxima_timeout, progress=req.progress)
    out = generate(d, req)
    _note(req.progress, f"{req.path}: {req.lang}, degree {out.function.degree}, "
                        f"{out.function.multiplications} multiplications, {time.perf_counter() - t0:.2f} s"
                        + (" (Maxima results from cache)" if d.maxima.cached else ""))
    return out
