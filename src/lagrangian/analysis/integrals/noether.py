"""Affine point symmetries of L and their Noether charges (Noether's theorem, point form).

A point transformation q -> q + eps xi(q) leaves L invariant when

    delta L = sum_j (dL/dq_j xi_j + dL/dq_dot_j xi_dot_j) = 0   identically,

and then Q = sum_j p_j xi_j (p_j = dL/dq_dot_j) is a constant of the motion.  We look for
affine generators xi = A q + b (so xi_dot = A q_dot): delta L is linear in the n*n + n unknown
constants of A and b, so sampling it at random states gives a linear system whose nullspace
(found numerically at 30 digits, rounded to small rationals and then verified symbolically)
holds every such symmetry.

Only systems without applied (Q_j) and dissipative (-dF/dq_dot_j) forces are analysed: with
them, invariance of L alone does not give a conserved quantity, so the answer is ``()``.
Generators whose constants depend on symbolic parameters (xi_1 = m2 x2 / m1, ...) are not
found unless those parameters are given numbers in ``parameters``.

>>> import lagrangian as lg
>>> [s.conserved for s in point_symmetries(lg.examples.planet())]
[m*r**2*theta_dot]
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import mpmath
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.steps import step_momenta
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import derivative
from lagrangian.symbolic.probe import is_zero

DIGITS = 30
RELATIVE_ZERO = mpmath.mpf("1e-20")  # singular values below this (relative) span the nullspace
ROUNDING = 1e-12  # tolerance of sympy.nsimplify when rounding the basis to rationals
#: The most unknown constants (n^2 + n for n coordinates) the search solves for by default:
#: five coordinates.  Its 30-digit factorization takes time growing as their cube (seconds at
#: five coordinates, a minute at eight), so larger systems are refused with the reason.
MAX_UNKNOWNS = 30


@dataclass(frozen=True)
class Symmetry:
    """A point symmetry q -> q + eps xi(q) of L and its conserved charge sum_j p_j xi_j."""

    generator: sp.ImmutableMatrix
    conserved: sp.Expr
    description: str


def _variation_columns(lagrangian: sp.Expr, eom: EquationsOfMotion) -> list[sp.Expr]:
    """d(delta L)/d(unknown) for the unknowns A_jk (row-major), then b_j:
    dL/dq_j q_k + dL/dq_dot_j q_dot_k, and dL/dq_j."""
    q, v = eom.coordinates, eom.velocities
    dq = [derivative(lagrangian, s) for s in q]  # d|u| = sign(u) du, as by hand
    dv = [derivative(lagrangian, s) for s in v]
    columns = [dq[j] * q[k] + dv[j] * v[k] for j in range(len(q)) for k in range(len(q))]
    return columns + dq


def _sample_matrix(columns: list[sp.Expr], symbols: list[sp.Symbol], rows: int) -> mpmath.matrix:
    """``columns`` at ``rows`` random rational points (skipping points where L is singular)."""
    rng = random.Random(20240607)
    function = sp.lambdify(symbols, columns, modules="mpmath")
    sampled: list[list[mpmath.mpf]] = []
    with mpmath.workdps(DIGITS):
        for _ in range(20 * rows):
            if len(sampled) == rows:
                break
            point = [sp.Rational(rng.randint(1, 10**6), 10**6) + sp.Rational(1, 2) for _ in symbols]
            try:
                values = [mpmath.mpmathify(x) for x in function(*[mpmath.mpf(p) for p in point])]
            except (ValueError, ZeroDivisionError, TypeError):
                continue
            if all(mpmath.isfinite(x) and mpmath.im(x) == 0 for x in values):
                sampled.append([mpmath.re(x) for x in values])
    return mpmath.matrix(sampled)


def _nullspace(matrix: mpmath.matrix, unknowns: int) -> list[list[mpmath.mpf]]:
    """A basis of the nullspace in reduced row echelon form (canonical, so rational when the
    nullspace is rational), from the SVD at 30 digits."""
    with mpmath.workdps(DIGITS):
        if matrix.rows > matrix.cols:  # A = Q R: same singular values and V, R is square
            matrix = mpmath.qr(matrix, mode="skinny")[1]
        _, s, vt = mpmath.svd_r(matrix, full_matrices=True, compute_uv=True)
        largest = max((abs(x) for x in s), default=mpmath.mpf(0))
        rank = sum(1 for x in s if largest > 0 and abs(x) > RELATIVE_ZERO * largest)
        basis = [[vt[i, k] for k in range(unknowns)] for i in range(rank, unknowns)]
        return _row_echelon(basis, unknowns)


def _row_echelon(rows: list[list[mpmath.mpf]], width: int) -> list[list[mpmath.mpf]]:
    """Gauss-Jordan elimination with partial pivoting; pivots scaled to 1."""
    rows = [list(r) for r in rows]
    pivot_row = 0
    for column in range(width):
        if pivot_row == len(rows):
            break
        best = max(range(pivot_row, len(rows)), key=lambda i: abs(rows[i][column]))
        if abs(rows[best][column]) < mpmath.mpf(10) ** (-DIGITS // 2):
            continue
        rows[pivot_row], rows[best] = rows[best], rows[pivot_row]
        pivot = rows[pivot_row][column]
        rows[pivot_row] = [x / pivot for x in rows[pivot_row]]
        for i in range(len(rows)):
            if i != pivot_row:
                factor = rows[i][column]
                rows[i] = [a - factor * b for a, b in zip(rows[i], rows[pivot_row])]
        pivot_row += 1
    return rows[:pivot_row]


def _rounded(vector: list[mpmath.mpf]) -> list[sp.Expr]:
    return [
        sp.nsimplify(sp.Float(mpmath.nstr(x, DIGITS), DIGITS), tolerance=ROUNDING, rational=True)
        for x in vector
    ]


def _vanishes(expr: sp.Expr) -> bool:
    """delta L == 0 symbolically (expand, then simplify, then trigsimp)."""
    expr = sp.expand(expr)
    if expr == 0:
        return True
    simplified = sp.simplify(expr)
    return bool(simplified == 0 or sp.trigsimp(simplified) == 0)


def _describe(a: sp.Matrix, b: sp.Matrix, q: tuple[sp.Symbol, ...], xi: sp.Matrix) -> str:
    nonzero_b = [j for j in range(len(q)) if b[j] != 0]
    if a.is_zero_matrix and len(nonzero_b) == 1:
        return f"translation along {q[nonzero_b[0]].name}"
    pairs = [(i, j) for i in range(len(q)) for j in range(i + 1, len(q)) if a[i, j] != 0]
    if b.is_zero_matrix and (a + a.T).is_zero_matrix and len(pairs) == 1:
        i, j = pairs[0]
        return f"rotation in the ({q[i].name}, {q[j].name}) plane"
    return "point symmetry xi = (" + ", ".join(str(e) for e in xi) + ")"


def _oriented(a: sp.Matrix, b: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """Rotations turned counter-clockwise (xi_i = -q_j, xi_j = q_i for i < j), so that the
    charge is the usual q_i p_j - q_j p_i."""
    n = a.rows
    first = next(((i, j) for i in range(n) for j in range(i + 1, n) if a[i, j] != 0), None)
    if b.is_zero_matrix and first is not None and a[first] > 0:
        return -a, -b
    return a, b


def _refuse_large_search(n: int, most: int) -> None:
    unknowns = n * n + n
    if unknowns <= most:
        return
    raise AnalysisError(
        f"the search for affine point symmetries xi = A q + b of {n} coordinates solves for "
        f"{unknowns} unknown constants (n^2 + n), more than the {most} searched by default: "
        "its 30-digit factorization takes time growing as their cube (about a minute at 72). "
        "Cyclic coordinates and the energy are still analyzed; to search anyway, call "
        f"lagrangian.analysis.point_symmetries(system, max_unknowns={unknowns})"
    )


def point_symmetries(
    subject: Subject, parameters: Values | None = None, max_unknowns: int = MAX_UNKNOWNS
) -> tuple[Symmetry, ...]:
    """Affine point symmetries xi = A q + b of L and their conserved Q = sum_j p_j xi_j.

    delta L = sum_j (dL/dq_j xi_j + dL/dq_dot_j (A q_dot)_j) = 0 for every q, q_dot, t.
    Returns ``()`` when an applied or dissipative force acts (see the module docstring).

    Parameters
    ----------
    subject:
        A System or its EquationsOfMotion.
    parameters:
        Substitutions for parameters (by name or symbol) made before the search.
    max_unknowns:
        The most unknown constants (n^2 + n) to solve for; a larger search is refused
        (AnalysisError) before it starts.

    >>> import lagrangian as lg
    >>> point_symmetries(lg.examples.planet())[0].description
    'translation along theta'
    """
    eom = equations_of(subject)
    if not all(is_zero(f) for f in (*eom.generalized_forces, *eom.dissipation_forces)):
        return ()
    values = substitutions(eom, parameters)
    lagrangian = to_sympy(substitute(eom.lagrangian, values))
    q, n = eom.coordinates, len(eom.coordinates)
    if n == 0:
        return ()
    _refuse_large_search(n, max_unknowns)
    columns = _variation_columns(lagrangian, eom)
    symbols = sorted(set().union(*(c.free_symbols for c in columns)), key=lambda s: s.name)
    unknowns = n * n + n
    matrix = _sample_matrix(columns, symbols, 3 * unknowns + 5)
    found = []
    for vector in _nullspace(matrix, unknowns):
        coefficients = _rounded(vector)
        a = sp.Matrix(n, n, coefficients[: n * n])
        b = sp.Matrix(coefficients[n * n :])
        a, b = _oriented(a, b)
        flat = list(a) + list(b)
        if not _vanishes(sum((c * e for c, e in zip(flat, columns)), sp.Integer(0))):
            continue
        xi = a * sp.Matrix(q) + b
        momenta = [substitute(m, values) for m in step_momenta(eom.system)]
        charge = sp.simplify(sum((p * x for p, x in zip(momenta, xi)), sp.Integer(0)))
        found.append(Symmetry(sp.ImmutableMatrix(xi), charge, _describe(a, b, q, xi)))
    return tuple(found)
