"""Building and running generated code, one toolchain per language: the
harness programs around generated code (harness.py, exact.py), the runtime
libraries' builds and installs (install.py for `max2code runtime`), the
conformance testees and the simulators' builds and runs.

TOOLCHAINS holds the toolchain of every language in max2code.targets.LANGUAGES,
in the same order, by the same name; what one language needs is in its own
module (c.py, m2.py, python.py, rust.py), the interface in base.py.  The
printers (max2code.targets) know nothing of building.
"""
from __future__ import annotations

from max2code.toolchain.base import Toolchain
from max2code.toolchain.c import CToolchain
from max2code.toolchain.m2 import Modula2Toolchain
from max2code.toolchain.python import PythonToolchain
from max2code.toolchain.rust import RustToolchain

TOOLCHAINS: dict[str, type[Toolchain]] = {t.name: t for t in (PythonToolchain, CToolchain, RustToolchain,
                                                              Modula2Toolchain)}


def toolchain(lang: str) -> Toolchain:
    """The toolchain of `lang`."""
    return TOOLCHAINS[lang]()
