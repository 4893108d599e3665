"""SymEngine as the fast backend for the heavy differentiation (DESIGN.md: SymPy objects
are what users see, SymEngine does the work).

Expressions go in with :func:`to_backend` and come back with a :class:`SympyView`, which
restores the user's own symbol objects by name.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import symengine as se
import sympy as sp

Backend = Any  # a symengine expression


def to_backend(expr: Any) -> Backend:
    """A SymEngine expression from a SymPy expression or a number."""
    return se.sympify(expr)


def vector_to_backend(values: Iterable[Any]) -> list[Backend]:
    return [se.sympify(v) for v in values]


def diff(expr: Backend, symbol: Backend) -> Backend:
    return expr.diff(symbol)


def gradient(expr: Backend, symbols: Sequence[Backend]) -> list[Backend]:
    """[d expr / d s for s in symbols]."""
    return [expr.diff(s) for s in symbols]


def jacobian(vector: Sequence[Backend], symbols: Sequence[Backend]) -> list[list[Backend]]:
    """J[i][j] = d vector_i / d symbols_j."""
    return [[v.diff(s) for s in symbols] for v in vector]


def is_zero(expr: Backend) -> bool:
    return bool(expr == 0)


def depends_on(expr: Backend, symbols: Iterable[Backend]) -> bool:
    free = expr.free_symbols
    return any(s in free for s in symbols)


class SympyView:
    """Converts SymEngine results back to SymPy with the user's symbol objects."""

    def __init__(self, symbols: Iterable[sp.Symbol]) -> None:
        self.by_name = {s.name: s for s in symbols}

    def __call__(self, expr: Backend) -> sp.Expr:
        result = sp.sympify(expr)
        swap = {
            s: self.by_name[s.name]
            for s in result.free_symbols
            if s.name in self.by_name and self.by_name[s.name] is not s
        }
        return result.xreplace(swap) if swap else result

    def vector(self, values: Iterable[Backend]) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix([self(v) for v in values])

    def matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix([[self(v) for v in row] for row in rows])

    def symmetric_matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        """Convert the upper triangle only and mirror it."""
        n = len(rows)
        upper = {(j, k): self(rows[j][k]) for j in range(n) for k in range(j, n)}
        return sp.ImmutableMatrix(n, n, lambda j, k: upper[(min(j, k), max(j, k))])
