"""Python's toolchain: nothing to compile, so the harnesses and the
generated simulator modules are byte-compiled (a syntax error fails there),
and the runtime max2code_rt runs them; its install copies the distribution."""
from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from max2code.toolchain.base import Toolchain


class PythonToolchain(Toolchain):
    name = "python"
    harness_source = "harness.py"

    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Byte-compile: a syntax error fails here, as a compile error would."""
        return [[sys.executable, "-W", "error", "-m", "py_compile", src]]

    def testee(self, baseline: bool = False) -> list[str]:
        return [sys.executable, "-m", "max2code_rt.testee"]

    def install_runtime(self, prefix: str) -> str:
        """Copy the distribution max2code-rt (pyproject.toml and the package) to
        PREFIX/lib/max2code/python/max2code-rt, for pip to install from there."""
        src = self.runtime_dir()
        dest = Path(prefix).resolve() / "lib" / "max2code" / "python" / "max2code-rt"
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        shutil.copy2(src / "pyproject.toml", dest / "pyproject.toml")
        shutil.copytree(src / "max2code_rt", dest / "max2code_rt", ignore=shutil.ignore_patterns("__pycache__"))
        return f"copied the distribution max2code-rt to {dest}; install it with\n  pip install {dest}"

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        return [[sys.executable, "-W", "error", "-m", "py_compile", src, os.path.join(workdir, "generated.py")]]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [sys.executable, "-W", "error", src]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Byte-compile the generated modules (the simulator is max2code_rt.sim)."""
        return [[sys.executable, "-W", "error", "-m", "py_compile", *generated.values()]]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [sys.executable, "-W", "error", "-m", "max2code_rt.sim_main",
                generated["circle_circle"], generated["point_edge"]]
