"""The printer shared by all targets: a `_print_<kind>` per node kind and
one precedence table.  A target subclass sets its properties (literal
form, call names, comment style, line directives, file layout template)
and overrides a `_print_` method only where its syntax differs."""
from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

if TYPE_CHECKING:       # annotations only: the simulator's commands import the targets without the generator
    from max2code.generate.lower import Node

# precedence: higher binds tighter
PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "neg": 3, "call": 4, "lit": 4, "ref": 4}


class Target:
    name: ClassVar[str]
    extension: ClassVar[str]                   # default output file extension
    comment: ClassVar[tuple[str, str]]         # (open, close) for a line comment
    line_directive: ClassVar[str | None] = None   # format with {line} {file}; None: origin comments
    line_offset: ClassVar[int] = 0             # added to the line in a directive (gm2 needs 1)
    exponent_letter: ClassVar[str] = "e"
    calls: ClassVar[dict[str, str]] = {"sin": "sin({})", "cos": "cos({})", "sqrt": "sqrt({})", "abs": "fabs({})"}
    statement_end: ClassVar[str] = ";"
    header_extension: ClassVar[str | None] = None   # a declarations file next to the code (templates/<lang>/header.j2)

    # ---- capabilities (what the reports, the runner and the tests loop over) ----
    compiled: ClassVar[bool] = True            # a native build (timed over many passes); Python is interpreted
    simulator: ClassVar[bool] = True           # has a simulator runtime (max2code simulate --lang NAME)
    gsl_baseline: ClassVar[str | None] = None  # the conformance name of its GSL baseline testee, if any
    requires: ClassVar[str] = ""               # what must be installed to build and run its code
    links: ClassVar[str] = ""                  # how generated code and the runtime link into a program
    # the exact code's NAME_window entry (every variant's coefficients again, beside the truncation
    # bound, sharing their sines and cosines); without it the driver calls shift, coefficients and
    # truncation one by one, with the same answers to the bit
    window_entry: ClassVar[bool] = True
    # names a parameter or equation may not take (max2code/generate/names.py asks every target
    # through reserved_as): (what they are, the names), e.g. the language's keywords, the library
    # names the generated file can see, the names the printer and templates use
    words: ClassVar[tuple[tuple[str, frozenset[str]], ...]] = ()
    # the same, for the names the generated code declares at file scope only (the equation's, the
    # `exact` functions'), not for parameters, which may hide them
    file_scope_words: ClassVar[tuple[tuple[str, frozenset[str]], ...]] = ()
    reserved_prefixes: ClassVar[tuple[str, ...]] = ()   # prefixes of the runtime's and the printer's names

    @classmethod
    def reserved_as(cls, name: str, file_scope: bool = True) -> str | None:
        """What `name` is in this language when the generated code cannot take it
        as an identifier (e.g. "a keyword of C"), or None; `file_scope`: whether
        the generated code declares it at file scope (else it is a parameter)."""
        for what, names in cls.words + (cls.file_scope_words if file_scope else ()):
            if name in names:
                return what
        for prefix in cls.reserved_prefixes:
            if name.startswith(prefix):
                return f"a name starting with '{prefix}' (reserved for the runtime and the generated code)"
        return None

    # ---- single precision (max2code --real=float) ------------------------
    single_type: ClassVar[str | None] = None          # the language's float type; None: it has none
    single_calls: ClassVar[dict[str, str]] = {}
    single_suffix: ClassVar[str] = ""                 # after a single-precision literal
    single_copies: ClassVar[bool] = False             # parameters stay double; the body uses float copies NAME_s

    def __init__(self, real: str = "double", renames: dict[str, str] | None = None):
        """A printer of arithmetic in `real` ("double" or "float") that prints the
        references in `renames` under their new names; configured once, never mutated."""
        if real not in ("double", "float"):
            raise ValueError(f"unknown real type {real!r} (double or float)")
        if real == "float" and self.single_type is None:
            raise ValueError(f"{self.name} has no single-precision floating-point type")
        self.single = real == "float"              # this printer prints single precision
        self.renames = dict(renames or {})         # references printed under another name

    def renaming(self, renames: dict[str, str]) -> "Target":
        """The same printer, printing the references in `renames` under their new names."""
        return type(self)("float" if self.single else "double", renames)

    def float_copies(self, names) -> "Target":
        """The printer for a body that reads float copies NAME_s of these
        parameters (single precision in a language without implicit
        conversions), or this printer when it needs none."""
        if self.single and self.single_copies:
            return self.renaming({p: p + "_s" for p in names})
        return self

    @property
    def real(self) -> str | None:
        """The type of the generated arithmetic, when it is single precision."""
        return self.single_type if self.single else None

    # ---- expressions --------------------------------------------------
    def expr(self, n: Node) -> str:
        return getattr(self, "_print_" + {"+": "add", "-": "sub", "*": "mul", "/": "div"}.get(n[0], n[0]))(n)

    def _operand(self, n: Node, parent_prec: int, right: bool = False) -> str:
        prec = PRECEDENCE[n[0]]
        text = self.expr(n)
        # negations are always parenthesised as operands (Modula-2 needs it, the rest read better)
        if n[0] == "neg" or prec < parent_prec or (right and prec == parent_prec):
            return f"({text})"
        return text

    def _binary(self, n: Node, op: str) -> str:
        p = PRECEDENCE[n[0]]
        # + and * are printed left-associative; the right operand of any
        # operator of the same precedence is parenthesised, so the
        # evaluation order is exactly the tree's.
        return f"{self._operand(n[1], p)} {op} {self._operand(n[2], p, right=True)}"

    def _print_add(self, n: Node) -> str:
        return self._binary(n, "+")

    def _print_sub(self, n: Node) -> str:
        return self._binary(n, "-")

    def _print_mul(self, n: Node) -> str:
        p = PRECEDENCE["*"]
        return f"{self._operand(n[1], p)}*{self._operand(n[2], p, right=True)}"

    def _print_div(self, n: Node) -> str:
        p = PRECEDENCE["/"]
        return f"{self._operand(n[1], p)}/{self._operand(n[2], p, right=True)}"

    def _print_neg(self, n: Node) -> str:
        return "-" + self._operand(n[1], PRECEDENCE["neg"])

    def _print_ref(self, n: Node) -> str:
        return self.renames.get(n[1], n[1])

    def _print_call(self, n: Node) -> str:
        return (self.single_calls if self.single else self.calls)[n[1]].format(self.expr(n[2]))

    def _print_lit(self, n: Node) -> str:
        if self.single:
            return self.single_literal(n[1])
        return self.real_literal(n[1])

    def single_literal(self, x: float) -> str:
        """The single-precision literal nearest to `x`, in its shortest form."""
        import struct
        f = struct.unpack("<f", struct.pack("<f", x))[0]
        for digits in range(1, 10):
            text = "%.*g" % (digits, f)
            if struct.unpack("<f", struct.pack("<f", float(text)))[0] == f:
                break
        return self.real_literal(float(text)) + self.single_suffix

    def real_literal(self, x: float) -> str:
        """A real literal that reads back as exactly `x` (never an integer)."""
        if x != x or x in (float("inf"), float("-inf")):
            raise ValueError("non-finite constant in generated code")
        s = repr(float(x))
        mant, _, exp = s.partition("e")
        if "." not in mant:
            mant += ".0"
        if exp:
            return f"{mant}{self.exponent_letter}{int(exp)}"
        return mant

    # ---- selection logic -----------------------------------------------
    equals: ClassVar[str] = "=="
    logical_and: ClassVar[str] = "&&"

    def zero_test(self, names) -> str:
        """An exact test that every parameter in `names` is zero."""
        return f" {self.logical_and} ".join(f"{n} {self.equals} {self.real_literal(0.0)}" for n in names)

    # ---- lines --------------------------------------------------------
    def origin_line(self, line: int, file: str) -> str:
        """A #line directive, or an origin comment where the language has none."""
        if self.line_directive is not None:
            return self.line_directive.format(line=line + self.line_offset, file=self.escape(file, "string"))
        return self.comment_line(f"from {file}:{line}")

    def comment_line(self, text: str) -> str:
        """A comment of one line holding `text` (escaped: it may carry user text)."""
        return f"{self.comment[0]}{self.escape(text, 'comment')}{self.comment[1]}"

    # ---- user text ------------------------------------------------------
    def escape(self, text: str, where: str) -> str:
        """User text (a doc string, a file name) as it may stand in this
        language's `where`: "comment" (inside a one-line comment), "doc" (a
        function's or parameter's documentation) or "string" (inside a string
        literal: a #line directive's file name).  The result is one line that
        cannot end the comment, doc or string early.  Every target prints
        every piece of user text through this method, and only through it."""
        raise NotImplementedError(type(self).__name__)


def visible(text: str, form) -> str:
    """`text` with every character that is not printable (line ends, controls,
    format characters such as bidirectional overrides, unpaired surrogates,
    unassigned code points) replaced by form(code point)."""
    return "".join(ch if ch.isprintable() else form(ord(ch)) for ch in text)


def c_string(text: str) -> str:
    """The contents of a C string literal (as the C preprocessor reads a #line
    directive's file name) that means `text`: backslash, quote and '?' (no
    trigraph) escaped, what is not printable as octal escapes of its bytes
    (UTF-8; a file name's undecodable bytes as they were)."""
    out = []
    for ch in text:
        if ch in '\\"?':
            out.append("\\" + ch)
        elif ch.isprintable():
            out.append(ch)
        else:
            try:
                data = ch.encode("utf-8", "surrogateescape")
            except UnicodeEncodeError:
                data = ch.encode("utf-8", "surrogatepass")
            out.append("".join(f"\\{b:03o}" for b in data))
    return "".join(out)


def code_point(c: int) -> str:
    """A readable name of a character that comments cannot show: \\uXXXX."""
    return f"\\u{c:04x}" if c <= 0xFFFF else f"\\U{c:08x}"
