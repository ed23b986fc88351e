"""Names the generated code takes from the .mxm file (the equation, the
parameters, the `exact` functions) must be identifiers in every target
language: not a keyword, not a name the printer or the templates use (each
target's `reserved` and `reserved_prefixes`), and not one of the names
max2code derives from the others.  A clash is refused at the name's place
in the file, whatever the --lang, so a file that generates for one language
generates for all four."""
from __future__ import annotations

import re

from max2code.errors import SourceError, Span
from max2code.targets import LANGUAGES


def clash(name: str) -> str | None:
    """Why `name` cannot be used, or None."""
    langs = []
    for lang, cls in sorted(LANGUAGES.items()):
        if name in cls.reserved or any(name.startswith(p) for p in cls.reserved_prefixes):
            langs.append(lang)
    if langs:
        return f"'{name}' is reserved in {', '.join(langs)} (a keyword, or a name the generated code uses)"
    return None


def check_names(mod) -> None:
    """Raise SourceError at the first name of `mod` (an MxmModule) that a target cannot take."""
    why = clash(mod.equation)
    if why:
        raise SourceError(mod.equation_span or Span(mod.path, 1, 1), f"equation name {why}; choose another name")
    if mod.variable_span is not None:
        why = clash(mod.variable)
        if why:
            raise SourceError(mod.variable_span, f"variable {why}; choose another name")
    names = {p.name for p in mod.parameters}
    for p in mod.parameters:
        why = clash(p.name)
        if why:
            raise SourceError(p.span, f"parameter {why}; choose another name")
        if p.name.startswith(mod.equation + "_"):
            raise SourceError(p.span, f"parameter '{p.name}' would clash with the generated functions "
                                      f"{mod.equation}_*; choose another name")
        if p.name.endswith("_s") and p.name[:-2] in names:
            raise SourceError(p.span, f"parameter '{p.name}' would clash with the single-precision copy of "
                                      f"'{p.name[:-2]}' (--real=float); choose another name")
    for a in mod.approximations:
        why = clash(a.name)
        if why:
            raise SourceError(a.span, f"'exact' function {why}; choose another name")


def name_from_file(stem: str) -> str:
    """The equation name a file without `equation NAME` gets from its file
    name: non-identifier characters become '_', and a name that starts with
    a digit or is reserved in a target gets the prefix 'eq_' (int.mxm: eq_int)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", stem) or "equation"
    if name[0].isdigit() or clash(name):
        name = "eq_" + name
    return name


def check_symbols(names, span: Span) -> None:
    """The polynomial's symbols, when they become parameters without a declaration."""
    for n in names:
        why = clash(n)
        if why:
            raise SourceError(span, f"the polynomial's symbol {why}; rename it, or declare the parameters")
