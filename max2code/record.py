"""Plain records: a class that lists its fields in `_fields` and sets them in
its own __init__ gets a repr and an equality by those fields (and, frozen,
a hash and no assignment after __init__).

What dataclasses would give, without importing them: `dataclasses` imports
`inspect`, which is some 29 million instructions of a `max2code simulate`
process of 250 million on a small scene (a tenth of its start)."""
from __future__ import annotations


class Record:
    """Fields in `_fields` (in order): repr and == as a dataclass's; unhashable, as a dataclass with eq."""
    _fields: tuple[str, ...] = ()

    def _values(self) -> tuple:
        return tuple(getattr(self, f) for f in self._fields)

    def __repr__(self) -> str:
        shown = getattr(self, "_repr_fields", self._fields)
        return f"{type(self).__qualname__}({', '.join(f'{f}={getattr(self, f)!r}' for f in shown)})"

    def __eq__(self, other):
        if other.__class__ is self.__class__:
            return self._values() == other._values()
        return NotImplemented

    __hash__ = None     # type: ignore[assignment]


class FrozenRecord(Record):
    """A Record whose fields are set once, in __init__ (through _set), and which hashes by them."""

    def _set(self, **values) -> None:
        for k, v in values.items():
            object.__setattr__(self, k, v)

    def __setattr__(self, name, value):
        raise AttributeError(f"cannot assign to field '{name}' of a frozen {type(self).__name__}")

    def __delattr__(self, name):
        raise AttributeError(f"cannot delete field '{name}' of a frozen {type(self).__name__}")

    def __hash__(self) -> int:
        return hash(self._values())
