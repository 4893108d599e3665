"""Built-in systems: every worked example of the seed notes, and scalable test systems.

Each example is a function returning a fresh :class:`~lagrangian.model.System`;
:data:`CATALOG` maps every example name to its function, and ``lagrangian.examples.NAME()``
works for each.

>>> import lagrangian as lg
>>> lg.examples.simple_pendulum().coordinates
(theta,)
"""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType
from typing import Any

from lagrangian.errors import ModelError
from lagrangian.examples import bodies, circuits, machines, particles, pendulums
from lagrangian.model import System

_MODULES: tuple[ModuleType, ...] = (pendulums, circuits, machines, particles, bodies)

#: Example name -> function building the System (scalable ones take a size argument).
CATALOG: dict[str, Callable[..., System]] = {
    name: getattr(module, name) for module in _MODULES for name in module.__all__
}


def names() -> list[str]:
    """Every example's name, sorted."""
    return sorted(CATALOG)


def describe(name: str) -> str:
    """The one-line description of an example (the first line of its docstring)."""
    return (get(name).__doc__ or "").strip().splitlines()[0]


def get(name: str) -> Callable[..., System]:
    """The function building example ``name``."""
    try:
        return CATALOG[name]
    except KeyError:
        import difflib

        close = difflib.get_close_matches(name, CATALOG, n=3)
        hint = f" Did you mean {', '.join(close)}?" if close else ""
        raise ModelError(
            f"There is no example named {name!r}.{hint} lagrangian.examples.names() lists them."
        ) from None


def __getattr__(name: str) -> Any:
    if name in CATALOG:
        return CATALOG[name]
    raise AttributeError(f"module 'lagrangian.examples' has no attribute {name!r}")


__all__ = ["CATALOG", "describe", "get", "names", *CATALOG]
