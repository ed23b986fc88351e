"""Python 3 (floats; math.sin / math.cos)."""
from max2code.targets.base import Target


class Python(Target):
    name = "python"
    extension = ".py"
    comment = ("# ", "")
    calls = {"sin": "math.sin({})", "cos": "math.cos({})", "sqrt": "math.sqrt({})", "abs": "abs({})"}
    statement_end = ""
    compiled = False
    requires = "Python 3.10 or later; the package max2code-rt (pure Python)"
    links = "`import` the generated module; it imports max2code_rt"
    reserved = frozenset("""
        False None True and as assert async await break class continue def del elif else except finally for from
        global if import in is lambda nonlocal not or pass raise return try while with yield match case type
        math abs len max min float int range list tuple print
        coef degree mask lo hi t horizon options out rate result motion nparams max2code_rt""".split()
        + [f"coef{k}" for k in range(17)])
    reserved_prefixes = ("_",)
    logical_and = "and"
