"""Variants of an equation: bodies without orbit, without acceleration, or
with a radius of zero, and every combination across bodies.

The zeros are substituted and folded by Maxima (one run for all variants,
one more to check every collection), variants giving the same polynomial
are merged, and a variant that can never be chosen (another one applies
whenever it does and costs no more) is dropped.  The result is ordered by
cost, cheapest first: the order in which the selection logic tests them.
"""
from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass

from max2code.generate.collect import Polynomial, collect
from max2code.errors import SourceError
from max2code.generate.expr import NotPolynomial
from max2code.generate.lower import FunctionIR, lower
from max2code.generate.maxima import DEFAULT_TIMEOUT, Statement, run_maxima
from max2code.progress import bar
from max2code.generate.reader import MaximaOutputError, read_expr

# kind of switch -> (the effect whose parameters become zero, short name)
KINDS = {"orbit": ("orbit_radius", "no_orbit"),
         "acceleration": ("acceleration", "no_accel"),
         "radius": ("radius", "point"),
         "spin": ("spin", "no_spin")}
# the world effect each kind of switch belongs to (None: a shape, always available)
WORLD_EFFECT_OF = {"orbit": "orbit", "spin": "orbit", "acceleration": "acceleration", "radius": None}
# effects a world may leave out with --effects; a zero radius (a point) is a
# shape, always available
WORLD_EFFECTS = ("acceleration", "orbit")


@dataclass(frozen=True, order=True)
class Switch:
    body: int
    kind: str
    params: tuple[str, ...]

    @property
    def label(self) -> str:
        return f"{KINDS[self.kind][1]}{self.body}"


@dataclass(frozen=True)
class Variant:
    name: str                       # generated function name
    switches: tuple[Switch, ...]    # what is switched off
    zeros: tuple[str, ...]          # the parameters that must be exactly 0
    polynomial: Polynomial
    function: FunctionIR
    aliases: tuple[str, ...] = ()   # other switch sets that gave the same polynomial

    @property
    def degree(self) -> int:
        return self.polynomial.degree

    @property
    def monomials(self) -> int:
        return sum(len(c.terms) for c in self.polynomial.coefficients)

    @property
    def cost(self) -> tuple[int, int]:
        return (self.degree, self.function.multiplications)

    def describe(self) -> dict:
        return {"name": self.name, "conditions": [f"{p} == 0" for p in self.zeros],
                "switched_off": [s.label for s in self.switches], "degree": self.degree,
                "terms": self.degree + 1, "monomials": self.monomials,
                "multiplications": self.function.multiplications, "same_as": list(self.aliases)}


def switches_of(derivation) -> list[Switch]:
    """Every switch the .mxm's parameter roles allow."""
    mod = derivation.module
    out = []
    bodies = sorted({p.body for p in mod.parameters if p.body is not None})
    for body in bodies:
        for kind, (effect, _) in KINDS.items():
            params = tuple(p.name for p in mod.parameters if p.body == body and p.effect == effect)
            if params:
                out.append(Switch(body, kind, params))
    return out


def _progress(on: bool, i: int, n: int, what: str) -> None:
    if on:
        bar(i, n, what)


@functools.lru_cache(maxsize=256)
def _read_polynomial(text: str, variable: str) -> Polynomial:
    """Maxima's text of a variant's polynomial, read and collected in powers
    of `variable` (an immutable Polynomial): remembered by the text, since
    one process generates the same equation for several languages and
    reading is most of the Python side of the variants."""
    return collect(read_expr(text), variable)


def derive_variants(derivation, *, effects: tuple[str, ...] | None = None, use_cache: bool = True,
                    timeout: float = DEFAULT_TIMEOUT, progress: bool = False, shared: bool = True) -> list[Variant]:
    """All variants reachable in a world with `effects` (None: every effect)."""
    mod = derivation.module
    if not any(p.body is not None for p in mod.parameters):
        raise SourceError(mod.maxima_span, "variants need parameter roles, e.g. 'parameter d \"...\" : body 1 orbit_radius'")
    allowed = WORLD_EFFECTS if effects is None else effects
    for e in allowed:
        if e not in WORLD_EFFECTS:
            raise SourceError(mod.maxima_span, f"unknown effect '{e}' for --effects; expected: {', '.join(WORLD_EFFECTS)}")
    switches = switches_of(derivation)
    forced = [s for s in switches if WORLD_EFFECT_OF[s.kind] is not None and WORLD_EFFECT_OF[s.kind] not in allowed]
    free = [s for s in switches if s not in forced]
    combos = [tuple(sorted(forced + list(c))) for r in range(len(free) + 1) for c in itertools.combinations(free, r)]

    origin = derivation.origin
    items = {}
    for i, combo in enumerate(combos):
        zeros = sorted({p for s in combo for p in s.params})
        subst = ", ".join(f"{p} = 0" for p in zeros)
        items[f"v{i}"] = f"expand(subst([{subst}], __m2c_p))" if zeros else "expand(__m2c_p)"
    _progress(progress, 0, len(combos) + 2, "Maxima folds the zeros of every variant")
    res = run_maxima(list(derivation.prelude), list(derivation.statements), items, fallback=origin,
                     timeout=timeout, use_cache=use_cache)
    polys: list[Polynomial] = []
    for i in range(len(combos)):
        try:
            polys.append(_read_polynomial(res.items[f"v{i}"], mod.variable))
        except (MaximaOutputError, NotPolynomial) as exc:
            raise SourceError(origin, f"variant {i}: {exc}") from None
    _progress(progress, 1, len(combos) + 2, "Maxima checks every collection")
    checks = {f"d{i}": f"ratsimp(({res.items[f'v{i}']}) - ({p.to_maxima()}))" for i, p in enumerate(polys)}
    chk = run_maxima([], [Statement("0;", origin)], checks, fallback=origin, timeout=timeout, use_cache=use_cache)
    bad = [k for k, v in chk.items.items() if v.strip() != "0"]
    if bad:
        raise SourceError(origin, f"internal error: collected coefficients of {len(bad)} variants differ from Maxima's; please report this")

    # merge variants with the same polynomial: keep the one with the fewest zeros
    groups: dict[Polynomial, list[int]] = {}
    for i, p in enumerate(polys):
        groups.setdefault(p, []).append(i)
    from max2code.generate.derive import parameters_of
    params, docs = parameters_of(derivation)
    variants: list[Variant] = []
    for n, (poly, members) in enumerate(groups.items()):
        members.sort(key=lambda i: (len({p for s in combos[i] for p in s.params}), [s.label for s in combos[i]]))
        best = combos[members[0]]
        zeros = tuple(sorted({p for s in best for p in s.params}))
        name = mod.equation + "".join("_" + s.label for s in best)
        _progress(progress, min(2 + n, len(combos) + 1), len(combos) + 2, f"lowering {name}")
        fn = lower(poly, name, mod.doc, params, docs, origin, shared=shared)
        aliases = tuple("+".join(s.label for s in combos[i]) or "full" for i in members[1:])
        variants.append(Variant(name, best, zeros, poly, fn, aliases))
    _progress(progress, len(combos) + 2, len(combos) + 2, f"{len(variants)} variants")

    # drop a variant when another applies whenever it does and costs no more
    kept = []
    for v in variants:
        dominated = any(w is not v and set(w.zeros) <= set(v.zeros) and w.cost <= v.cost and
                        (w.cost, len(w.zeros), w.name) < (v.cost, len(v.zeros), v.name) for w in variants)
        if not dominated:
            kept.append(v)
    kept.sort(key=lambda v: (v.cost, len(v.zeros), v.name))
    return kept
