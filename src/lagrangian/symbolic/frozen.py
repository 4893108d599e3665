"""FrozenMapping: a read-only mapping, so that values holding one (a System's parameters, the
parameters of its equations of motion) really are values.

``types.MappingProxyType`` is read-only too, but it cannot be pickled (a System could not be
sent to another process of a sweep) and it is a view of a dict someone else may still hold.
A FrozenMapping owns a private copy, compares equal to any mapping with the same items, and
hashes when its values do.

>>> import sympy as sp
>>> m = sp.Symbol("m")
>>> parameters = FrozenMapping({m: 1.0})
>>> parameters[m], parameters == {m: 1.0}
(1.0, True)
>>> parameters[m] = 2.0
Traceback (most recent call last):
...
TypeError: 'FrozenMapping' object does not support item assignment
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator, Mapping
from typing import Any, TypeVar

K = TypeVar("K")
V = TypeVar("V")
T = TypeVar("T")


class FrozenMapping(Mapping[K, V]):
    """An immutable mapping with the items of ``items`` (a mapping or key-value pairs)."""

    __slots__ = ("_items",)

    def __init__(self, items: Mapping[K, V] | Iterable[tuple[K, V]] = ()) -> None:
        self._items: dict[K, V] = dict(items)

    def __getitem__(self, key: K) -> V:
        return self._items[key]

    def __iter__(self) -> Iterator[K]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __contains__(self, key: object) -> bool:
        return key in self._items

    def __eq__(self, other: object) -> bool:
        if isinstance(other, FrozenMapping):
            return self._items == other._items
        if isinstance(other, Mapping):
            return self._items == dict(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(frozenset(self._items.items()))

    def __repr__(self) -> str:
        return f"FrozenMapping({self._items!r})"

    def __reduce__(self) -> tuple[Any, ...]:
        return (FrozenMapping, (self._items,))


def frozen(mapping: Mapping[K, V] | Iterable[tuple[K, V]]) -> FrozenMapping[K, V]:
    """``mapping`` as a FrozenMapping (itself when it already is one)."""
    return mapping if isinstance(mapping, FrozenMapping) else FrozenMapping(mapping)


def rebuilt(kind: type[T], fields: Mapping[str, Any]) -> T:
    """``kind(**fields)``: a frozen dataclass made again from its fields (unpickling)."""
    return kind(**fields)


def reduce_to_fields(value: Any) -> tuple[Any, ...]:
    """``__reduce__`` of a frozen dataclass that checks and freezes its fields when made:
    pickled as its init fields and made again through its constructor, so that an
    unpickled value is as read-only as the original (NumPy unpickles arrays writeable)."""
    names = [f.name for f in dataclasses.fields(value) if f.init]
    return (rebuilt, (type(value), {name: getattr(value, name) for name in names}))
