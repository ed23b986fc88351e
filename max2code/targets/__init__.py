"""Target languages: one printer and one properties table per language.

LANGUAGES is the only list of languages: the simulator, the conformance
runner, the reports and the tests loop over it and ask each target's
capability properties (simulator, gsl_baseline, compiled, header_extension,
single_type).  Its order is the reference runtime (Python) first, then the
compiled ones.  Printing only: building and running a language's code is
its toolchain's job (max2code/toolchain/).  Adding a language means adding
a module here, one in max2code/toolchain/ and templates/<lang>/; nothing
else changes.
"""
from __future__ import annotations

from max2code.targets.base import Target
from max2code.targets.c import C
from max2code.targets.m2 import Modula2
from max2code.targets.python import Python
from max2code.targets.rust import Rust

LANGUAGES: dict[str, type[Target]] = {t.name: t for t in (Python, C, Rust, Modula2)}


def simulator_languages() -> tuple[str, ...]:
    """The languages with a simulator runtime, the reference first."""
    return tuple(n for n, t in LANGUAGES.items() if t.simulator)


def gsl_baselines() -> tuple[str, ...]:
    """The conformance names of the GSL baseline testees."""
    return tuple(t.gsl_baseline for t in LANGUAGES.values() if t.gsl_baseline)


def target(lang: str, real: str = "double") -> Target:
    """The printer of `lang`, configured for arithmetic in `real`."""
    return LANGUAGES[lang](real)
