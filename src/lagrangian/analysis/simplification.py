"""Simplification of small results: the one place the analysis calls ``sympy.simplify``
on what it reports.

``sympy.simplify`` pays off on a short expression (a stiffness entry, a frequency, a term of
the energy) and can take minutes on a long one, so a result is simplified only when it has at
most ``limit`` operations (:func:`lagrangian.symbolic.probe.is_small`); larger ones are returned
as they are.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> simplify_small(sp.sin(x)**2 + sp.cos(x)**2)
1
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import SMALL, is_small

#: A stricter limit for results that are many and rarely simplify much (rates, A and B).
QUICK = 30
#: Entries up to which a matrix is simplified entry by entry (10 x 10); a larger one (the
#: stiffness of a chain of twenty links, 400 entries) is returned as it is, so that the time
#: spent simplifying stays bounded as the system grows.
SIMPLIFIED_ENTRIES = 100


def simplify_small(expr: Any, limit: int = SMALL) -> sp.Expr:
    """``sympy.simplify(expr)`` when ``expr`` has at most ``limit`` operations, else ``expr``."""
    expr = to_sympy(expr)
    return sp.simplify(expr) if is_small(expr, limit) else expr


def simplify_small_matrix(matrix: sp.MatrixBase, limit: int = SMALL) -> sp.ImmutableMatrix:
    """Every entry through :func:`simplify_small`, as an immutable matrix (as it is when it
    has more than :data:`SIMPLIFIED_ENTRIES` entries)."""
    if matrix.rows * matrix.cols > SIMPLIFIED_ENTRIES:
        return sp.ImmutableMatrix(matrix)
    entries = [simplify_small(e, limit) for e in matrix]
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, entries)
