"""Render a FunctionIR (or a paper-style fragment) through templates/<lang>/."""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass

import jinja2

from max2code.generate.lower import FunctionIR, Node
from max2code.paths import TEMPLATES
from max2code.targets.base import Target

TEMPLATE_DIR = str(TEMPLATES)


@functools.lru_cache(maxsize=None)
def environment() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATE_DIR),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


@dataclass(frozen=True)
class BodyLine:
    kind: str          # "derived", "temp" or "coef"
    name: str          # variable name, or the power of t for "coef"
    text: str          # the printed expression
    origin: str | None # a #line directive or origin comment


@dataclass(frozen=True)
class FragmentItem:
    text: str
    origin: str | None


def _finish(text: str, target: Target, out_name: str) -> str:
    """Replace @@RESET@@ with a directive back to the generated file itself."""
    lines = re.sub(r"\n{3,}", "\n\n", text).split("\n")
    for i, line in enumerate(lines):
        if line == "@@RESET@@" and target.line_directive:
            # the line after the directive is line i + 2 of this file
            lines[i] = target.origin_line(i + 2, out_name)
    return "\n".join(lines).rstrip("\n") + "\n"


@dataclass(frozen=True)
class SelectionCase:
    name: str                 # the variant's function
    degree: int
    masks: tuple[int, ...]    # the switch masks for which it is the cheapest exact variant


@dataclass(frozen=True)
class Selection:
    """Selection logic: bit i of the mask is set when every parameter of
    switches[i] is exactly zero; each mask maps to one variant."""
    name: str                                       # the entry function
    switches: tuple[tuple[str, tuple[str, ...]], ...]   # (label, parameters)
    cases: tuple[SelectionCase, ...]                # cheapest first
    max_degree: int
    effects: str                                    # the effects the code was generated for
    complete: bool                                  # every mask has a variant (no effect left out)


def _function_context(target: Target, fn: FunctionIR, note: str, mxm_name: str, line_directives: bool) -> dict:
    origin = target.origin_line(fn.origin.line, mxm_name) if line_directives else None
    printer = target.float_copies(fn.params)     # --real=float: the body may read float copies of the parameters
    body = [BodyLine("derived", a.name, printer.expr(a.node), origin) for a in fn.derived]
    body += [BodyLine("temp", a.name, printer.expr(a.node), origin) for a in fn.temps]
    body += [BodyLine("coef", str(k), printer.expr(c), origin) for k, c in enumerate(fn.coefficients)]
    if origin is not None and target.line_directive is None:
        # an origin comment once is enough where the language has no directives
        body = [body[0]] + [BodyLine(b.kind, b.name, b.text, None) for b in body[1:]]
    out_array = "coef"
    while out_array in fn.params or out_array in {a.name for a in fn.derived + fn.temps}:
        out_array += "_"
    unused = set(fn.unused_params)      # a walk of every tree: once, not once per parameter
    used = [p for p in fn.params if p not in unused]
    return {"fn": fn, "body": body, "locals": [a.name for a in fn.derived + fn.temps], "out": out_array, "note": note,
            "used": used}


def render_module(target: Target, functions: list[tuple[FunctionIR, str]], selection: Selection | None,
                  header: list[str], variable: str, mxm_name: str, out_name: str, line_directives: bool,
                  exact: dict | None = None, declarations: str | None = None) -> str:
    """A file of coefficient functions (the full equation and its variants)
    and, when given, the selection logic that picks among them.  With
    `declarations` (the header's file name), the target's header for that
    file instead: the same entries' declarations (templates/<lang>/header.j2)."""
    first = functions[0][0]
    ctx = [_function_context(target, fn, note, mxm_name, line_directives) for fn, note in functions]
    for i, c in enumerate(ctx):
        c["first"] = i == 0
    by_mask: list[str | None] = []
    if selection is not None:
        names = {m: c.name for c in selection.cases for m in c.masks}
        by_mask = [names.get(m) for m in range(1 << len(selection.switches))]
    tpl = environment().get_template(f"{target.name}/{'header.j2' if declarations else 'file.j2'}")
    toc = selection.name.replace("_coefficients", "_toc") if selection is not None else None
    which = selection.name.replace("_coefficients", "_variant") if selection is not None else None
    # for each mask, the index of its variant in selection.cases (-1: none)
    index_by_mask = [] if selection is None else [
        next((i for i, c in enumerate(selection.cases) if m in c.masks), -1) for m in range(1 << len(selection.switches))]
    text = tpl.render(target=target, functions=ctx, selection=selection, selection_by_mask=by_mask, toc=toc,
                      variant_fn=which, index_by_mask=index_by_mask,
                      variant_unused=[] if selection is None else
                      [p for p in first.params if all(p not in zs for _, zs in selection.switches)],
                      header=header, variable=variable, exact=exact, decl=bool(declarations), source=out_name,
                      guard=_guard(declarations or ""),
                      params=list(zip(first.params, first.param_docs)),
                      reset=bool(line_directives and target.line_directive))
    return _finish(text, target, out_name)


def _guard(file_name: str) -> str:
    """The include guard of a header named `file_name`: an ASCII C identifier."""
    guard = re.sub(r"[^A-Za-z0-9]", "_", file_name).upper()
    return guard if guard[:1].isalpha() else "M2C_GENERATED_" + guard


def render_fragment(target: Target, items: list[FragmentItem], header: list[str], out_name: str,
                    line_directives: bool) -> str:
    tpl = environment().get_template(f"{target.name}/fragment.j2")
    text = tpl.render(target=target, items=items, header=header,
                      reset=bool(line_directives and target.line_directive))
    return _finish(text, target, out_name)


def inline_derived(n: Node, derived: dict[str, Node]) -> Node:
    """Put derived inputs (sin(f), 1/x) back in place, for fragments without locals."""
    if n[0] == "ref" and n[1] in derived:
        return inline_derived(derived[n[1]], derived)
    if n[0] in ("lit", "ref"):
        return n
    return (n[0],) + tuple(inline_derived(c, derived) if isinstance(c, tuple) else c for c in n[1:])
