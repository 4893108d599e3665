"""Caches keyed by the identity of an immutable value: the same object gives the same result.

Systems and equations of motion are frozen dataclasses of SymPy trees: comparing two by value
means comparing trees, and hashing them is not always possible.  What a cache of a pure
function needs is identity.  A plain ``lru_cache`` keyed on ``id(obj)`` is wrong (an id is
reused once its object is gone), so:

- :class:`IdentityCache` keeps a result for as long as its key lives: every entry holds a weak
  reference whose callback drops the entry when the key is collected, before the id can be
  reused.  The result must not refer to its key, or the key would never be collected.
- :class:`RecentCache` keeps the results of the last ``size`` keys, holding each key strongly
  (so its id cannot be reused while the entry exists).  The result may refer to its key; the
  price is that the last ``size`` keys and results stay alive until they are pushed out.
- :func:`remembered` is ``functools.lru_cache`` for functions of hashable values (a rotation's
  axes and angles, a constraint's text).

Every cache of the package is one of these, and each registers itself on creation:
:func:`forget_all` empties all of them at once (a long-lived process — the playground's
workers, a notebook — lets go of every model it has seen; a test starts from nothing).

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

import functools
import threading
import weakref
from collections import OrderedDict
from collections.abc import Callable
from typing import Any, Generic, Protocol, TypeVar

from lagrangian.limits import swallows_exceptions

K = TypeVar("K")
V = TypeVar("V")
F = TypeVar("F", bound=Callable[..., Any])


class _Clearable(Protocol):
    def clear(self) -> None: ...


class _FunctionCache:
    """The registry's handle on one ``lru_cache``d function."""

    def __init__(self, function: Any) -> None:
        self.function = function

    def clear(self) -> None:
        self.function.cache_clear()


#: Every cache of the package (weakly: a cache made by a test and dropped leaves the registry).
_REGISTRY: weakref.WeakSet[Any] = weakref.WeakSet()
#: The handles of the remembered functions (module-level functions live as long as the process).
_FUNCTIONS: list[_FunctionCache] = []


def forget_all() -> int:
    """Empty every cache of the package: the derivations, compiled functions, constraint forms,
    rotations and parsed texts it remembers.  Returns how many caches were emptied.

    >>> forget_all() >= 1
    True
    """
    caches: list[_Clearable] = [*_REGISTRY, *_FUNCTIONS]
    for cache in caches:
        cache.clear()
    return len(caches)


def remembered(maxsize: int) -> Callable[[F], F]:
    """``functools.lru_cache(maxsize)``, registered so that :func:`forget_all` empties it.

    >>> @remembered(maxsize=2)
    ... def square(x: int) -> int:
    ...     return x * x
    >>> square(3), square.cache_info().currsize
    (9, 1)
    """

    def decorate(function: F) -> F:
        cached = functools.lru_cache(maxsize=maxsize)(function)
        _FUNCTIONS.append(_FunctionCache(cached))
        return cached  # type: ignore[return-value]

    return decorate


class IdentityCache(Generic[K, V]):
    """Results of ``compute(key)`` keyed by the identity of ``key``, dropped with the key.

    The cached values must not refer to their key, or the key would never be collected.
    """

    def __init__(self) -> None:
        self._entries: dict[int, tuple[weakref.ref[K], V]] = {}
        _REGISTRY.add(self)

    def get(self, key: K, compute: Callable[[K], V]) -> V:
        """The cached value for ``key``, computing and storing it on the first call."""
        ident = id(key)
        entry = self._entries.get(ident)
        if entry is not None and entry[0]() is key:
            return entry[1]
        value = compute(key)
        entries = self._entries

        @swallows_exceptions  # a weak reference's callback
        def forget(ref: weakref.ref[K], ident: int = ident) -> None:
            current = entries.get(ident)
            if current is not None and current[0] is ref:
                del entries[ident]

        entries[ident] = (weakref.ref(key, forget), value)
        return value

    def clear(self) -> None:
        """Forget every entry."""
        self._entries.clear()

    def peek(self, key: K) -> V | None:
        """The cached value for ``key``, or None when there is none (nothing is computed)."""
        entry = self._entries.get(id(key))
        return entry[1] if entry is not None and entry[0]() is key else None

    def __len__(self) -> int:
        return len(self._entries)


class RecentCache(Generic[K, V]):
    """Results of ``compute(key)`` for the ``size`` keys used last, keyed by identity.

    Each entry holds its key strongly, so a value may refer to its key (an EquationsOfMotion
    refers to its System); the least recently used entry is dropped when a new one would
    exceed ``size``.

    >>> cache = RecentCache(2)
    >>> a, b, c = [1], [2], [3]
    >>> [cache.get(key, len) for key in (a, b, a, c)], len(cache)
    ([1, 1, 1, 1], 2)
    >>> cache.clear(); len(cache)
    0
    """

    def __init__(self, size: int) -> None:
        self.size = size
        self._entries: OrderedDict[int, tuple[K, V]] = OrderedDict()
        self._lock = threading.Lock()
        _REGISTRY.add(self)

    def get(self, key: K, compute: Callable[[K], V]) -> V:
        """The cached value for ``key``, computing and storing it on the first call."""
        ident = id(key)
        with self._lock:
            entry = self._entries.get(ident)
            if entry is not None and entry[0] is key:
                self._entries.move_to_end(ident)
                return entry[1]
        value = compute(key)  # outside the lock: it may use this cache itself
        with self._lock:
            self._entries[ident] = (key, value)
            self._entries.move_to_end(ident)
            while len(self._entries) > self.size:
                self._entries.popitem(last=False)
        return value

    def clear(self) -> None:
        """Forget every entry (and let the keys and values go)."""
        with self._lock:
            self._entries.clear()

    def __len__(self) -> int:
        return len(self._entries)
