"""Which coordinates and speeds a linearization on the constraint manifold keeps, and which it
eliminates (the q_ind / q_dep, u_ind / u_dep split of sympy.physics.mechanics' Linearizer).

The dependent columns of a constraint Jacobian J (r independent rows at the operating point)
must make J[:, dependent] invertible, and well conditioned: they are picked by Gram–Schmidt
with column pivoting, preferring (among the columns within a factor ``PREFERENCE`` of the
best) the ones listed first.  With the coordinates in their given order this eliminates
y for a pendulum hanging at (0, -l) and x_dot, y_dot for a rolling disc.

>>> dependent_columns([[0.0, -2.0]], [0, 1])
(1,)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from lagrangian.symbolic.probe import RANK_TOLERANCE

#: A column counts as good as the best when its residual norm is at least this share of it.
PREFERENCE = 0.5


def _residual(column: list[float], basis: list[list[float]]) -> list[float]:
    """``column`` minus its projection on the orthonormal ``basis``."""
    rest = list(column)
    for e in basis:
        dot = sum(a * b for a, b in zip(rest, e))
        rest = [a - dot * b for a, b in zip(rest, e)]
    return rest


def dependent_columns(
    rows: Sequence[Sequence[float]], preference: Sequence[int], start: Sequence[int] = ()
) -> tuple[int, ...]:
    """Columns of ``rows`` (a numeric Jacobian) spanning its column space, ``start`` first,
    then by column pivoting with ties broken by ``preference`` order (see the module
    docstring).  Sorted."""
    if not rows:
        return ()
    columns = {j: [float(row[j]) for row in rows] for j in preference}
    scale = max((abs(x) for c in columns.values() for x in c), default=0.0) or 1.0
    basis: list[list[float]] = []
    chosen: list[int] = []

    def take(j: int) -> bool:
        rest = _residual(columns[j], basis)
        norm = math.sqrt(sum(x * x for x in rest))
        if norm <= RANK_TOLERANCE * scale * 1e3:
            return False
        basis.append([x / norm for x in rest])
        chosen.append(j)
        return True

    for j in start:
        take(j)
    while len(basis) < len(rows):
        norms = {
            j: math.sqrt(sum(x * x for x in _residual(columns[j], basis)))
            for j in preference
            if j not in chosen
        }
        if not norms or max(norms.values()) <= RANK_TOLERANCE * scale * 1e3:
            break
        best = max(norms.values())
        take(next(j for j in preference if j in norms and norms[j] >= PREFERENCE * best))
    return tuple(sorted(chosen))
