"""solve_linear(matrix, vector): Gaussian elimination with partial pivoting, compiled, in place.

    matrix z = vector   ->   vector <- z           (Golub & Van Loan, Matrix Computations, 3.4)

The systems are small (one row per coordinate, or per coordinate and stage), so a loop without
allocation beats a call into LAPACK.  (Copies of the elimination with the size known to the
compiler, which LLVM unrolls, halve the time of a 6 x 6 solve but add a fifth to the one-time
compile of the marches: not taken.)  Returns False, leaving the arrays changed, when a pivot
is exactly zero.  This module is imported only when numba is
installed.
"""

from __future__ import annotations

from numba import njit


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def solve_linear(matrix, vector) -> bool:
    """Overwrite ``vector`` with matrix^-1 vector; False when the matrix is singular."""
    return eliminate(matrix, vector, vector.size)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def eliminate(matrix, vector, n) -> bool:
    """The elimination of :func:`solve_linear` on the first ``n`` rows (``n`` the size)."""
    for k in range(n):
        pivot, largest = k, abs(matrix[k, k])
        for i in range(k + 1, n):
            if abs(matrix[i, k]) > largest:
                pivot, largest = i, abs(matrix[i, k])
        if largest == 0.0:
            return False
        if pivot != k:
            for j in range(k, n):
                matrix[k, j], matrix[pivot, j] = matrix[pivot, j], matrix[k, j]
            vector[k], vector[pivot] = vector[pivot], vector[k]
        inverse = 1.0 / matrix[k, k]
        matrix[k, k] = inverse  # kept for the back substitution
        for i in range(k + 1, n):
            factor = matrix[i, k] * inverse
            for j in range(k + 1, n):
                matrix[i, j] -= factor * matrix[k, j]
            vector[i] -= factor * vector[k]
    for i in range(n - 1, -1, -1):
        total = vector[i]
        for j in range(i + 1, n):
            total -= matrix[i, j] * vector[j]
        vector[i] = total * matrix[i, i]
    return True
