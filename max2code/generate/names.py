"""Names the generated code takes from the .mxm file (the equation, the
parameters, the `exact` functions) must be identifiers in every target
language and plain symbols to Maxima: not a keyword, not a library name the
generated file sees, not a name the printer or the templates use (each
target's `words` and `reserved_prefixes`, asked through `reserved_as`; the
equation and `exact` function names, which the generated code declares at
file scope, also not a name the target's library declares there), not
a Maxima keyword, constant or system variable (maxima_words.txt, beside
this module), and not one of the names max2code derives from the others.
A clash is refused at the name's place in the file, whatever the --lang, so
a file that generates for one language generates for all four.  Names that
only Maxima sees (options, the arguments of `exact` functions) are checked
against Maxima's words."""
from __future__ import annotations

import functools
import re
from importlib import resources

from max2code.errors import SourceError, Span
from max2code.targets import LANGUAGES

# the identifiers every target language accepts
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@functools.lru_cache(maxsize=1)
def maxima_words() -> tuple[tuple[str, frozenset[str]], ...]:
    """Maxima's words, grouped by what they are: (what, names)."""
    text = resources.files("max2code.generate").joinpath("maxima_words.txt").read_text(encoding="utf-8")
    groups: list[tuple[str, set[str]]] = []
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        if line.startswith("["):
            groups.append((line.strip()[1:-1], set()))
        else:
            groups[-1][1].update(line.split())
    return tuple((what, frozenset(names)) for what, names in groups)


def maxima_clash(name: str) -> str | None:
    """What `name` is to Maxima when it cannot be a plain symbol, or None."""
    for what, names in maxima_words():
        if name in names:
            return what
    return None


def clash(name: str, file_scope: bool = True) -> str | None:
    """Why `name` cannot be used, or None: the languages (and Maxima) whose word it is, and what it is there.
    `file_scope`: whether the generated code declares it at file scope (the equation, an `exact`
    function); a parameter's name is declared in the functions' parameter lists only."""
    if not IDENTIFIER.fullmatch(name):
        return (f"'{name}' is not an identifier in every target language (letters A-Z and a-z, digits and '_', "
                "not starting with a digit)")
    found = []
    for lang, cls in sorted(LANGUAGES.items()):
        what = cls.reserved_as(name, file_scope)
        if what:
            found.append((lang, what))
    what = maxima_clash(name)
    if what:
        found.append(("maxima", what))
    if found:
        return (f"'{name}' is reserved in {', '.join(lang for lang, _ in found)} "
                f"({'; '.join(what for _, what in found)})")
    return None


def check_names(mod) -> None:
    """Raise SourceError at the first name of `mod` (an MxmModule) that a target or Maxima cannot take."""
    why = clash(mod.equation)
    if why:
        raise SourceError(mod.equation_span or Span(mod.path, 1, 1), f"equation name {why}; choose another name")
    if mod.variable_span is not None:
        why = clash(mod.variable, file_scope=False)
        if why:
            raise SourceError(mod.variable_span, f"variable {why}; choose another name")
    for o in mod.options:
        what = maxima_clash(o.name)
        if what:
            raise SourceError(o.span, f"option '{o.name}' is reserved in maxima ({what}); choose another name")
    names = {p.name for p in mod.parameters}
    for p in mod.parameters:
        why = clash(p.name, file_scope=False)
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
        for f in a.formals:
            what = maxima_clash(f)
            if what:
                raise SourceError(a.span, f"the argument '{f}' of '{a.name}' is reserved in maxima ({what}); "
                                          "choose another name")


def name_from_file(stem: str) -> str:
    """The equation name a file without `equation NAME` gets from its file
    name: non-identifier characters become '_', and a name that starts with
    a digit or is reserved in a target gets the prefix 'eq_' (int.mxm: eq_int)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", stem) or "equation"
    if name[0].isdigit() or clash(name):
        name = "eq_" + name
    return name


def use_of(mod, name: str) -> Span | None:
    """Where the Maxima text of `mod` first names the symbol `name` (outside
    comments and strings), or None."""
    text = mod.maxima_text
    pattern = re.compile(r"/\*.*?\*/|\"(?:[^\"\\]|\\.)*\"|(?<![A-Za-z0-9_%])" + re.escape(name) +
                         r"(?![A-Za-z0-9_%])", re.S)
    for m in pattern.finditer(text):
        if m.group(0) == name:
            line, col = mod.maxima_span.line, mod.maxima_span.column
            for ch in text[:m.start()]:
                line, col = (line + 1, 1) if ch == "\n" else (line, col + 1)
            return Span(mod.maxima_span.file, line, col)
    return None


def check_symbols(names, span: Span, mod=None) -> None:
    """The polynomial's symbols, when they become parameters without a
    declaration: each is reported at its first use in the Maxima text of
    `mod` (else at `span`, the polynomial's statement)."""
    for n in names:
        why = clash(n, file_scope=False)
        if why:
            where = (use_of(mod, n) if mod is not None else None) or span
            raise SourceError(where, f"the polynomial's symbol {why}; rename it, or declare the parameters")
