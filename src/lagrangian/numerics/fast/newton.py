"""What the compiled variational integrators share: the system's C functions bound to their
buffers, the sizes and tests of a Newton iteration, and the velocity equations that end
every step.

A system reaches the loops as the three C functions of
:mod:`lagrangian.numerics.fast.discrete` (midpoint terms, Legendre map, constraints) and their
``user_data`` pointers; :func:`bind` gives them their input and output buffers, with the
parameters written once, and :func:`evaluate_midpoint`, :func:`evaluate_legendre`,
:func:`evaluate_constraints` call them.

:func:`velocity_step` solves the velocity equations of a step's end,

    dL/dq_dot(q1, v1, t1) = momentum + weight A1^T mu,     A1 v1 + dh/dt(q1, t1) = 0,

for (v1, mu) by Newton's method (one solve when the Legendre map is affine in v), as
:func:`lagrangian.simulation.variational.step.velocity_step` does in NumPy, with the same
tolerances (:mod:`lagrangian.numerics.discrete_lagrangian`).  Every function returns a status
(:data:`OK` or the failure) instead of raising.

The pieces of a step, here and in the marches, are inlined into the march that calls them
(numba's ``inline="always"``): called as functions they took arrays and tuples of arrays by
value, hundreds of words pushed per call, most of a step of a small system; inlined, LLVM
optimizes the step whole (a double pendulum's midpoint step five times faster, at about twice
the one-time compile of the march).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import carray, njit, types
from numba.core.extending import intrinsic

from lagrangian.numerics.discrete_lagrangian import (
    MAX_ITERATIONS,
    RESIDUAL_GUARD,
    SMALL_CORRECTION,
)
from lagrangian.numerics.fast.linear import solve_linear

#: Statuses of a step, and of a chunk of steps (RUNNING: done, the end not reached yet).
OK = RUNNING = 0
FINISHED = 1
POSITION_DIVERGED = 2
POSITION_SINGULAR = 3
VELOCITY_DIVERGED = 4
VELOCITY_SINGULAR = 5


@intrinsic
def _data_pointer(typingctx, array):
    """The pointer to the first element of ``array``."""
    signature = types.CPointer(array.dtype)(array)

    def codegen(context, builder, signature, arguments):
        return context.make_array(array)(context, builder, arguments[0]).data

    return signature, codegen


@njit(cache=False, nogil=True, error_model="numpy")
def unowned(array):
    """A view of the C-contiguous ``array`` that holds no reference to its memory.

    numba counts the references of every array it passes to a function that it does not
    inline, by an atomic operation: a few per argument per call, most of the time of a step
    of a small system.  A view without an owner skips them; whoever made ``array`` keeps it
    alive while the view is used (:func:`hold`)."""
    return carray(_data_pointer(array), array.shape)  # type: ignore[call-arg]


@njit(cache=False, nogil=True, error_model="numpy")
def hold(owners) -> None:
    """Nothing: a use of ``owners`` after the loop that works on their :func:`unowned`
    views, so that numba frees them only then."""
    return None


@njit(cache=False, nogil=True, error_model="numpy")
def unowned_system(system):
    """``system`` of :func:`bind` with :func:`unowned` buffers (hold ``system`` meanwhile)."""
    midpoint, legendre, constraints = system
    return (
        (midpoint[0], midpoint[1], unowned(midpoint[2]), unowned(midpoint[3])),
        (legendre[0], legendre[1], unowned(legendre[2]), unowned(legendre[3])),
        (constraints[0], constraints[1], unowned(constraints[2]), unowned(constraints[3])),
    )


@njit(cache=False, nogil=True, error_model="numpy")
def bind(functions, data, p, n, m):
    """(f, user_data, in, out) of the midpoint terms, the Legendre map and the constraints
    (``data`` their user_data) of n coordinates and m constraints, with ``in`` holding the
    parameters p already (after [q, v, t] or [q, t])."""
    midpoint, legendre, constraints = functions
    m_in, m_out = np.empty(2 * n + 1 + p.size), np.empty(3 * n + 5 * n * n)
    l_in, l_out = np.empty(2 * n + 1 + p.size), np.empty(n + n * n)
    c_in = np.empty(n + 1 + p.size)
    for i in range(p.size):
        m_in[2 * n + 1 + i] = p[i]
        l_in[2 * n + 1 + i] = p[i]
        c_in[n + 1 + i] = p[i]
    c_out = np.empty(max(m * (2 + n + n * n), 1))
    return (
        (midpoint, data[0], m_in, m_out),
        (legendre, data[1], l_in, l_out),
        (constraints, data[2], c_in, c_out),
    )


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def call(function, q, v, t):
    """out of ``function`` = (f, user_data, in, out) at (q, v, t), or at (q, t) for an
    empty v."""
    f, user_data, inputs, outputs = function
    n = q.size
    for i in range(n):
        inputs[i] = q[i]
    for i in range(v.size):
        inputs[n + i] = v[i]
    inputs[n + v.size] = t
    f(outputs.ctypes, inputs.ctypes, user_data)
    return outputs


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def evaluate_constraints(system, q, t, h, jacobian, rate, hessians):
    """h, A, dh/dt and the Hessians d2h_j/dq2 at (q, t) into the given arrays."""
    m, n = h.size, q.size
    if m == 0:
        return
    values = call(system[2], q, q[:0], t)
    for j in range(m):
        h[j] = values[j]
        rate[j] = values[m + m * n + j]
        for i in range(n):
            jacobian[j, i] = values[m + j * n + i]
            for k in range(n):
                hessians[j, i, k] = values[2 * m + m * n + (j * n + i) * n + k]


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def largest(x) -> float:
    """max |x_i| over every entry (0 when empty), NaN when an entry is NaN."""
    result = 0.0
    for value in x.flat:
        size = abs(value)
        if size > result or size != size:
            result = size
            if size != size:
                return size
    return result


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def within(residual, size, tolerance) -> bool:
    """residual <= tolerance * size (size 0 counts as 1); False for NaN."""
    return residual <= tolerance * (size if size != 0.0 else 1.0)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def small_correction(correction, new, old) -> bool:
    """Whether a Newton correction is below SMALL_CORRECTION of the size of ``new`` and of
    its change from ``old`` (False for NaN)."""
    size = 0.0
    for i in range(new.size):
        size = max(size, abs(new[i]), abs(new[i] - old[i]))
    if size != size:
        return False
    return within(largest(correction), size, SMALL_CORRECTION)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def constraints_hold(h, jacobian, q1, q0) -> bool:
    """|h| <= RESIDUAL_GUARD |A| (|q1| + |q1 - q0|) (True without constraints)."""
    if h.size == 0:
        return True
    change = 0.0
    for i in range(q1.size):
        change = max(change, abs(q1[i] - q0[i]))
    reach = largest(jacobian) * (largest(q1) + change)
    return within(largest(h), reach, RESIDUAL_GUARD)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def solve(matrix, rhs) -> bool:
    """rhs <- matrix^-1 rhs; False when the matrix is singular or the solution not finite."""
    return solve_linear(matrix, rhs) and finite(rhs)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def newton_update(matrix, rhs, x, x_old, multipliers) -> bool:
    """One Newton correction of unknowns x and their constraints' ``multipliers`` from the
    saddle-point system [[K, B], [C, 0]] (correction) = rhs, its blocks K, B, C filled by
    the caller (the position and the velocity equations fill them differently): the
    multipliers' block zeroed, solved in place, x_old = x, then both corrected.  False
    when the matrix is singular or the correction is not finite."""
    n, m = x.size, multipliers.size
    for j in range(m):
        for k in range(m):
            matrix[n + j, n + k] = 0.0
    if not solve(matrix, rhs):
        return False
    for i in range(n):
        x_old[i] = x[i]
        x[i] -= rhs[i]
    for j in range(m):
        multipliers[j] -= rhs[n + j]
    return True


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def factor(matrix, pivots) -> bool:
    """LU factors of ``matrix`` with partial pivoting, in place, for :func:`substitute`
    (Golub & Van Loan, Matrix Computations, 3.4): the multipliers of the elimination below
    the diagonal (each in the row it was made for), the upper factor above it, the
    reciprocals of its pivots on it; ``pivots[k]`` the row swapped with row k at step k.
    False at an exactly zero pivot (singular)."""
    n = pivots.size
    for k in range(n):
        pivot, size = k, abs(matrix[k, k])
        for i in range(k + 1, n):
            if abs(matrix[i, k]) > size:
                pivot, size = i, abs(matrix[i, k])
        pivots[k] = pivot
        if size == 0.0:
            return False
        if pivot != k:  # the rows' multipliers stay: substitute swaps as it eliminates
            for j in range(k, n):
                matrix[k, j], matrix[pivot, j] = matrix[pivot, j], matrix[k, j]
        inverse = 1.0 / matrix[k, k]
        matrix[k, k] = inverse
        for i in range(k + 1, n):
            factor = matrix[i, k] * inverse
            matrix[i, k] = factor
            for j in range(k + 1, n):
                matrix[i, j] -= factor * matrix[k, j]
    return True


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def substitute(matrix, pivots, vector) -> bool:
    """vector <- M^-1 vector from the factors of M by :func:`factor`; False when the
    solution is not finite."""
    n = pivots.size
    for k in range(n):
        pivot = pivots[k]
        if pivot != k:
            vector[k], vector[pivot] = vector[pivot], vector[k]
        for i in range(k + 1, n):
            vector[i] -= matrix[i, k] * vector[k]
    for i in range(n - 1, -1, -1):
        total = vector[i]
        for j in range(i + 1, n):
            total -= matrix[i, j] * vector[j]
        vector[i] = total * matrix[i, i]
    return finite(vector)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def finite(values) -> bool:
    """Whether every entry of ``values`` is finite."""
    for value in values:  # noqa: SIM110 (a loop numba compiles without allocating)
        if not np.isfinite(value):
            return False
    return True


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def velocity_step(system, q1, momentum, t1, weight, constraint, linear, v, mu, work):
    """Solve the velocity equations (module docstring) for v (in place, from its guess) and
    mu; ``constraint`` = (A1, dh/dt) at (q1, t1); ``momentum`` becomes momentum + weight
    A1^T mu.  Returns (status, evaluations of the Legendre map)."""
    jacobian, rate = constraint
    matrix, rhs, v_old = work
    n, m = q1.size, mu.size
    mu[:] = 0.0
    small = False
    for iteration in range(MAX_ITERATIONS + 1):
        values = call(system[1], q1, v, t1)
        size = max(largest(values[:n]), largest(momentum))
        for i in range(n):
            impulse = 0.0
            for j in range(m):
                impulse += -weight * jacobian[j, i] * mu[j]
            rhs[i] = values[i] - momentum[i] + impulse
        if small and within(largest(rhs[:n]), size, RESIDUAL_GUARD):
            add_impulse(momentum, weight, jacobian, mu)
            return OK, iteration + 1
        for i in range(n):
            for k in range(n):
                matrix[i, k] = values[n + i * n + k]
        for j in range(m):
            total = rate[j]
            for i in range(n):
                matrix[i, n + j] = -weight * jacobian[j, i]
                matrix[n + j, i] = jacobian[j, i]
                total += jacobian[j, i] * v[i]
            rhs[n + j] = total
        if not newton_update(matrix, rhs, v, v_old, mu):
            return VELOCITY_SINGULAR, iteration + 1
        if linear:  # the equations are linear in (v1, mu): solved exactly
            add_impulse(momentum, weight, jacobian, mu)
            return OK, 1
        small = small_correction(rhs[:n], v, v_old)
    return VELOCITY_DIVERGED, MAX_ITERATIONS + 1


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def add_impulse(momentum, weight, jacobian, mu):
    """momentum += weight A^T mu."""
    for i in range(momentum.size):
        impulse = 0.0
        for j in range(mu.size):
            impulse += -weight * jacobian[j, i] * mu[j]
        momentum[i] -= impulse
