"""Every global name a function of the package or the Python runtime reads
is defined in its module (imported, assigned, a def or a class) or is a
builtin: a name lost when code moves between modules fails here, not in
front of a user (`max2code event-vs-frame` once stopped at once with a
NameError).  Python's own symbol tables say which names a scope reads as
globals, so nothing is guessed from the text."""
from __future__ import annotations

import builtins
import symtable
from pathlib import Path

import pytest

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
MODULES = sorted([*(ROOT / "max2code").rglob("*.py"), *(ROOT / "runtimes" / "python" / "max2code_rt").rglob("*.py"),
                  *(ROOT / "bench").glob("*.py"), *(ROOT / "scripts").glob("*.py")])
# names a module has without defining them
MODULE_NAMES = {"__file__", "__name__", "__doc__", "__spec__", "__loader__", "__package__", "__builtins__",
                "__path__", "__annotations__", "__dict__"}


def undefined_globals(path: Path) -> list[str]:
    """`NAME (line of the scope that reads it)` for each global read nowhere defined."""
    text = path.read_text(encoding="utf-8")
    top = symtable.symtable(text, str(path), "exec")
    defined = {s.get_name() for s in top.get_symbols() if s.is_assigned() or s.is_imported()}
    defined |= {c.get_name() for c in top.get_children()}          # defs and classes at the top
    known = defined | set(dir(builtins)) | MODULE_NAMES
    missing = []

    def walk(table):
        for child in table.get_children():
            for sym in child.get_symbols():
                if sym.is_referenced() and (sym.is_global() or sym.is_declared_global()) \
                        and sym.get_name() not in known:
                    missing.append(f"{sym.get_name()} (read in {child.get_name()}, line {child.get_lineno()})")
            walk(child)
    walk(top)
    return missing


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_global_a_function_reads_is_defined(path):
    assert undefined_globals(path) == []


def test_a_lost_import_is_found(tmp_path):
    lost = tmp_path / "lost.py"
    lost.write_text("from os import path\n\ndef f():\n    return _helper(path)\n\nclass C:\n    def g(self):\n"
                    "        return len(sep)\n", encoding="utf-8")
    assert undefined_globals(lost) == ["_helper (read in f, line 3)", "sep (read in g, line 7)"]
