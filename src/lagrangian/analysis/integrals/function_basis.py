"""The ansatz of the first-integral search: a finite basis of functions phi_k(t, q) in which
the unknown generators, divergence terms and coefficients of first integrals are sought.

The basis is the products of t, the coordinates and the non-polynomial functions the
Lagrangian itself is built from, up to a total degree (Olver, *Applications of Lie
Groups to Differential Equations*, §5.3, seeks generators the same way): sin and cos of every
coordinate under a trigonometric function, 1/sin of those whose sine can vanish in the metric
(the cot(theta) of a rotation about a horizontal axis in spherical coordinates), every
exponential of the coordinates (exp(q1 - q2) of a Toda lattice), and every radical base to the
powers -1 and 1 (r and 1/r of a Kepler potential written in x, y, z).

Products of these atoms are often linearly dependent (sin(theta) * 1/sin(theta) = 1,
sin**2 + cos**2 = 1): :func:`function_basis` keeps a maximal independent subset, tested by the
rank of their values at random points, so every null vector found later is a real solution.

>>> x, y = sp.symbols("x y")
>>> [str(f) for f in function_basis(sp.cos(x) + y**2, (x, y), degree=1).functions]
['1', 't', 'x', 'y', 'sin(x)', 'cos(x)', '1/sin(x)', 'cot(x)']
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagrangian.symbolic.symbols import t

#: Norm of the part of a (normalized) basis function outside the span of those before it
#: below which it counts as dependent on them.
DEPENDENCE = 1e-8
#: Where variables are sampled: angles away from the zeros of sin, the rest widely.
ANGLE_RANGE = (0.25, 2.9)
RANGE = (-3.0, 3.0)
#: Random points at which the basis is tested for independence (beyond its size).
EXTRA_POINTS = 20


@dataclass(frozen=True)
class FunctionBasis:
    """Independent functions phi_k(t, q) and, for evaluating them on samples, their values
    and first derivatives as NumPy functions of (t, q_1, ..., q_n)."""

    variables: tuple[sp.Symbol, ...]  # (t, q_1, ..., q_n)
    functions: tuple[sp.Expr, ...]
    angles: tuple[sp.Symbol, ...] = ()

    def random_points(self, rows: int, rng: np.random.Generator) -> np.ndarray:
        """Random (t, q) rows spread widely (near-dependence of smooth functions on a small
        box would pass for a relation), angles inside (0, pi) where no sine vanishes."""
        return random_points(self.variables, self.angles, rows, rng)

    def values_and_gradients(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """phi_k at ``points`` (rows of (t, q)), shape (rows, k), and d phi_k / d variable,
        shape (rows, k, 1 + n)."""
        values = _evaluated(self.functions, self.variables, points)
        gradients = np.stack(
            [
                _evaluated(tuple(f.diff(v) for f in self.functions), self.variables, points)
                for v in self.variables
            ],
            axis=-1,
        )
        return values, gradients


def random_points(
    variables: Sequence[sp.Symbol], angles: Sequence[sp.Symbol], rows: int, rng: np.random.Generator
) -> np.ndarray:
    """``rows`` random values of ``variables``: in (0.25, 2.9) for angles, else (-3, 3)."""
    columns = [rng.uniform(*(ANGLE_RANGE if v in angles else RANGE), size=rows) for v in variables]
    return np.column_stack(columns)


def _evaluated(
    functions: Sequence[sp.Expr], variables: Sequence[sp.Symbol], points: np.ndarray
) -> np.ndarray:
    compiled = sp.lambdify(variables, list(functions), modules="numpy")
    columns = compiled(*points.T)
    rows = points.shape[0]
    return np.column_stack([np.broadcast_to(np.asarray(c, dtype=float), (rows,)) for c in columns])


def angles(expr: sp.Expr, coordinates: Sequence[sp.Symbol]) -> list[sp.Symbol]:
    """The coordinates that are angles: those under a trigonometric function of ``expr``, and,
    when there are any, the coordinates ``expr`` does not contain (the azimuth of a sphere)."""
    found = [
        q
        for q in coordinates
        if any(q in f.args[0].free_symbols for f in expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot))
    ]
    if found:
        found += [q for q in coordinates if q not in expr.free_symbols]
    return found


def atoms(expr: sp.Expr, coordinates: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """The non-polynomial building blocks of ``expr``: sin, cos, 1/sin and cot of its angles,
    its exponentials of the coordinates, and its radical bases to the powers 1 and -1 (those
    that are functions of t and the coordinates alone)."""
    found: list[sp.Expr] = []
    # functions of (t, q) alone: the basis is evaluated with no parameters or velocities
    configuration = {t, *coordinates}
    for q in angles(expr, coordinates):
        found += [sp.sin(q), sp.cos(q), 1 / sp.sin(q), sp.cot(q)]
    for growth in expr.atoms(sp.exp):
        if growth.free_symbols and growth.free_symbols <= configuration and growth not in found:
            found.append(growth)  # exp(q1 - q2) of a Toda lattice
    for power in expr.atoms(sp.Pow):
        base, exponent = power.as_base_exp()
        if not base.free_symbols or not base.free_symbols <= configuration:
            continue  # sqrt(1 - x_dot**2) of a relativistic particle, sqrt(R**2 - x**2)
        if exponent.is_Rational and not exponent.is_integer:
            root = base ** sp.Rational(1, exponent.q)
            found += [a for a in (root, 1 / root) if a not in found]
    return found


def function_basis(
    lagrangian: sp.Expr, coordinates: Sequence[sp.Symbol], degree: int = 2
) -> FunctionBasis:
    """Independent products of t, the coordinates and the :func:`atoms` of ``lagrangian``
    (each atom at most once) of total degree <= ``degree``, the simplest first."""
    variables = (t, *coordinates)
    factors = [*variables, *atoms(lagrangian, coordinates)]
    candidates: list[sp.Expr] = []
    for size in range(degree + 1):
        for chosen in itertools.combinations_with_replacement(range(len(factors)), size):
            if any(i >= len(variables) and chosen.count(i) > 1 for i in chosen):
                continue  # an atom once: sin**2 is 1 - cos**2, 1/r**2 is not in L
            candidate = sp.Mul(*(factors[i] for i in chosen))
            if candidate not in candidates:
                candidates.append(candidate)
    turning = tuple(angles(lagrangian, coordinates))
    rng = np.random.default_rng(7)
    points = random_points(variables, turning, 2 * len(candidates) + EXTRA_POINTS, rng)
    return FunctionBasis(variables, tuple(_independent(candidates, variables, points)), turning)


def _independent(
    candidates: list[sp.Expr], variables: tuple[sp.Symbol, ...], points: np.ndarray
) -> list[sp.Expr]:
    """A maximal linearly independent subset of ``candidates`` (over the constants), kept in
    order: Gram–Schmidt (twice, for accuracy) on their values at random points."""
    values = _evaluated(candidates, variables, points)
    return [candidates[j] for j in independent_columns(values)]


def independent_columns(values: np.ndarray) -> list[int]:
    """The columns of ``values`` (functions sampled at points, one column each) that are
    linearly independent of those before them: Gram–Schmidt, twice for accuracy, on the
    columns scaled to unit norm.

    >>> independent_columns(np.array([[1.0, 2.0, 0.0], [1.0, 2.0, 1.0]]))
    [0, 2]
    """
    values = values / np.maximum(np.linalg.norm(values, axis=0), 1e-300)
    kept: list[int] = []
    basis = np.zeros((values.shape[0], 0))
    for j in range(values.shape[1]):
        residual = values[:, j]
        for _ in range(2):
            residual = residual - basis @ (basis.T @ residual)
        if np.linalg.norm(residual) > DEPENDENCE:
            kept.append(j)
            basis = np.column_stack([basis, residual / np.linalg.norm(residual)])
    return kept
