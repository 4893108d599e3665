"""SymEngine as the fast backend for the heavy differentiation (docs/architecture.md: SymPy
objects are what users see, SymEngine does the work).

Expressions go in with :func:`to_backend` and come back with a :class:`SympyView`
(:mod:`lagrangian.symbolic.sympy_view`, shared with the model's rolling contacts), which
rebuilds them as SymPy with the user's own symbol objects.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import symengine as se
import sympy as sp

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


def vector_to_backend(
    values: Iterable[Any], terms: dict[Any, Backend] | None = None
) -> list[Backend]:
    """Each of ``values`` in SymEngine (:func:`to_backend`).  With ``terms``, the terms of a
    SymPy sum are converted once across calls and remembered there, the sum made of them: the
    positions of a chain repeat the terms of the points above them (link k's in every point
    below it), n^2/2 terms for n points, of which n differ."""
    if terms is None:
        return [to_symengine(v) for v in values]
    return [_sum_to_backend(v, terms) if isinstance(v, sp.Add) else to_symengine(v) for v in values]


def _sum_to_backend(expr: sp.Add, terms: dict[Any, Backend]) -> Backend:
    converted = []
    for term in expr.args:
        known = terms.get(term)
        if known is None:
            known = terms[term] = to_symengine(term)
        converted.append(known)
    return se.Add(*converted)
