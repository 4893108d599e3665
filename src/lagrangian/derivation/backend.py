"""SymEngine as the fast backend for the heavy differentiation (docs/architecture.md: SymPy
objects are what users see, SymEngine does the work).

Expressions go in with :func:`to_backend` and come back with a :class:`SympyView`, which
rebuilds them as SymPy with the user's own symbol objects.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.model.conversion import to_sympy
from lagrangian.model.identity_cache import IdentityCache
from lagrangian.model.nonsmooth import piecewise_smooth

Backend = Any  # a symengine expression


def to_backend(expr: Any) -> Backend:
    """A SymEngine expression from a SymPy expression or a number."""
    return se.sympify(expr)


def vector_to_backend(values: Iterable[Any]) -> list[Backend]:
    return [se.sympify(v) for v in values]


_TRIG: dict[type, Callable[..., sp.Expr]] = {se.sin: sp.sin, se.cos: sp.cos}


class SympyView:
    """Converts SymEngine results back to SymPy, with the user's symbol objects.

    Sines and cosines of a difference of two symbols, which pendulum-like systems have by
    the hundred, are built directly in SymPy's canonical form (the first symbol in SymPy's
    order positive) instead of through SymPy's general evaluation; everything else goes
    through SymPy's own constructors.
    """

    def __init__(self, symbols: Iterable[sp.Symbol]) -> None:
        self.by_name = {s.name: s for s in symbols}
        self._memo: dict[Backend, sp.Expr] = {}

    def __call__(self, expr: Backend) -> sp.Expr:
        memo = self._memo
        if expr in memo:
            return memo[expr]
        if isinstance(expr, se.Symbol):
            result = self.by_name.get(expr.name) or sp.Symbol(expr.name)
        elif expr.is_Add:
            result = sp.Add(*[self(a) for a in expr.args])
        elif expr.is_Mul:
            result = sp.Mul(*[self(a) for a in expr.args])
        elif expr.is_Pow:
            base, exponent = expr.args
            result = sp.Pow(self(base), self(exponent))
        elif type(expr) in _TRIG:
            result = self._trig(_TRIG[type(expr)], self(expr.args[0]))
        elif expr.is_Number:
            result = to_sympy(expr)
        else:
            result = self._fallback(expr)
        memo[expr] = result
        return result

    def _fallback(self, expr: Backend) -> sp.Expr:
        # SymEngine knows only SymPy's complex Abs, sign and Heaviside
        result = piecewise_smooth(to_sympy(expr))
        swap = {
            s: self.by_name[s.name]
            for s in result.free_symbols
            if s.name in self.by_name and self.by_name[s.name] is not s
        }
        return result.xreplace(swap) if swap else result

    @staticmethod
    def _trig(function: Callable[..., sp.Expr], argument: sp.Expr) -> sp.Expr:
        difference = _symbol_difference(argument)
        if difference is None:
            return function(argument)
        first, second, flipped = difference
        canonical = sp.Add(first, -second)
        value = function(canonical, evaluate=False)
        return -value if flipped and function is sp.sin else value

    def vector(self, values: Iterable[Backend]) -> sp.ImmutableMatrix:
        entries = list(values)
        return _remember(sp.ImmutableMatrix([self(v) for v in entries]), entries)

    def matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        converted = sp.ImmutableMatrix([[self(v) for v in row] for row in rows])
        return _remember(converted, [v for row in rows for v in row])

    def symmetric_matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        """Convert the upper triangle only and mirror it."""
        n = len(rows)
        upper = {(j, k): self(rows[j][k]) for j in range(n) for k in range(j, n)}
        converted = sp.ImmutableMatrix(n, n, lambda j, k: upper[(min(j, k), max(j, k))])
        entries = [rows[min(j, k)][max(j, k)] for j in range(n) for k in range(n)]
        return _remember(converted, entries)


#: The backend entries each matrix a SympyView converted came from, row by row: numeric code
#: compiles those directly instead of converting the SymPy matrix back (a tenth of the
#: compile time of a 10-link pendulum's equations).
_SOURCES: IdentityCache[sp.ImmutableMatrix, tuple[Backend, ...]] = IdentityCache()


def _remember(converted: sp.ImmutableMatrix, entries: Sequence[Backend]) -> sp.ImmutableMatrix:
    _SOURCES.get(converted, lambda _: tuple(entries))
    return converted


def backend_entries(matrix: Any) -> tuple[Backend, ...] | None:
    """The SymEngine entries (row by row) that ``matrix`` was converted from by a
    :class:`SympyView`, or None for a matrix built any other way."""
    return _SOURCES.peek(matrix) if isinstance(matrix, sp.ImmutableMatrix) else None


def _symbol_difference(argument: sp.Expr) -> tuple[sp.Symbol, sp.Symbol, bool] | None:
    """For a +- (x - y) with x, y symbols: (first, second, flipped) with first before second
    in SymPy's order, ``flipped`` when the argument is second - first; else None."""
    if not (argument.is_Add and len(argument.args) == 2):
        return None
    a, b = argument.args
    positive = [term for term in (a, b) if term.is_Symbol]
    negative = [
        -term
        for term in (a, b)
        if term.is_Mul and term.args[0] == -1 and len(term.args) == 2 and term.args[1].is_Symbol
    ]
    if len(positive) != 1 or len(negative) != 1:
        return None
    x, y = positive[0], negative[0]
    first, second = sorted((x, y), key=sp.default_sort_key)
    return first, second, x is not first
