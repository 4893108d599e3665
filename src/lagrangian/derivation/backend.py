"""SymEngine as the fast backend for the heavy differentiation (docs/architecture.md: SymPy
objects are what users see, SymEngine does the work).

Expressions go in with :func:`to_backend` and come back with a :class:`SympyView`
(:mod:`lagrangian.symbolic.sympy_view`, shared with the model's rolling contacts), which
rebuilds them as SymPy with the user's own symbol objects.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from lagrangian.symbolic.native import to_symengine
from lagrangian.symbolic.sympy_view import (
    Backend,
    SympyView,
    backend_entries,
    cycle_collection_paused,
    unevaluated_trig,
)

__all__ = [
    "Backend",
    "SympyView",
    "backend_entries",
    "cycle_collection_paused",
    "to_backend",
    "unevaluated_trig",
    "vector_to_backend",
]


def to_backend(expr: Any) -> Backend:
    """A SymEngine expression from a SymPy expression or a number, with no function that
    SymEngine would hand back to SymPy (:func:`lagrangian.symbolic.native.to_symengine`)."""
    return to_symengine(expr)


def vector_to_backend(values: Iterable[Any]) -> list[Backend]:
    """Each of ``values`` in SymEngine (:func:`to_backend`)."""
    return [to_symengine(v) for v in values]
