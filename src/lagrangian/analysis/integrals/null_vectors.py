"""Exact solutions of a linear system found numerically: the null vectors of a sampled
determining system, with their coefficients recovered as rationals times monomials in the
parameters.

A determining equation sum_k c_k column_k(t, q, q_dot; p) = 0, required identically, is
sampled at random points; the null space of the samples holds every solution.  The basis is
brought to reduced row-echelon form (each vector has a pivot coefficient 1 where the others
vanish), so a vector is one symmetry, not an arbitrary mixture.  Its coefficients depend on
the parameters p; they are found at a generic point p* and again (on the same support) with
each parameter doubled:
c(2 p_j) / c(p*) = 2**e_j gives the exponent of p_j (a textbook coefficient is a monomial: m,
q*B, m*k), and c(p*) / prod p*_j**e_j a small rational.  Whatever does not fit that shape is
dropped; whatever fits is then verified symbolically by the caller.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from fractions import Fraction

import numpy as np
import sympy as sp

#: Singular values below this, relative to the largest, may span the null space: it ends at
#: the widest gap (at least ``GAP``) among them, since near-dependences of smooth functions
#: on the samples reach 1e-9 while exact null vectors sit at rounding level.
NULL = 1e-7
GAP = 1e3
#: Columns whose norm is below this, relative to the largest, are zero (rounding only).
ROUNDING = 1e-11
#: Pivots smaller than this (relative) are numerical noise in the row-echelon form.
PIVOT = 1e-7
#: Tolerance of a coefficient's exponent and of its rational value.
FIT = 1e-6
#: Largest denominator accepted for a rational coefficient.
DENOMINATOR = 1000


def null_basis(matrix: np.ndarray) -> tuple[np.ndarray, tuple[int, ...]]:
    """The null space of ``matrix`` in reduced row-echelon form (rows, pivot 1) and the pivot
    columns; columns are scaled to unit norm first and the scaling undone after."""
    if matrix.shape[1] == 0:
        return np.zeros((0, 0)), ()
    norms = np.linalg.norm(matrix, axis=0)
    norms[norms == 0] = 1.0
    scaled = matrix / norms
    _, singular, vt = np.linalg.svd(scaled, full_matrices=scaled.shape[0] < scaled.shape[1])
    null = vt[_rank(singular, scaled.shape[1]) :] / norms  # back to the unknowns' own scale
    return _row_echelon(null)


def _rank(singular: np.ndarray, unknowns: int) -> int:
    """The numerical rank: the count before the widest gap among the small singular values
    (the unknowns beyond the rows count as zeros)."""
    values = np.concatenate([singular, np.zeros(max(0, unknowns - singular.size))])
    largest = values[0] if values.size else 1.0
    small = np.flatnonzero(values < NULL * largest)
    if small.size == 0:
        return unknowns
    floor = 1e-15 * largest + 1e-300  # rounding level: every exact zero alike
    tail = np.maximum(values[small[0] - 1 :], floor)
    gaps = tail[:-1] / tail[1:]
    widest = int(np.argmax(gaps))
    if gaps[widest] < GAP:
        return unknowns  # no clear null space: nothing is exactly a solution
    return small[0] - 1 + widest + 1


def _row_echelon(rows: np.ndarray) -> tuple[np.ndarray, tuple[int, ...]]:
    rows = rows.copy()
    pivots: list[int] = []
    r = 0
    for column in range(rows.shape[1]):
        if r == len(rows):
            break
        best = r + int(np.argmax(np.abs(rows[r:, column])))
        if abs(rows[best, column]) <= PIVOT * np.max(np.abs(rows[r:])):
            continue  # noise: no pivot in this column
        rows[[r, best]] = rows[[best, r]]
        rows[r] /= rows[r, column]
        for other in range(len(rows)):
            if other != r:
                rows[other] -= rows[other, column] * rows[r]
        pivots.append(column)
        r += 1
    rows = rows[:r]
    rows[np.abs(rows) < PIVOT] = 0.0
    return rows, tuple(pivots)


def _rational(value: float) -> sp.Rational | None:
    fraction = Fraction(value).limit_denominator(DENOMINATOR)
    if abs(float(fraction) - value) > FIT * max(1.0, abs(value)):
        return None
    return sp.Rational(fraction.numerator, fraction.denominator)


def without_rounding(matrix: np.ndarray) -> np.ndarray:
    """``matrix`` with its columns at rounding level (relative to the largest) made exact
    zeros: such a column is a solution on its own (r**2 theta_dot, an angular momentum, is
    one term of a polar ansatz), and scaled to unit norm its noise would pass for data and
    enter the other null vectors with any weight."""
    norms = np.linalg.norm(matrix, axis=0)
    if not norms.size:
        return matrix
    return np.where(norms <= ROUNDING * norms.max(), 0.0, matrix)


def exact_null_vectors(
    sampled: Callable[[dict[sp.Symbol, float]], np.ndarray],
    parameters: Sequence[sp.Symbol],
    generic: dict[sp.Symbol, float],
) -> list[list[sp.Expr]]:
    """The solutions of the sampled system ``sampled(parameter values)`` as exact vectors
    (rationals times monomials in ``parameters``), from its null space at ``generic`` and
    with each parameter doubled; vectors whose coefficients do not fit are left out.
    Samples where the system is not real (sqrt(1 - x_dot**2) at |x_dot| > 1) are left out."""

    def real(values: dict[sp.Symbol, float]) -> np.ndarray:
        with np.errstate(all="ignore"):
            matrix = sampled(values)
        return without_rounding(matrix[np.all(np.isfinite(matrix), axis=1)])

    base, pivots = null_basis(real(generic))
    if not len(base):
        return []
    exponents = np.zeros((len(parameters), *base.shape))
    for j, p in enumerate(parameters):
        moved = _same_support(real({**generic, p: 2 * generic[p]}), base, pivots)
        with np.errstate(divide="ignore", invalid="ignore"):
            exponents[j] = np.log2(np.abs(moved / base))
    polynomial = _PolynomialFit(real, parameters, generic, base, pivots)
    exact = []
    for i, row in enumerate(base):
        vector = _exact_row(row, exponents[:, i, :], parameters, generic)
        vector = vector or polynomial.vector(i)
        if vector is not None:
            exact.append(vector)
    return exact


#: Highest total degree of a coefficient fitted as a polynomial in the parameters.
POLYNOMIAL_DEGREE = 2


class _PolynomialFit:
    """Coefficients that are polynomials in the parameters (g*(m1 - m2) of an Atwood
    machine's time-dependent momentum), fitted by least squares to the null vectors at random
    parameter points; sampled only when a vector's coefficients are not all monomials."""

    def __init__(
        self,
        sampled: Callable[[dict[sp.Symbol, float]], np.ndarray],
        parameters: Sequence[sp.Symbol],
        generic: dict[sp.Symbol, float],
        base: np.ndarray,
        pivots: Sequence[int],
    ) -> None:
        self.sampled, self.parameters, self.generic = sampled, tuple(parameters), generic
        self.base, self.pivots = base, pivots
        self.monomials = [
            sp.Mul(*chosen)
            for d in range(POLYNOMIAL_DEGREE + 1)
            for chosen in itertools.combinations_with_replacement(self.parameters, d)
        ]
        self.values: np.ndarray | None = None
        self.design: np.ndarray | None = None

    def _sample(self) -> tuple[np.ndarray, np.ndarray]:
        rng = np.random.default_rng(29)
        points = [self.generic] + [
            {p: float(rng.uniform(0.7, 1.7)) for p in self.parameters}
            for _ in range(len(self.monomials) + 4)
        ]
        self.values = np.array(
            [_same_support(self.sampled(point), self.base, self.pivots) for point in points]
        )
        compiled = sp.lambdify(self.parameters, self.monomials, modules="numpy")
        self.design = np.array(
            [
                np.broadcast_to(compiled(*(pt[p] for p in self.parameters)), len(self.monomials))
                for pt in points
            ],
            dtype=float,
        )
        return self.values, self.design

    def vector(self, i: int) -> list[sp.Expr] | None:
        """Row ``i`` of the null basis with polynomial coefficients, or None."""
        if not self.parameters:
            return None
        values, design = self._sample() if self.values is None else (self.values, self.design)
        assert design is not None
        vector: list[sp.Expr] = []
        for k in range(self.base.shape[1]):
            column = values[:, i, k]
            if self.base[i, k] == 0.0:
                vector.append(sp.Integer(0))
                continue
            if not np.all(np.isfinite(column)):
                return None
            fitted, *_ = np.linalg.lstsq(design, column, rcond=None)
            numbers = [_rational(float(c)) if abs(c) > PIVOT else sp.Integer(0) for c in fitted]
            if any(n is None for n in numbers):
                return None
            exact = np.array([float(n) for n in numbers])  # type: ignore[arg-type]
            if np.max(np.abs(design @ exact - column)) > FIT * max(1.0, np.abs(column).max()):
                return None
            vector.append(sp.Add(*(n * m for n, m in zip(numbers, self.monomials))))
        return vector


def _same_support(matrix: np.ndarray, base: np.ndarray, pivots: Sequence[int]) -> np.ndarray:
    """The null vectors of ``matrix`` with the support and pivot of each row of ``base``
    (pivot 1): a small least-squares solve per vector instead of a new decomposition.  A row
    that is no null vector of ``matrix`` comes back as NaN (its fit then fails)."""
    moved = np.full_like(base, np.nan)
    for i, (row, pivot) in enumerate(zip(base, pivots)):
        support: list[int] = [int(k) for k in np.flatnonzero(row) if k != pivot]
        vector = np.zeros_like(row)
        vector[pivot] = 1.0
        if support:
            columns = matrix[:, support]
            solution, *_ = np.linalg.lstsq(columns, -matrix[:, pivot], rcond=None)
            vector[support] = solution
        residual = np.linalg.norm(matrix @ vector)
        scale = np.linalg.norm(matrix[:, [pivot, *support]]) * max(1.0, np.abs(vector).max())
        if residual <= NULL * scale:
            moved[i] = vector
    return moved


def _exact_row(
    row: np.ndarray,
    exponents: np.ndarray,
    parameters: Sequence[sp.Symbol],
    generic: dict[sp.Symbol, float],
) -> list[sp.Expr] | None:
    vector: list[sp.Expr] = []
    for k, value in enumerate(row):
        if value == 0.0:
            vector.append(sp.Integer(0))
            continue
        if not np.all(np.isfinite(exponents[:, k])):
            return None
        powers = [round(2 * e) / 2 for e in exponents[:, k]]
        if any(
            not math.isfinite(e) or abs(e - p) > 1e3 * FIT for e, p in zip(exponents[:, k], powers)
        ):
            return None
        scale = math.prod(generic[p] ** e for p, e in zip(parameters, powers))
        number = _rational(value / scale)
        if number is None:
            return None
        monomial = sp.Mul(*(p ** sp.nsimplify(e) for p, e in zip(parameters, powers)))
        vector.append(number * monomial)
    return vector
