"""Target languages: one printer and one properties table per language.

Adding a language means adding a module here and templates/<lang>/;
nothing else changes.
"""
from __future__ import annotations

from max2code.targets.base import Target
from max2code.targets.c import C
from max2code.targets.m2 import Modula2
from max2code.targets.python import Python
from max2code.targets.rust import Rust

LANGUAGES: dict[str, type[Target]] = {t.name: t for t in (C, Modula2, Python, Rust)}


def target(lang: str) -> Target:
    return LANGUAGES[lang]()
