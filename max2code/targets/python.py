"""Python 3 (floats; math.sin / math.cos)."""

from max2code.targets.base import Target, visible


class Python(Target):
    name = "python"
    extension = ".py"
    comment = ("# ", "")
    calls = {"sin": "math.sin({})", "cos": "math.cos({})", "sqrt": "math.sqrt({})", "abs": "abs({})"}
    statement_end = ""
    compiled = False
    requires = "Python 3.10 or later; the package max2code-rt (pure Python)"
    links = "`import` the generated module; it imports max2code_rt"
    words = (
        ("a keyword of Python", frozenset("""
            False None True and as assert async await break class continue def del elif else except finally for
            from global if import in is lambda nonlocal not or pass raise return try while with yield match case
            type""".split())),
        ("a built-in name of Python", frozenset("""
            abs aiter all anext any ascii bin bool breakpoint bytearray bytes callable chr classmethod compile
            complex copyright credits delattr dict dir divmod enumerate eval exec exit filter float format
            frozenset getattr globals hasattr hash help hex id input int isinstance issubclass iter len license list
            locals map max memoryview min next object oct open ord pow print property quit range repr reversed
            round set setattr slice sorted staticmethod str sum super tuple type vars zip
            ArithmeticError AssertionError AttributeError BaseException BaseExceptionGroup BlockingIOError
            BrokenPipeError BufferError BytesWarning ChildProcessError ConnectionAbortedError ConnectionError
            ConnectionRefusedError ConnectionResetError DeprecationWarning EOFError Ellipsis EncodingWarning
            EnvironmentError Exception ExceptionGroup FileExistsError FileNotFoundError FloatingPointError
            FutureWarning GeneratorExit IOError ImportError ImportWarning IndentationError IndexError
            InterruptedError IsADirectoryError KeyError KeyboardInterrupt LookupError MemoryError
            ModuleNotFoundError NameError NotADirectoryError NotImplemented NotImplementedError OSError
            OverflowError PendingDeprecationWarning PermissionError ProcessLookupError PythonFinalizationError
            RecursionError ReferenceError ResourceWarning RuntimeError RuntimeWarning StopAsyncIteration
            StopIteration SyntaxError SyntaxWarning SystemError SystemExit TabError TimeoutError TypeError
            UnboundLocalError UnicodeDecodeError UnicodeEncodeError UnicodeError UnicodeTranslateError
            UnicodeWarning UserWarning ValueError Warning ZeroDivisionError""".split())),
        ("a name the generated Python uses", frozenset("""
            math coef degree mask lo hi t horizon options out rate result motion nparams max2code_rt""".split()
            + [f"coef{k}" for k in range(17)])),
    )
    reserved_prefixes = ("_",)
    logical_and = "and"

    def escape(self, text: str, where: str) -> str:
        """A '#' comment ends at a line end; a doc is the text of a triple-quoted
        string, where backslash and quote are escaped too (and the string's value
        is `text` again)."""
        text = visible(text, _escape) if where != "doc" else "".join(
            "\\" + ch if ch in '\\"' else ch if ch.isprintable() else _escape(ord(ch)) for ch in text)
        if where == "string":
            raise ValueError("the generated Python prints no user text in strings")
        return text


def _escape(c: int) -> str:
    """A Python string escape of the character with code point `c`."""
    return f"\\x{c:02x}" if c <= 0xFF else f"\\u{c:04x}" if c <= 0xFFFF else f"\\U{c:08x}"
