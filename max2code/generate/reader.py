"""Read Maxima's one-line output into an exact Expr tree (second grammar:
max2code/generate/grammar/maxima_output.lark)."""
from __future__ import annotations

import functools
from fractions import Fraction
from importlib import resources

from lark import Lark, Transformer, v_args
from lark.exceptions import UnexpectedInput

from max2code.generate.expr import Add, Call, Eq, Expr, Mul, Num, Pow, Sym


class MaximaOutputError(ValueError):
    """Maxima's output could not be read; `column` is 1-based in the text."""

    def __init__(self, message: str, column: int):
        super().__init__(message)
        self.column = column


def _flat(cls, items):
    out = []
    for it in items:
        out.extend(it.terms if cls is Add and isinstance(it, Add) else
                   it.factors if cls is Mul and isinstance(it, Mul) else (it,))
    return cls(tuple(out))


_MINUS_ONE = Num(Fraction(-1))


class _ToExpr(Transformer):
    @v_args(inline=True)
    def integer(self, tok):
        return Num(Fraction(int(tok)))

    @v_args(inline=True)
    def float(self, tok):
        s = str(tok).lower().replace("b", "e").replace("d", "e")
        return Num(Fraction(s))   # the decimal as written, exactly

    @v_args(inline=True)
    def symbol(self, tok):
        return Sym(str(tok))

    def call(self, items):
        return Call(str(items[0]), tuple(items[1]))

    def noun(self, items):
        raise MaximaOutputError(f"unevaluated quoted call '{items[0]}(...)' in the result", items[0].column)

    def args(self, items):
        return list(items)

    def add(self, items):
        return _flat(Add, items)

    def sub(self, items):
        return _flat(Add, [items[0], _negate(items[1])])

    def mul(self, items):
        return _flat(Mul, items)

    def div(self, items):
        a, b = items
        if isinstance(b, Num):
            if b.value == 0:
                raise MaximaOutputError("division by zero in Maxima's result", 1)
            return _flat(Mul, [a, Num(1 / b.value)])
        return _flat(Mul, [a, Pow(b, _MINUS_ONE)])

    @v_args(inline=True)
    def neg(self, a):
        return _negate(a)

    @v_args(inline=True)
    def pow(self, base, exp):
        return Pow(base, exp)

    @v_args(inline=True)
    def equation(self, lhs, rhs):
        return Eq(lhs, rhs)


@functools.lru_cache(maxsize=1)
def _parser() -> Lark:
    # the transformer runs inside the LALR parser: no tree is built, so a
    # sum of thousands of terms does not recurse thousands deep
    text = resources.files("max2code.generate").joinpath("grammar/maxima_output.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", strict=True, maybe_placeholders=False, transformer=_ToExpr())


def _negate(e: Expr) -> Expr:
    if isinstance(e, Num):
        return Num(-e.value)
    return _flat(Mul, [_MINUS_ONE, e])


def read_expr(text: str) -> Expr:
    """Parse one Maxima output string."""
    try:
        return _parser().parse(text)
    except UnexpectedInput as exc:
        col = getattr(exc, "column", 1) or 1
        near = text[max(0, col - 20):col + 20]
        raise MaximaOutputError(f"cannot read Maxima's output at column {col}: ...{near}...", col) from None
    except Exception as exc:  # a transformer error wraps the original one
        orig = getattr(exc, "orig_exc", exc)
        if isinstance(orig, MaximaOutputError):
            raise orig from None
        raise
