"""What every language's toolchain does: the commands that build and run
its harness programs, its conformance testee and its simulator, and the
build and install of its runtime library.  A language's module subclasses
Toolchain; the methods that raise NotImplementedError are the ones it must
define."""
from __future__ import annotations

import functools
import subprocess
import sys
from pathlib import Path
from typing import ClassVar

from max2code.errors import Max2CodeError
from max2code.paths import RUNTIMES


class Toolchain:
    name: ClassVar[str]                        # the language's name, as in max2code.targets.LANGUAGES
    # the compilers and tools whose version decides what its builds make (each answers `--version`)
    tools: ClassVar[tuple[str, ...]] = ()

    def tool_versions(self) -> dict[str, str]:
        """Each tool's first line of `--version` (or "not found"), and the
        Python running max2code: part of the key of programs kept for reuse
        (max2code.toolchain.cache), so that a new compiler rebuilds them."""
        return {"python": sys.version, **{tool: _version(tool) for tool in self.tools}}

    # ---- evaluation harness (templates/<lang>/harness.j2) ---------------
    harness_source: ClassVar[str]              # the harness's file name in its workdir

    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """Commands that compile the harness at `src` into `exe`."""
        raise NotImplementedError(type(self).__name__)

    harness_rows_fixed: ClassVar[bool] = False   # the exact harness holds at most toolchain.exact.MAX_ROWS rows

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        """Commands that compile an exact-motion or polynomial harness (with the
        generated file in `workdir`) against the runtime, GSL baseline included."""
        raise NotImplementedError(type(self).__name__)

    def harness_run(self, src: str, exe: str) -> list[str]:
        """The command that runs the built harness."""
        raise NotImplementedError(type(self).__name__)

    # Every toolchain in TOOLCHAINS defines the methods above and testee
    # (tests build and run each one); the simulator pair only for languages
    # whose `simulator` capability (max2code.targets) is True, the only ones
    # `simulate` and `crosscheck` accept.

    # ---- the simulator (docs/simulator.md) ------------------------------
    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Commands that build this language's simulator in `workdir` from the
        generated files (equation name -> file name in workdir); `variants`:
        how many variants each equation's NAME_variant counts (from the
        generator's selection, GeneratedFile.selection)."""
        raise NotImplementedError(f"{type(self).__name__} must define sim_build and sim_run (simulator = True)")

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        """The command that runs the built simulator (compiled scene on stdin)."""
        raise NotImplementedError(f"{type(self).__name__} must define sim_build and sim_run (simulator = True)")

    # the file name of the shared library of the live world API (docs/engine-api.md)
    # that world_build makes in sim_build's workdir, or None when it makes none
    world_library: ClassVar[str | None] = None

    def world_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Commands that build the shared library `world_library` in sim_build's
        workdir (beside the built simulator, from the same generated files), run
        only when it is asked for (max2code.sim.simulate.world_library)."""
        raise NotImplementedError(f"{type(self).__name__} names a world_library but does not define world_build")

    # ---- conformance testee (docs/roots.md, "Conformance suite") -------
    def testee(self, baseline: bool = False) -> list[str]:
        """Build this runtime's conformance testee if needed (the GSL baseline's
        with `baseline`) and return the command that runs it."""
        raise NotImplementedError(f"{type(self).__name__} must define testee")

    # ---- the runtime as a library (max2code runtime LANG [--install PREFIX]) ----
    def runtime_dir(self) -> Path:
        """The folder of this language's runtime sources."""
        return RUNTIMES / self.name

    def install_runtime(self, prefix: str) -> str:
        """Build and install the runtime under `prefix`; returns how to use it."""
        raise Max2CodeError(f"max2code runtime: error: {self.name}: no install step; the sources are in {self.runtime_dir()}")

    def runtime_flags(self) -> list[str]:
        """Compiler arguments that make this checkout's runtime (its root
        solver) available to generated code; builds the runtime if needed."""
        return []


@functools.lru_cache(maxsize=None)
def _version(tool: str) -> str:
    try:
        r = subprocess.run([tool, "--version"], stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return "not found"
    return (r.stdout or r.stderr).strip().split("\n", 1)[0]
