"""Parse a .mxm file into an MxmModule (typed, with source positions).

The grammar is max2code/generate/grammar/mxm.lark; this module turns Lark's tree
into dataclasses and Lark's exceptions into `FILE:LINE:COL: error: ...`.
"""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from fractions import Fraction
from importlib import resources

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from max2code.errors import SourceError, Span
from max2code.generate.names import name_from_file
from max2code.textio import read_text


@dataclass(frozen=True)
class Block:
    """Target-language text of an initialise/term/finalise block."""
    kind: str            # "initialise", "term" or "finalise"
    index: int | None    # the term's power of t; None for initialise/finalise
    lang: str | None     # None: for every language
    text: str            # the text between the braces, verbatim
    span: Span           # where the text starts (just after "{")


# What a parameter can describe (`parameter a "doc" : body 1 position`).
EFFECTS = ("position", "velocity", "acceleration", "orbit_radius", "angular_velocity", "phase", "radius", "spin")


@dataclass(frozen=True)
class Parameter:
    name: str
    doc: str
    span: Span
    body: int | None = None     # which body it belongs to
    effect: str | None = None   # one of EFFECTS


@dataclass(frozen=True)
class Option:
    name: str
    value: Fraction
    doc: str
    span: Span
    low: Fraction | None = None     # `in LOW..HIGH`: the values allowed (inclusive)
    high: Fraction | None = None

    @property
    def whole(self) -> bool:
        """A whole-number option (its default is whole) takes whole numbers only."""
        return self.value.denominator == 1

    def check(self, value: Fraction) -> str | None:
        """Why `value` is not allowed, or None."""
        if self.whole and value.denominator != 1:
            return f"must be a whole number (the default is {self.value})"
        if self.low is not None and not self.low <= value <= self.high:
            return f"must be from {_num(self.low)} to {_num(self.high)}"
        return None


def _num(v: Fraction) -> str:
    return str(v.numerator) if v.denominator == 1 else str(v)


@dataclass(frozen=True)
class Approximation:
    """`exact NAME(formals) { text }`: the Maxima function NAME of the text
    approximates `text` (the exact motion, in the formals and the variable)."""
    name: str
    formals: tuple[str, ...]
    text: str            # Maxima text between the braces, verbatim
    span: Span           # the declaration (its NAME)
    text_span: Span      # where the text starts


@dataclass(frozen=True)
class Shift:
    """`shift NAME { text }`: the parameter's value when the clock restarts at
    time t (Maxima text in the parameters and the variable)."""
    param: str
    text: str
    span: Span
    text_span: Span


@dataclass(frozen=True)
class MxmModule:
    """A parsed .mxm file."""
    path: str
    equation: str                    # generated function name
    doc: str
    variable: str                    # the polynomial's variable, t by default
    terms: int | None                # `polynomial terms N`, if given
    terms_span: Span | None
    parameters: tuple[Parameter, ...]
    options: tuple[Option, ...]
    blocks: tuple[Block, ...]
    maxima_text: str                 # Maxima text, verbatim
    maxima_span: Span                # where maxima_text starts
    dialect: str                     # "begin-end" or "brace"
    source_lines: int = field(default=0)
    approximations: tuple[Approximation, ...] = ()   # `exact` declarations
    shifts: tuple[Shift, ...] = ()                   # `shift` declarations
    equation_span: Span | None = None                # `equation NAME`, when given (else the name is the file's)
    variable_span: Span | None = None                # `variable NAME`, when given

    def blocks_for(self, lang: str) -> tuple[Block, ...]:
        """Blocks that apply to `lang`: of each kind, those tagged `for lang`
        if there are any, else the untagged ones."""
        out = []
        for kind in ("initialise", "term", "finalise"):
            tagged = [b for b in self.blocks if b.kind == kind and b.lang == lang]
            out += tagged or [b for b in self.blocks if b.kind == kind and b.lang is None]
        return tuple(out)


_FRIENDLY = {
    "INT": "a whole number", "NAME": "a name", "NUMBER": "a number", "STRING": 'a "string"',
    "BRACE_BLOCK": "a { ... } block", "MAXIMA_TEXT": "'begin' ... 'end'", "EQUAL": "'='",
    "$END": "end of file", "COLON": "':'",
}


def _friendly(term: str) -> str:
    if term in _FRIENDLY:
        return _FRIENDLY[term]
    if term.isupper() and term.isalpha():  # anonymous keyword terminals are named after the keyword
        return f"'{term.lower()}'"
    return term


@functools.lru_cache(maxsize=1)
def _parser() -> Lark:
    text = resources.files("max2code.generate").joinpath("grammar/mxm.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", strict=True, propagate_positions=True, maybe_placeholders=False)


def _span(path: str, tok: Token, skip: int = 0) -> Span:
    """Span of `tok`, moved `skip` characters into it."""
    line, col = tok.line, tok.column
    for ch in str(tok)[:skip]:
        if ch == "\n":
            line, col = line + 1, 1
        else:
            col += 1
    return Span(path, line, col)


class _Build(Transformer):
    def __init__(self, path: str):
        super().__init__()
        self.path = path

    @v_args(inline=True)
    def terms_decl(self, n):
        return ("terms", int(n), _span(self.path, n))

    def equation_decl(self, items):
        doc = items[1][1:-1] if len(items) > 1 else ""
        return ("equation", str(items[0]), doc, _span(self.path, items[0]))

    @v_args(inline=True)
    def variable_decl(self, name):
        return ("variable", str(name), _span(self.path, name))

    def parameter_decl(self, items):
        role = items[-1] if items and isinstance(items[-1], tuple) else None
        rest = items[:-1] if role else items
        doc = rest[1][1:-1] if len(rest) > 1 else ""
        body, effect = (role[0], role[1]) if role else (None, None)
        return ("parameter", Parameter(str(rest[0]), doc, _span(self.path, rest[0]), body, effect))

    def role(self, items):
        body, effect = items
        if str(effect) not in EFFECTS:
            raise SourceError(_span(self.path, effect), f"unknown effect '{effect}'; expected one of: {', '.join(EFFECTS)}")
        if int(body) < 1:
            raise SourceError(_span(self.path, body), "bodies are numbered from 1")
        return (int(body), str(effect))

    def option_decl(self, items):
        name, num = items[0], items[1]
        rest = items[2:]
        low = high = None
        if rest and isinstance(rest[0], tuple):
            (low, high, rspan), rest = rest[0], rest[1:]
        doc = rest[0][1:-1] if rest else ""
        opt = Option(str(name), Fraction(str(num)), doc, _span(self.path, name), low, high)
        if low is not None:
            if low > high:
                raise SourceError(rspan, f"the range {_num(low)}..{_num(high)} is empty")
            why = opt.check(opt.value)
            if why:
                raise SourceError(_span(self.path, num), f"option {name} = {num}: {why}")
        return ("option", opt)

    def range(self, items):
        return (Fraction(str(items[0])), Fraction(str(items[1])), _span(self.path, items[0]))

    def formals(self, items):
        return [(str(n), _span(self.path, n)) for n in items]

    def exact_decl(self, items):
        name, formals, tok = items
        return ("exact", Approximation(str(name), tuple(f for f, _ in formals), str(tok)[1:-1],
                                       _span(self.path, name), _span(self.path, tok, 1)), formals)

    def shift_decl(self, items):
        name, tok = items
        return ("shift", Shift(str(name), str(tok)[1:-1], _span(self.path, name), _span(self.path, tok, 1)))

    def header(self, items):
        return items[0]

    @v_args(inline=True)
    def lang(self, name):
        return str(name)

    def _block(self, kind, index, items):
        lang = items[0] if len(items) == 2 else None
        tok = items[-1]
        skip = 2 if tok.type == "RAW_BLOCK" else 1
        return Block(kind, index, lang, str(tok)[skip:-skip], _span(self.path, tok, skip))

    def initialise(self, items):
        return self._block("initialise", None, items)

    def finalise(self, items):
        return self._block("finalise", None, items)

    def term(self, items):
        n = items[0]
        block = self._block("term", int(n), items[1:])
        return (block, _span(self.path, n))

    @v_args(inline=True)
    def maxima_begin_end(self, tok):
        text = str(tok)
        body = text[len("begin"):text.rstrip().rfind("end")]
        return ("begin-end", body, _span(self.path, tok, len("begin")))

    @v_args(inline=True)
    def maxima_brace(self, tok):
        return ("brace", str(tok)[1:-1], _span(self.path, tok, 1))

    def block(self, items):
        return items[0]

    def start(self, items):
        return items


def _syntax_error(path: str, text: str, exc: UnexpectedInput) -> SourceError:
    line = getattr(exc, "line", None) or 1
    col = getattr(exc, "column", None) or 1
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        lines = text.splitlines() or [""]
        line, col = len(lines), len(lines[-1]) + 1
        exp = ", ".join(sorted(_friendly(t) for t in exc.expected))
        if not re.sub(r"//[^\n]*", "", text).strip():
            return SourceError(Span(path, 1, 1), "empty file: expected a header, blocks and the Maxima text ('begin' ... 'end')")
        return SourceError(Span(path, line, col), f"unexpected end of file; expected {exp}")
    if isinstance(exc, UnexpectedCharacters):
        rest = text[exc.pos_in_stream:]
        word = re.match(r"\S+", rest)
        found = word.group(0)[:30] if word else repr(rest[:1])
        if rest.startswith("begin"):
            return SourceError(Span(path, line, col), "'begin' has no matching 'end' (the Maxima text must close with 'end' at the start of a line)")
        if rest.startswith("{"):
            return SourceError(Span(path, line, col), "unbalanced braces: this '{' has no matching '}' (braces nest at most five deep)")
        allowed = sorted(_friendly(t) for t in (exc.allowed or ()))
        exp = f"; expected {', '.join(allowed)}" if allowed else ""
        return SourceError(Span(path, line, col), f"unexpected '{found}'{exp}")
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if str(tok) == "begin":
            return SourceError(Span(path, line, col), "'begin' has no matching 'end' (the Maxima text must close with 'end' at the start of a line)")
        exp = ", ".join(sorted(_friendly(t) for t in exc.expected))
        shown = str(tok).splitlines()[0][:30] if str(tok) else tok.type
        return SourceError(Span(path, line, col), f"unexpected '{shown}'; expected {exp}")
    return SourceError(Span(path, line, col), str(exc).splitlines()[0])


def parse_mxm(text: str, path: str = "<string>") -> MxmModule:
    """Parse .mxm `text`; errors name `path`, line and column."""
    try:
        tree = _parser().parse(text)
        items = _Build(path).transform(tree)
    except UnexpectedInput as exc:
        raise _syntax_error(path, text, exc) from None
    except VisitError as exc:  # a bad number in an option, an unknown effect
        if isinstance(exc.orig_exc, SourceError):
            raise exc.orig_exc from None
        raise SourceError(Span(path, 1, 1), f"invalid value: {exc.orig_exc}") from None
    return _check(path, text, items)


def _check(path: str, text: str, items: list) -> MxmModule:
    stem = re.sub(r"\.mxm$", "", path.replace("\\", "/").rsplit("/", 1)[-1])
    equation = name_from_file(stem)
    doc, variable, terms, terms_span = "", "t", None, None
    equation_span = variable_span = None
    params: list[Parameter] = []
    options: list[Option] = []
    blocks: list[Block] = []
    seen_terms: dict[str | None, list[int]] = {}   # per language tag
    maxima = None
    approximations: list[Approximation] = []
    shifts: list[Shift] = []
    for item in items:
        if isinstance(item, tuple) and item and item[0] == "terms":
            if terms is not None:
                raise SourceError(item[2], "'polynomial terms' is given twice")
            terms, terms_span = item[1], item[2]
            if terms < 1:
                raise SourceError(item[2], "'polynomial terms' must be at least 1")
        elif isinstance(item, tuple) and item and item[0] == "equation":
            equation, doc, equation_span = item[1], item[2], item[3]
        elif isinstance(item, tuple) and item and item[0] == "variable":
            variable, variable_span = item[1], item[2]
        elif isinstance(item, tuple) and item and item[0] == "parameter":
            p = item[1]
            if any(q.name == p.name for q in params):
                raise SourceError(p.span, f"parameter '{p.name}' is declared twice")
            params.append(p)
        elif isinstance(item, tuple) and item and item[0] == "option":
            o = item[1]
            if any(q.name == o.name for q in options):
                raise SourceError(o.span, f"option '{o.name}' is declared twice")
            options.append(o)
        elif isinstance(item, tuple) and item and item[0] == "exact":
            a, formals = item[1], item[2]
            if any(q.name == a.name for q in approximations):
                raise SourceError(a.span, f"'exact {a.name}' is declared twice")
            seen: set[str] = set()
            for f, fspan in formals:
                if f in seen:
                    raise SourceError(fspan, f"'{f}' appears twice in the arguments of '{a.name}'")
                seen.add(f)
            if not a.text.strip():
                raise SourceError(a.text_span, f"'exact {a.name}' needs the exact expression between the braces")
            approximations.append(a)
        elif isinstance(item, tuple) and item and item[0] == "shift":
            sh = item[1]
            if any(q.param == sh.param for q in shifts):
                raise SourceError(sh.span, f"'shift {sh.param}' is declared twice")
            if not sh.text.strip():
                raise SourceError(sh.text_span, f"'shift {sh.param}' needs its value at time t between the braces")
            shifts.append(sh)
        elif isinstance(item, tuple) and item and isinstance(item[0], Block):
            block, nspan = item
            seq = seen_terms.setdefault(block.lang, [])
            if block.index != len(seq):
                raise SourceError(nspan, f"term {block.index} is out of order: expected term {len(seq)} (terms count up from 0)")
            seq.append(block.index)
            blocks.append(block)
        elif isinstance(item, Block):
            if item.kind == "initialise" and any(b.kind in ("term", "finalise") and b.lang == item.lang for b in blocks):
                raise SourceError(item.span, "'initialise' must come before the 'term' and 'finalise' blocks")
            if item.kind == "finalise" and any(b.kind == "finalise" and b.lang == item.lang for b in blocks):
                raise SourceError(item.span, "'finalise' is given twice")
            if item.kind == "initialise" and any(b.kind == "initialise" and b.lang == item.lang for b in blocks):
                raise SourceError(item.span, "'initialise' is given twice")
            blocks.append(item)
        elif isinstance(item, tuple) and item and item[0] in ("begin-end", "brace"):
            maxima = item
    assert maxima is not None  # the grammar requires it
    dialect, mtext, mspan = maxima
    if not mtext.strip():
        raise SourceError(mspan, "the Maxima text is empty: expected the polynomial's equation")
    for lang, seq in sorted(seen_terms.items(), key=lambda kv: kv[0] or ""):
        if terms is not None and len(seq) != terms:
            which = f" for {lang}" if lang else ""
            raise SourceError(terms_span, f"'polynomial terms {terms}' but the file has {len(seq)} term blocks{which} (term 0 to term {len(seq) - 1})")
    if variable in {p.name for p in params}:
        raise SourceError(next(p.span for p in params if p.name == variable), f"'{variable}' is the polynomial's variable and cannot be a parameter")
    return MxmModule(
        path=path, equation=equation, doc=doc, variable=variable, terms=terms, terms_span=terms_span,
        parameters=tuple(params), options=tuple(options), blocks=tuple(blocks), maxima_text=mtext,
        maxima_span=mspan, dialect=dialect, source_lines=text.count("\n") + (0 if text.endswith("\n") else 1),
        approximations=tuple(approximations), shifts=tuple(shifts), equation_span=equation_span,
        variable_span=variable_span,
    )


def read_mxm(path: str, name: str | None = None) -> MxmModule:
    """Read and parse the .mxm file at `path`; `name` (default: `path`) is how
    messages, headers and #line directives name it."""
    return parse_mxm(read_text(path), name or path)
