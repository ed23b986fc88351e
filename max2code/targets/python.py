"""Python 3 (floats; math.sin / math.cos)."""
import sys

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

    harness_source = "harness.py"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Byte-compile: a syntax error fails here, as a compile error would."""
        return [[sys.executable, "-W", "error", "-m", "py_compile", src]]

    def testee(self, baseline: bool = False) -> list[str]:
        return [sys.executable, "-m", "max2code_rt.testee"]

    def install_runtime(self, prefix: str) -> str:
        """Copy the distribution max2code-rt (pyproject.toml and the package) to
        PREFIX/lib/max2code/python/max2code-rt, for pip to install from there."""
        import shutil
        from pathlib import Path
        src = self.runtime_dir()
        dest = Path(prefix).resolve() / "lib" / "max2code" / "python" / "max2code-rt"
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        shutil.copy2(src / "pyproject.toml", dest / "pyproject.toml")
        shutil.copytree(src / "max2code_rt", dest / "max2code_rt", ignore=shutil.ignore_patterns("__pycache__"))
        return f"copied the distribution max2code-rt to {dest}; install it with\n  pip install {dest}"

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        import os
        return [[sys.executable, "-W", "error", "-m", "py_compile", src, os.path.join(workdir, "generated.py")]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [sys.executable, "-W", "error", src]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Byte-compile the generated modules (the simulator is max2code_rt.sim)."""
        return [[sys.executable, "-W", "error", "-m", "py_compile", *generated.values()]]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [sys.executable, "-W", "error", "-m", "max2code_rt.sim_main",
                generated["circle_circle"], generated["point_edge"]]
