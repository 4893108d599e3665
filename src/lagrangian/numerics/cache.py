"""IdentityCache: remember a pure function's result per object, for as long as the object lives.

EquationsOfMotion and System are frozen dataclasses holding dicts, so they are not hashable and
comparing two of them by value means comparing SymPy trees.  What a cache needs is identity:
the same object gives the same result.  A plain ``lru_cache`` keyed on ``id(obj)`` is wrong
(an id is reused once its object is gone); here every entry holds a weak reference whose
callback drops the entry when its object is collected, before the id can be reused.

>>> cache = IdentityCache()
>>> class Box: ...
>>> box = Box()
>>> cache.get(box, lambda b: 42), len(cache)
(42, 1)
>>> del box
>>> len(cache)
0
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Generic, TypeVar

K = TypeVar("K")
V = TypeVar("V")


class IdentityCache(Generic[K, V]):
    """Results of ``compute(key)`` keyed by the identity of ``key``, dropped with the key.

    The cached values must not refer to their key, or the key would never be collected.
    """

    def __init__(self) -> None:
        self._entries: dict[int, tuple[weakref.ref[K], V]] = {}

    def get(self, key: K, compute: Callable[[K], V]) -> V:
        """The cached value for ``key``, computing and storing it on the first call."""
        ident = id(key)
        entry = self._entries.get(ident)
        if entry is not None and entry[0]() is key:
            return entry[1]
        value = compute(key)
        entries = self._entries

        def forget(ref: weakref.ref[K], ident: int = ident) -> None:
            current = entries.get(ident)
            if current is not None and current[0] is ref:
                del entries[ident]

        entries[ident] = (weakref.ref(key, forget), value)
        return value

    def __len__(self) -> int:
        return len(self._entries)
