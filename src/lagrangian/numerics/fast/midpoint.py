"""The midpoint-rule variational integrator compiled: a chunk of steps in one call.

The equations are those of :mod:`lagrangian.simulation.variational.step` (the forced,
constrained discrete Euler-Lagrange equations of the midpoint discrete Lagrangian in
position-momentum form), solved by the same Newton iterations with the same tolerances and
starting guesses, so the compiled march gives the NumPy march's trajectory to rounding.  A
step (q0, p0) -> (q1, p1):

    p0 + dt/2 (L_q + Q) - L_v + dt/2 A(q0, t0)^T lambda = 0,   h(q1, t1) = 0   (at the midpoint)
    p1 = dt/2 (L_q + Q) + L_v + dt/2 A(q1, t1)^T mu,  A(q1, t1) v1 + dh/dt = 0,
    p1 = dL/dq_dot(q1, v1, t1).

Newton's method ends when a correction is below SMALL_CORRECTION of the unknowns and the
residual it corrected is within RESIDUAL_GUARD of its terms: the corrected q1 is then exact to
rounding (the error is of the square of the correction), and so is its momentum, taken from
the last evaluation and its Jacobian (an error of the same square) instead of one more
evaluation of the terms.  A step of a smooth motion costs two evaluations.

:func:`march_midpoint` makes a chunk of steps over the nodes that
:mod:`lagrangian.numerics.fast.discrete_nodes` makes as it goes; the march keeps its state in
arrays between chunks (so that the caller can report progress and stop on Ctrl-C between
them).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lagrangian.numerics.discrete_lagrangian import MAX_ITERATIONS, RESIDUAL_GUARD
from lagrangian.numerics.fast.discrete_nodes import (
    END_ROW,
    EVALUATIONS,
    FIRST_ROW,
    KNOWN,
    NODE,
    arrive,
    begin,
    next_node,
    wants_output,
)
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
    hold,
    largest,
    newton_update,
    small_correction,
    unowned,
    unowned_system,
    velocity_step,
    within,
)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def position_step(system, q0, p0, t0, dt, jacobian0, q1, lam, found, work):
    """Solve the position equations (module docstring) for (q1, lambda), in place from their
    guesses; ``found`` = (momentum, h, A, dh/dt, Hessians) receives dt/2 (L_q + Q) + L_v and
    the constraints at (q1, t1).  Returns (status, evaluations of the midpoint terms)."""
    momentum, h, a1, rate, hessians = found
    matrix, rhs, q_mid, v_mid, q_old = work
    n, m = q0.size, lam.size
    t_mid, t1 = t0 + dt / 2, t0 + dt
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
        converging = within(rows, size, RESIDUAL_GUARD) and constraints_hold(h, a1, q1, q0)
        newton_matrix(values, dt, n, matrix)
        for j in range(m):
            rhs[n + j] = h[j]
            for i in range(n):
                matrix[i, n + j] = dt / 2 * jacobian0[j, i]
                matrix[n + j, i] = a1[j, i]
        if not newton_update(matrix, rhs, q1, q_old, lam):
            return POSITION_SINGULAR, iteration + 1
        if converging and small_correction(rhs[:n], q_old, q0):
            corrected_momentum(values, dt, n, rhs, momentum)
            evaluate_constraints(system, q1, t1, h, a1, rate, hessians)
            return OK, iteration + 1
    return POSITION_DIVERGED, MAX_ITERATIONS + 1


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
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


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def corrected_momentum(values, dt, n, correction, momentum):
    """momentum -= J correction: dt/2 (L_q + Q) + L_v moved with q1 by -correction, J its
    Jacobian in q1, dt/4 (L_qq + Q_q) + (L_qv + L_qv^T + Q_v)/2 + L_vv/dt."""
    base, size = 3 * n, n * n
    for i in range(n):
        change = 0.0
        for k in range(n):
            ik, ki = i * n + k, k * n + i
            L_qq, L_vv = values[base + ik], values[base + 2 * size + ik]
            L_qv, L_vq = values[base + size + ik], values[base + size + ki]
            Q_q, Q_v = values[base + 3 * size + ik], values[base + 4 * size + ik]
            slope = dt / 4 * (L_qq + Q_q) + (L_qv + L_vq + Q_v) / 2 + L_vv / dt
            change += slope * correction[k]
        momentum[i] -= change


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def guess(clock, q, history, known, q1):
    """q_{k+1} into q1: the polynomial through q_k and the ``known`` (0, 1 or 2) earlier
    nodes history[0] = q_{k-1}, history[1] = q_{k-2}, extrapolated (an error O(dt^3));
    ``clock`` = [t_{k-2}, t_{k-1}, t_k, t_{k+1}]."""
    for i in range(q.size):
        if known == 0:
            q1[i] = q[i]
            continue
        s1 = (q[i] - history[0, i]) / (clock[2] - clock[1])
        if known == 1:
            q1[i] = q[i] + (clock[3] - clock[2]) * s1
            continue
        s0 = (history[0, i] - history[1, i]) / (clock[1] - clock[0])
        curvature = (s1 - s0) / (clock[2] - clock[0])
        q1[i] = q[i] + (clock[3] - clock[2]) * (s1 + (clock[3] - clock[1]) * curvature)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def keep_halves(k, lam, mu, dt, halves, out, cursor):
    """The halves (lambda_k, mu_k, dt_k) of step k into ``halves`` (rows 0-2: the first three
    steps; rows 3-5: the last three, by k mod 3), and the multiplier at node k > 0 into its
    output rows, (dt_{k-1} lambda_k + dt_k mu_{k-1}) / (dt_{k-1} + dt_k)."""
    m = lam.size
    rows = (k, 3 + k % 3) if k < 3 else (3 + k % 3, 3 + k % 3)
    for row in rows:
        for j in range(m):
            halves[row, j] = lam[j]
            halves[row, m + j] = mu[j]
        halves[row, 2 * m] = dt
    if k == 0:
        return
    before = halves[3 + (k - 1) % 3]
    multipliers = out[3]
    for row in range(cursor[FIRST_ROW], cursor[END_ROW]):
        for j in range(m):
            weighted = before[2 * m] * lam[j] + dt * before[m + j]
            multipliers[row, j] = weighted / (before[2 * m] + dt)


def march_midpoint(
    midpoint, legendre, constraints, data, p, schedule, linear, state, steps, cursor, clock,
    out, halves,
):  # fmt: skip
    """At most ``steps`` steps from the current node (the first node, recorded, when
    cursor[NODE] < 0): step to the next node, record its output rows.

    ``midpoint``, ``legendre``, ``constraints``, ``data``: the C functions and user_data of
    :class:`~lagrangian.numerics.fast.discrete.NativeMechanics`; ``schedule``, ``cursor``,
    ``clock``, ``out``: the nodes and output rows of
    :mod:`lagrangian.numerics.fast.discrete_nodes`; ``linear``: whether the Legendre map is
    affine in v; ``state`` = (q, v, p, lambda, h, A, dh/dt, history) at the current node,
    updated in place; ``halves``: the multipliers' halves of :func:`keep_halves`.  Returns
    RUNNING, FINISHED or the failure.
    """
    q, v, momentum, lam, h, jacobian, rate, history = state
    n, m = q.size, lam.size
    system = bind((midpoint, legendre, constraints), data, p, n, m)
    vectors = np.empty((6, n))
    constraint_rows = np.empty((4, m))
    a1, hessians = np.empty((m, n)), np.empty((m, n, n))
    matrix, rhs = np.empty((n + m, n + m)), np.empty(n + m)
    free = (unowned(vectors), unowned(constraint_rows), unowned(a1), unowned(hessians))
    solver = (unowned(matrix), unowned(rhs))
    mine = (
        unowned(q), unowned(v), unowned(momentum), unowned(lam), unowned(h), unowned(jacobian),
        unowned(rate), unowned(history),
    )  # fmt: skip
    place = (unowned(schedule[0]), unowned(schedule[1]), unowned(schedule[2]), schedule[3])
    rows = (unowned(out[0]), unowned(out[1]), unowned(out[2]), unowned(out[3]))
    records = (*rows, unowned(out[4]), unowned(out[5]))
    status = midpoint_steps(
        unowned_system(system), place, linear, mine, steps, unowned(cursor), unowned(clock),
        records, unowned(halves), free, solver,
    )  # fmt: skip
    hold((system, vectors, constraint_rows, a1, hessians, matrix, rhs))
    return status


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def midpoint_steps(
    system, schedule, linear, state, steps, cursor, clock, out, halves, free, solver
):
    """:func:`march_midpoint` on arrays that hold no references (:func:`unowned`)."""
    q, v, momentum, lam, h, jacobian, rate, history = state
    vectors, constraint_rows, a1, hessians = free
    q1, momentum1, work_1, work_2, work_3, work_4 = (
        vectors[0], vectors[1], vectors[2], vectors[3], vectors[4], vectors[5]
    )  # fmt: skip
    lam1, mu, h1, rate1 = (
        constraint_rows[0], constraint_rows[1], constraint_rows[2], constraint_rows[3]
    )  # fmt: skip
    matrix, rhs = solver
    work = (matrix, rhs, work_1, work_2, work_3)
    velocity_work = (matrix, rhs, work_4)
    m = lam.size
    begin(schedule, cursor, clock, q, v, h, jacobian, rate, out)
    for _ in range(steps):
        t0, t1 = clock[2], clock[3]
        if t1 == np.inf:
            return FINISHED
        dt = t1 - t0
        guess(clock, q, history, cursor[KNOWN], q1)
        lam1[:] = lam
        found = (momentum1, h1, a1, rate1, hessians)
        status, evaluations = position_step(
            system, q, momentum, t0, dt, jacobian, q1, lam1, found, work
        )
        cursor[EVALUATIONS] += evaluations
        if status != OK:
            return status
        momentum[:] = momentum1
        t2 = next_node(schedule, cursor, clock)
        if m > 0 or wants_output(schedule, cursor, t1, t2 == np.inf):
            h[:] = h1
            jacobian[:] = a1
            rate[:] = rate1
            for i in range(q.size):
                v[i] = (q1[i] - q[i]) / dt
            constraint = (jacobian, rate)
            status, evaluations = velocity_step(
                system, q1, momentum, t1, dt / 2, constraint, linear, v, mu, velocity_work
            )
            cursor[EVALUATIONS] += evaluations
            if status != OK:
                return status
        if m > 0:
            keep_halves(cursor[NODE], lam1, mu, dt, halves, out, cursor)
        history[1] = history[0]
        history[0] = q
        cursor[KNOWN] = min(cursor[KNOWN] + 1, 2)
        q[:] = q1
        lam[:] = lam1
        arrive(schedule, cursor, clock, t2, q, v, h, jacobian, rate, out)
    return RUNNING
