"""The multiplier form of a constrained system as one C function for the C loop.

With the constraints differentiated to A q_ddot = gamma (:func:`lagrangian.constraints.
constrained_equations`), the accelerations and multipliers solve

    [ M  -A^T ] [ q_ddot ]   [ forcing                        ]
    [ A    0  ] [ lambda ] = [ gamma - 2 alpha c - beta^2 h   ]

(c = A q_dot + b the velocity residuals, h the position residuals of the holonomic rows, 0
for velocity rows; alpha, beta Baumgarte's gains, as :mod:`lagrangian.numerics.constrained`
writes it).  The unknowns z = [q_ddot; lambda] begin with the accelerations, so the C loop
(:mod:`lagrangian.numerics.fast.c_loop`) solves this system at every stage as it solves the
free state equations: matrix and vector from one LLVM-compiled function, Gaussian elimination
with partial pivoting in C, the multipliers solved for and not integrated.  alpha and beta
are the last two parameters, so new gains need no new compilation.

At the output rows the multipliers come from the same function, every row at once (one call
of the compiled function on the rows, a batched solve), and the constraint residual
max(|h|, |A q_dot + b|) from a second compiled function of the residuals
(:func:`constraint_rows`).

>>> import sympy as sp, lagrangian as lg
>>> from lagrangian.constraints import constrained_equations
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)],
...     particles=[lg.Particle("bead", 1, (x, y))])
>>> native = native_constrained(constrained_equations(ring))
>>> native is None or (native.equations.size, native.equations.parameters)
(3, ('baumgarte_alpha', 'baumgarte_beta'))
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.numerics.fast.c_loop import c_function
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.constrained import (
    BAUMGARTE,
    multiplier_system,
    residual_expressions,
)
from lagrangian.numerics.fast.native import NativeFunction
from lagrangian.symbolic.caches import IdentityCache


@dataclass(frozen=True)
class NativeConstrained:
    """The multiplier form compiled for the C loop: ``equations`` (matrix and vector of
    [t, q, q_dot, p, alpha, beta]) and ``residuals`` (h of every row, 0 for velocity rows,
    then A q_dot + b, of the same inputs); ``multipliers`` is the number of rows."""

    equations: FastEquations
    residuals: NativeFunction
    multipliers: int


_CACHE: IdentityCache[ConstrainedEquations, NativeConstrained | None] = IdentityCache()


def native_constrained(equations: ConstrainedEquations) -> NativeConstrained | None:
    """The multiplier form of ``equations`` (module docstring) compiled by SymEngine's LLVM
    backend, built once per ConstrainedEquations object, or None where it cannot compile it;
    its inputs are [t, q, q_dot, the system's parameters, alpha, beta]."""
    return _CACHE.get(equations, _build)


def constraint_rows(
    native: NativeConstrained, t: np.ndarray, x: np.ndarray, p: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The multipliers (rows, m) and the largest constraint residual (rows,) at the states
    x (rows of [q; q_dot]) at times t, the parameters p ending with alpha and beta (one row
    for every state, or a row per state: the members of a batch); NaN multipliers where the
    augmented matrix is singular."""
    rows, m, size = len(t), native.multipliers, native.equations.size
    residual = np.zeros(rows)
    multipliers = np.full((rows, m), np.nan)
    if rows == 0:
        return multipliers, residual
    p = np.asarray(p, dtype=float)
    inputs = np.column_stack((t, x, np.broadcast_to(p, (rows, p.shape[-1]))))
    values = np.asarray(native.equations.function.owner(inputs), dtype=float).reshape(rows, -1)
    matrix = values[:, : size * size].reshape(rows, size, size)
    vector = values[:, size * size :]
    n = size - m
    try:
        multipliers = np.linalg.solve(matrix, vector[..., None])[:, n:, 0]
    except np.linalg.LinAlgError:  # a singular row: solved one by one, NaN where singular
        for i in range(rows):
            with contextlib.suppress(np.linalg.LinAlgError):
                multipliers[i] = np.linalg.solve(matrix[i], vector[i])[n:]
    h_and_c = np.asarray(native.residuals.owner(inputs), dtype=float).reshape(rows, -1)
    residual = np.max(np.abs(h_and_c), axis=1, initial=0.0)
    return multipliers, residual


def _build(equations: ConstrainedEquations) -> NativeConstrained | None:
    q, n = equations.coordinates, len(equations.coordinates)
    alpha, beta = (sp.Symbol(name) for name in BAUMGARTE)
    matrix, vector = multiplier_system(equations, alpha, beta)
    velocities = equations.velocities[:n]
    parameters = [*equations.parameters, alpha, beta]
    symbols = [equations.time, *q, *velocities, *parameters]
    function = c_function(symbols, [*matrix, *vector])
    h, c = residual_expressions(equations)
    residuals = c_function(symbols, [*h, *c])
    if function is None or residuals is None:
        return None
    fast = FastEquations(
        coordinates=tuple(s.name for s in q),
        parameters=tuple(s.name for s in parameters),
        state_names=(*(s.name for s in q), *(s.name for s in velocities)),
        second=tuple(range(n)),
        first=(),
        size=len(vector),
        function=function,
    )
    return NativeConstrained(fast, residuals, len(equations.multipliers))
