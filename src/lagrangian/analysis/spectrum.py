"""Eigenvalues in SymPy/mpmath, to 30 digits; symmetric problems larger than
:data:`EXTENDED_PRECISION_SIZE` in double precision (LAPACK through SciPy).

    A v = lambda v                 (linearization: frequencies Im lambda > 0, growth Re lambda > 0)
    K v = omega^2 M v              (small oscillations, M symmetric positive definite)

mpmath's symmetric eigensolver takes about 40 s for the modes of a 100 x 100 pencil (n^3
operations in Python); LAPACK takes milliseconds, with the double-precision accuracy of a
backward-stable method (each omega^2 to about n * 1e-16 times the largest), which is also
the precision the results are reported in.

>>> eigenvalues(sp.Matrix([[0, 1], [-4, 0]]))
(-2.0*I, 2.0*I)
"""

from __future__ import annotations

from collections.abc import Iterable

import mpmath
import numpy as np
import sympy as sp

DIGITS = 30
TOLERANCE = 1e-12
#: The largest symmetric problem solved to 30 digits (mpmath); larger ones in double precision.
EXTENDED_PRECISION_SIZE = 24


def _mp_matrix(matrix: sp.MatrixBase) -> mpmath.matrix:
    with mpmath.workdps(DIGITS):
        return mpmath.matrix(
            [[mpmath.mpmathify(complex(e)) for e in matrix.row(i)] for i in range(matrix.rows)]
        )


def _number(z: complex | mpmath.mpc, scale: float) -> sp.Expr:
    """A SymPy number, tiny real or imaginary parts (relative to ``scale``) dropped."""
    re, im = float(mpmath.re(z)), float(mpmath.im(z))
    tiny = TOLERANCE * max(scale, 1.0)
    re = 0.0 if abs(re) < tiny else re
    im = 0.0 if abs(im) < tiny else im
    return sp.Float(re, 15) + sp.I * sp.Float(im, 15) if im else sp.Float(re, 15)


def _sort_key(z: sp.Expr) -> tuple[float, float]:
    re, im = z.as_real_imag()
    return (round(float(re), 9), round(float(im), 9))


def eigenvalues(matrix: sp.MatrixBase) -> tuple[sp.Expr, ...]:
    """Numerical eigenvalues of a matrix of numbers (sorted by real, then imaginary part)."""
    if matrix.rows == 0:
        return ()
    values = mpmath.eig(_mp_matrix(matrix), left=False, right=False)
    scale = max((abs(complex(v)) for v in values), default=1.0)
    return tuple(sorted((_number(v, scale) for v in values), key=_sort_key))


def eigenpairs(matrix: sp.MatrixBase) -> list[tuple[complex, list[complex]]]:
    """Numerical eigenvalues and right eigenvectors of a matrix of numbers, in no order."""
    if matrix.rows == 0:
        return []
    with mpmath.workdps(DIGITS):
        values, vectors = mpmath.eig(_mp_matrix(matrix))
        return [
            (complex(values[i]), [complex(vectors[r, i]) for r in range(vectors.rows)])
            for i in range(len(values))
        ]


def _doubles(matrix: sp.MatrixBase) -> np.ndarray:
    """The real parts of a matrix of numbers, in double precision (a Float read directly:
    ``complex`` of a SymPy number splits it into real and imaginary parts first, a tenth of
    the normal modes of a 100-link chain)."""
    return np.array(
        [
            [float(e) if isinstance(e, sp.Float) else complex(e).real for e in matrix.row(i)]
            for i in range(matrix.rows)
        ]
    )


def symmetric_eigenvalues(matrix: sp.MatrixBase) -> tuple[float, ...]:
    """Eigenvalues of a real symmetric matrix of numbers, ascending."""
    if matrix.rows == 0:
        return ()
    if matrix.rows > EXTENDED_PRECISION_SIZE:
        import scipy.linalg  # only for large matrices: deriving loads no SciPy

        return tuple(float(v) for v in scipy.linalg.eigvalsh(_doubles(matrix)))
    with mpmath.workdps(DIGITS):
        values = mpmath.eigsy(_mp_matrix(matrix).apply(mpmath.re), eigvals_only=True)
    return tuple(sorted(float(v) for v in values))


def generalized_modes(
    stiffness: sp.MatrixBase, mass: sp.MatrixBase
) -> list[tuple[float, sp.ImmutableMatrix]]:
    """(omega^2, v) with K v = omega^2 M v, ascending, via the Cholesky factor M = C C^T:
    C^-1 K C^-T y = omega^2 y, v = C^-T y (each v scaled to largest component +1)."""
    if stiffness.rows > EXTENDED_PRECISION_SIZE:
        return _double_modes(stiffness, mass)
    with mpmath.workdps(DIGITS):
        k = _mp_matrix(stiffness).apply(mpmath.re)
        c = mpmath.cholesky(_mp_matrix(mass).apply(mpmath.re))
        c_inv = mpmath.inverse(c)
        values, vectors = mpmath.eigsy(c_inv * k * c_inv.T)
        shapes = c_inv.T * vectors
        result = []
        for i in range(len(values)):
            column = [float(shapes[r, i]) for r in range(shapes.rows)]
            biggest = max(column, key=abs)
            result.append(
                (float(values[i]), sp.ImmutableMatrix([sp.Float(x / biggest, 15) for x in column]))
            )
    return sorted(result, key=lambda pair: pair[0])


def _double_modes(
    stiffness: sp.MatrixBase, mass: sp.MatrixBase
) -> list[tuple[float, sp.ImmutableMatrix]]:
    """:func:`generalized_modes` in double precision (LAPACK's symmetric-definite solver)."""
    import scipy.linalg  # only for large pencils: deriving loads no SciPy

    values, vectors = scipy.linalg.eigh(_doubles(stiffness), _doubles(mass))
    result = []
    for i, value in enumerate(values):
        column = vectors[:, i]
        biggest = column[np.argmax(np.abs(column))]
        shape = sp.ImmutableMatrix([sp.Float(float(x / biggest), 15) for x in column])
        result.append((float(value), shape))
    return sorted(result, key=lambda pair: pair[0])


def _distinct(values: Iterable[float]) -> tuple[sp.Float, ...]:
    kept: list[float] = []
    for v in sorted(values):
        if not kept or abs(v - kept[-1]) > 1e-9 * max(abs(v), 1.0):
            kept.append(v)
    return tuple(sp.Float(v, 15) for v in kept)


def frequencies(values: Iterable[sp.Expr]) -> tuple[sp.Expr, ...]:
    """The distinct positive imaginary parts (rad/s) of numerical eigenvalues."""
    return _distinct(float(sp.im(v)) for v in values if float(sp.im(v)) > 0)


def growth_rates(values: Iterable[sp.Expr]) -> tuple[sp.Expr, ...]:
    """The distinct positive real parts (1/s) of numerical eigenvalues."""
    return _distinct(float(sp.re(v)) for v in values if float(sp.re(v)) > 0)
