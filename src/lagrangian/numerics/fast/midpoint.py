"""The midpoint-rule variational integrator compiled: a chunk of steps in one call.

The equations are those of :mod:`lagrangian.simulation.variational.step` (the forced,
constrained discrete Euler-Lagrange equations of the midpoint discrete Lagrangian in
position-momentum form), solved by the same Newton iterations with the same tolerances and
starting guesses, so the compiled march gives the NumPy march's trajectory to rounding.  A
step (q0, p0) -> (q1, p1):

    p0 + dt/2 (L_q + Q) - L_v + dt/2 A(q0, t0)^T lambda = 0,   h(q1, t1) = 0   (at the midpoint)
    p1 = dt/2 (L_q + Q) + L_v + dt/2 A(q1, t1)^T mu,  A(q1, t1) v1 + dh/dt = 0,
    p1 = dL/dq_dot(q1, v1, t1).

:func:`march_midpoint` takes the nodes first..last-1 of the time grid; the march keeps its
state in arrays between chunks (so that the caller can report progress and stop on Ctrl-C
between them).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lagrangian.numerics.discrete_lagrangian import MAX_ITERATIONS, RESIDUAL_GUARD
from lagrangian.numerics.fast.newton import (
    FINISHED,
    OK,
    POSITION_DIVERGED,
    POSITION_SINGULAR,
    RUNNING,
    bind,
    call,
    constraints_hold,
    evaluate_constraints,
    largest,
    small_correction,
    solve,
    velocity_step,
    within,
)


@njit(cache=False, nogil=True, error_model="numpy")
def position_step(system, q0, p0, t0, dt, jacobian0, q1, lam, found, work):
    """Solve the position equations (module docstring) for (q1, lambda), in place from their
    guesses; ``found`` = (momentum, h, A, dh/dt, Hessians) receives dt/2 (L_q + Q) + L_v and
    the constraints at (q1, t1).  Returns (status, evaluations of the midpoint terms)."""
    momentum, h, a1, rate, hessians = found
    matrix, rhs, q_mid, v_mid, q_old = work
    n, m = q0.size, lam.size
    t_mid, t1 = t0 + dt / 2, t0 + dt
    small = False
    for iteration in range(MAX_ITERATIONS + 1):
        for i in range(n):
            q_mid[i] = (q0[i] + q1[i]) / 2
            v_mid[i] = (q1[i] - q0[i]) / dt
        values = call(system[0], q_mid, v_mid, t_mid)
        evaluate_constraints(system, q1, t1, h, a1, rate, hessians)
        size = 0.0
        for i in range(n):
            force = dt / 2 * (values[i] + values[2 * n + i])
            impulse = 0.0
            for j in range(m):
                impulse += dt / 2 * jacobian0[j, i] * lam[j]
            rhs[i] = p0[i] + force - values[n + i] + impulse
            momentum[i] = force + values[n + i]
            size = max(size, abs(p0[i]), abs(force), abs(values[n + i]), abs(impulse))
        rows = largest(rhs[:n])
        if small and within(rows, size, RESIDUAL_GUARD) and constraints_hold(h, a1, q1, q0):
            return OK, iteration + 1
        newton_matrix(values, dt, n, matrix)
        for j in range(m):
            rhs[n + j] = h[j]
            for i in range(n):
                matrix[i, n + j] = dt / 2 * jacobian0[j, i]
                matrix[n + j, i] = a1[j, i]
            for k in range(m):
                matrix[n + j, n + k] = 0.0
        if not solve(matrix, rhs):
            return POSITION_SINGULAR, iteration + 1
        for i in range(n):
            q_old[i] = q1[i]
            q1[i] -= rhs[i]
        for j in range(m):
            lam[j] -= rhs[n + j]
        small = small_correction(rhs[:n], q_old, q0)
    return POSITION_DIVERGED, MAX_ITERATIONS + 1


@njit(cache=False, nogil=True, error_model="numpy")
def newton_matrix(values, dt, n, matrix):
    """The q1 block of the position equations' Jacobian,
    dt/4 (L_qq + Q_q) + (L_qv - L_qv^T + Q_v)/2 - L_vv/dt, from the midpoint terms."""
    base, size = 3 * n, n * n
    for i in range(n):
        for k in range(n):
            ik, ki = i * n + k, k * n + i
            L_qq, L_vv = values[base + ik], values[base + 2 * size + ik]
            L_qv, L_vq = values[base + size + ik], values[base + size + ki]
            Q_q, Q_v = values[base + 3 * size + ik], values[base + 4 * size + ik]
            matrix[i, k] = dt / 4 * (L_qq + Q_q) + (L_qv - L_vq + Q_v) / 2 - L_vv / dt


@njit(cache=False, nogil=True, error_model="numpy")
def guess(grid, k, q, history, known, q1):
    """q_{k+1} into q1: the polynomial through q_k and the ``known`` (0, 1 or 2) earlier
    nodes history[0] = q_{k-1}, history[1] = q_{k-2}, extrapolated (an error O(dt^3))."""
    for i in range(q.size):
        if known == 0:
            q1[i] = q[i]
            continue
        s1 = (q[i] - history[0, i]) / (grid[k] - grid[k - 1])
        if known == 1:
            q1[i] = q[i] + (grid[k + 1] - grid[k]) * s1
            continue
        s0 = (history[0, i] - history[1, i]) / (grid[k - 1] - grid[k - 2])
        curvature = (s1 - s0) / (grid[k] - grid[k - 2])
        q1[i] = q[i] + (grid[k + 1] - grid[k]) * (s1 + (grid[k + 1] - grid[k - 1]) * curvature)


@njit(cache=False, nogil=True, error_model="numpy")
def record(row, q, v, h, jacobian, rate, out):
    """Output row ``row``: q, v and the largest residual max(|h|, |A v + dh/dt|)."""
    q_out, v_out, residual_out = out[0], out[1], out[2]
    worst = largest(h)
    for j in range(h.size):
        total = rate[j]
        for i in range(q.size):
            total += jacobian[j, i] * v[i]
        worst = max(worst, abs(total))
    for i in range(q.size):
        q_out[row, i] = q[i]
        v_out[row, i] = v[i]
    residual_out[row] = worst


def march_midpoint(
    midpoint, legendre, constraints, data, p, grid, row_of, nodes, linear, state, counts, out
):
    """Nodes nodes[0]..nodes[1]-1 of ``grid``: record each output node, step to the next.

    ``midpoint``, ``legendre``, ``constraints``, ``data``: the C functions and user_data of
    :class:`~lagrangian.numerics.fast.discrete.NativeMechanics`; ``row_of[k]``: the output row
    of node k, or -1; ``linear``: whether the Legendre map is affine in v; ``state`` =
    (q, v, p, lambda, h, A, dh/dt, history) at the current node, updated in place;
    ``counts`` = [known history, evaluations, last node reached]; ``out`` = (q, v, residual,
    lambda, mu): rows by output and by step.  Returns RUNNING, FINISHED or the failure.
    """
    q, v, momentum, lam, h, jacobian, rate, history = state
    lam_steps, mu_steps = out[3], out[4]
    n, m = q.size, lam.size
    system = bind((midpoint, legendre, constraints), data, p, n, m)
    q1, lam1, mu, momentum1 = np.empty(n), np.empty(m), np.empty(m), np.empty(n)
    h1, a1, rate1, hessians = np.empty(m), np.empty((m, n)), np.empty(m), np.empty((m, n, n))
    matrix, rhs = np.empty((n + m, n + m)), np.empty(n + m)
    work = (matrix, rhs, np.empty(n), np.empty(n), np.empty(n))
    velocity_work = (matrix, rhs, np.empty(n))
    for k in range(nodes[0], nodes[1]):
        if row_of[k] >= 0:
            record(row_of[k], q, v, h, jacobian, rate, out)
        if k == grid.size - 1:
            return FINISHED
        t0, dt = grid[k], grid[k + 1] - grid[k]
        guess(grid, k, q, history, counts[0], q1)
        lam1[:] = lam
        found = (momentum1, h1, a1, rate1, hessians)
        status, evaluations = position_step(
            system, q, momentum, t0, dt, jacobian, q1, lam1, found, work
        )
        counts[1] += evaluations
        if status != OK:
            return status
        momentum[:] = momentum1
        if m > 0 or row_of[k + 1] >= 0:
            h[:] = h1
            jacobian[:] = a1
            rate[:] = rate1
            for i in range(n):
                v[i] = (q1[i] - q[i]) / dt
            constraint = (jacobian, rate)
            status, evaluations = velocity_step(
                system, q1, momentum, t0 + dt, dt / 2, constraint, linear, v, mu, velocity_work
            )
            counts[1] += evaluations
            if status != OK:
                return status
            mu_steps[k] = mu
        history[1] = history[0]
        history[0] = q
        counts[0] = min(counts[0] + 1, 2)
        q[:] = q1
        lam[:] = lam1
        lam_steps[k] = lam
        counts[2] = k + 1
    k = nodes[1]  # the node reached is kept now: the caller may stop before the next chunk
    if k < grid.size and row_of[k] >= 0:
        record(row_of[k], q, v, h, jacobian, rate, out)
    return RUNNING
