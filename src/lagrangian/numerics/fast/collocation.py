"""The collocation integrators (Gauss–Legendre, the Lobatto IIIA–IIIB pair) compiled: a chunk
of steps in one call.

The stage equations and their Newton iteration are those of
:mod:`lagrangian.simulation.variational.collocation_step` (unknowns the stage velocities V_i and the
scaled multipliers h Lambda_1..h Lambda_{s-1}; the momenta at every stage and the
constraints at stages 2..s divided by h), the march that of
:mod:`lagrangian.simulation.variational.collocation_march`; the tableau arrives as arrays
``(a, a_hat, b, c)``.

Where the time of a step goes (a double pendulum, three stages): the system's terms are a
quarter of it; the Jacobian of the stage equations and its factors, the stage bookkeeping
the rest.  So the iteration stops at its second evaluation of the stages (the forces at the
last correction from their Jacobian), the Jacobian is assembled and factored once a step,
at the first iterate, and reused by the corrections after it (simplified Newton,
:mod:`lagrangian.numerics.stage_newton`), in a function of its own
(:func:`factor_stage_jacobian`), and the extrapolation of the stage velocities is made once
per size of step, not at every step.  The iteration starts from that extrapolation corrected
by the extrapolated errors of the steps before (:mod:`lagrangian.numerics.stage_prediction`):
most steps of a smooth motion then end at Newton's first correction, one evaluation of the
stages.
This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lagrangian.numerics.discrete_lagrangian import (
    MAX_ITERATIONS,
    RESIDUAL_GUARD,
    SMALL_CORRECTION,
)
from lagrangian.numerics.fast.discrete_nodes import (
    EVALUATIONS,
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
    evaluate_constraints,
    factor,
    hold,
    largest,
    substitute,
    unowned,
    unowned_system,
    velocity_step,
    within,
)
from lagrangian.numerics.stage_newton import REFRESH_RATE, settled
from lagrangian.numerics.stage_prediction import (
    NEWTON_RESIDUAL_GUARD,
    corrected_guess,
    forget,
    remember,
    step_ratio,
)

_inline = njit(cache=False, nogil=True, error_model="numpy", inline="always")
#: :func:`lagrangian.numerics.stage_newton.settled`, compiled into the march.
compiled_settled = _inline(settled)
#: The start of the stage iteration (:mod:`lagrangian.numerics.stage_prediction`): functions
#: of their own (their loops keep their values in registers, see
#: :func:`factor_stage_jacobian`), called with views without owners.
_apart = njit(cache=False, nogil=True, error_model="numpy")
compiled_corrected_guess, compiled_remember = _apart(corrected_guess), _apart(remember)
compiled_forget, compiled_step_ratio = _inline(forget), _inline(step_ratio)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def evaluate_stages(system, tableau, q0, t0, dt, V, stages):
    """The terms at the stages Q_i = q0 + dt sum_j a_ij V_j, t_i = t0 + c_i dt into ``stages``
    = (Q, F = L_q + Q_f, L_v, L_qv, L_qv + Q_v, L_vv, L_qq + Q_q, h, A, Hessians, dh/dt)."""
    a, c = tableau[0], tableau[3]
    Q, F, L_v, L_qv, F_v, L_vv, K, h, A, H, rate = stages
    s, n = V.shape
    size = n * n
    for i in range(s):
        for b in range(n):
            total = 0.0
            for j in range(s):
                total += a[i, j] * V[j, b]
            Q[i, b] = q0[b] + dt * total
        t = t0 + c[i] * dt
        values = call(system[0], Q[i], V[i], t)
        for b in range(n):
            F[i, b] = values[b] + values[2 * n + b]
            L_v[i, b] = values[n + b]
        base = 3 * n
        for row in range(n):  # nested loops: an integer division per entry costs more
            for col in range(n):
                e = base + row * n + col
                K[i, row, col] = values[e] + values[e + 3 * size]
                L_qv[i, row, col] = values[e + size]
                F_v[i, row, col] = values[e + size] + values[e + 4 * size]
                L_vv[i, row, col] = values[e + 2 * size]
        evaluate_constraints(system, Q[i], t, h[i], A[i], rate[i], H[i])


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def stage_residual(tableau, p0, dt, lam, stages, forces, rhs):
    """The momentum rows and the scaled constraint rows into ``rhs``; ``forces`` receives
    F_j + A_j^T Lambda_j.  Returns the size of the momentum rows' terms."""
    a_hat = tableau[1]
    Q, F, L_v, h, A = stages[0], stages[1], stages[2], stages[7], stages[8]
    s, n = Q.shape
    r, m = lam.shape
    for j in range(s):
        for b in range(n):
            total = F[j, b]
            if j < r:
                for l in range(m):
                    total += A[j, l, b] * lam[j, l]
            forces[j, b] = total
    size = 0.0
    for i in range(s):
        for b in range(n):
            pushed = 0.0
            for j in range(s):
                pushed += dt * a_hat[i, j] * forces[j, b]
            rhs[i * n + b] = L_v[i, b] - p0[b] - pushed
            size = max(size, abs(L_v[i, b]), abs(p0[b]), abs(pushed))
    for i in range(r):
        for l in range(m):
            rhs[s * n + i * m + l] = h[i + 1, l] / dt
    return size


@njit(cache=False, nogil=True, error_model="numpy")
def factor_stage_jacobian(a, a_hat, weights, dt, r, L_qv, F_v, L_vv, K, A, matrix, pivots):
    """The Jacobian of the stage equations (:func:`stage_jacobian`) into ``matrix``, factored
    there (:func:`lagrangian.numerics.fast.newton.factor`); False when it is singular.

    A function of its own, called with the arrays one by one (views without owners, so the
    call costs a few words): compiled apart from the march, its loops keep their values in
    registers, where inlined into the march they spilled to the stack (a third of a step)."""
    stage_jacobian(a, a_hat, weights, dt, r, L_qv, F_v, L_vv, K, A, matrix)
    return factor(matrix, pivots)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def add_constraint_hessians(lam, H, K):
    """K_j += sum_l Lambda_jl d2h_l/dq2 at the stages j with multipliers."""
    r, m = lam.shape
    n = K.shape[1]
    for j in range(r):
        for l in range(m):
            for x in range(n):
                for y in range(n):
                    K[j, x, y] += lam[j, l] * H[j, l, x, y]


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def stage_jacobian(a, a_hat, weights, dt, r, L_qv, F_v, L_vv, K, A, matrix):
    """The Jacobian of the stage equations in (V, dt Lambda) (see
    :mod:`lagrangian.simulation.variational.collocation_step`; ``weights`` of
    :func:`couplings`, the stage terms of :func:`evaluate_stages`, K with the constraint
    Hessians of :func:`add_constraint_hessians`, r the stages with multipliers)."""
    s, n = L_vv.shape[0], L_vv.shape[1]
    m = A.shape[1]
    for i in range(s):
        for k in range(s):
            drift, push = dt * a[i, k], dt * a_hat[i, k]
            for x in range(n):
                for y in range(n):
                    coupling = 0.0
                    for j in range(s):
                        coupling += weights[i, k, j] * K[j, x, y]
                    value = drift * L_qv[i, y, x] - push * F_v[k, x, y] - dt * dt * coupling
                    if i == k:
                        value += L_vv[i, x, y]
                    matrix[i * n + x, k * n + y] = value
        for k in range(r):
            for x in range(n):
                for l in range(m):
                    matrix[i * n + x, s * n + k * m + l] = -a_hat[i, k] * A[k, l, x]
    for i in range(r):
        for l in range(m):
            for k in range(s):
                for y in range(n):
                    matrix[s * n + i * m + l, k * n + y] = a[i + 1, k] * A[i + 1, l, y]
            for k in range(r * m):
                matrix[s * n + i * m + l, s * n + k] = 0.0


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def stages_hold(stages, q0, r) -> bool:
    """|h| <= RESIDUAL_GUARD |A| (|Q| + |Q - q0|) at the constrained stages 2..r+1."""
    if r == 0:
        return True
    Q, h, A = stages[0][1 : r + 1], stages[7][1 : r + 1], stages[8][1 : r + 1]
    change = 0.0
    for i in range(r):
        for b in range(q0.size):
            change = max(change, abs(Q[i, b] - q0[b]))
    return within(largest(h), largest(A) * (largest(Q) + change), RESIDUAL_GUARD)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def stage_step(system, tableau, weights, q0, p0, t0, dt, V, lam, found, work):
    """Solve the stage equations for V (s, n) and Lambda (r, m) in place from their guesses
    by simplified Newton iterations (:mod:`lagrangian.numerics.stage_newton`); ``found`` =
    (q1, momentum before the impulse of Lambda_s).  Returns (status, stage evaluations)."""
    b = tableau[2]
    stages, forces, matrix, rhs, pivots = work
    q1, momentum = found
    s, n = V.shape
    r, m = lam.shape
    fresh, last = True, 0.0  # the Jacobian is factored at the first iterate
    for iteration in range(MAX_ITERATIONS + 1):
        evaluate_stages(system, tableau, q0, t0, dt, V, stages)
        size = stage_residual(tableau, p0, dt, lam, stages, forces, rhs)
        # the residual left after the correction within RESIDUAL_GUARD: of the square of
        # the one before it after a Newton step (stage_prediction.NEWTON_RESIDUAL_GUARD)
        guard = NEWTON_RESIDUAL_GUARD if fresh else RESIDUAL_GUARD
        converging = within(largest(rhs[: s * n]), size, guard)
        converging = converging and stages_hold(stages, q0, r)
        reach = 0.0
        for i in range(s):
            for x in range(n):
                reach = max(reach, abs(stages[0][i, x]), abs(stages[0][i, x] - q0[x]))
        L_qv, F_v, L_vv, K, A = stages[3], stages[4], stages[5], stages[6], stages[8]
        add_constraint_hessians(lam, stages[9], K)
        if fresh and not factor_stage_jacobian(
            tableau[0], tableau[1], weights, dt, r, L_qv, F_v, L_vv, K, A, matrix, pivots
        ):
            return POSITION_SINGULAR, (iteration + 1) * s
        if not substitute(matrix, pivots, rhs):
            return POSITION_SINGULAR, (iteration + 1) * s
        for i in range(s):
            for x in range(n):
                V[i, x] -= rhs[i * n + x]
        for i in range(r):
            for l in range(m):
                lam[i, l] -= rhs[s * n + i * m + l] / dt
        change = dt * largest(rhs[: s * n])
        rate = 0.0 if fresh or last == 0.0 else change / last
        if (
            converging
            and within(change, reach, SMALL_CORRECTION)
            and compiled_settled(rate, change, reach)
        ):
            corrected_forces(tableau, dt, lam, stages, rhs, forces)
            for x in range(n):
                q1[x] = q0[x] + dt * weighted(b, V, x)  # the last stage of Lobatto (a_s = b)
                momentum[x] = p0[x] + dt * weighted(b, forces, x)
            return OK, (iteration + 1) * s
        fresh = not rate <= REFRESH_RATE  # Newton's rate lost: a new Jacobian next
        last = change
    return POSITION_DIVERGED, (MAX_ITERATIONS + 1) * s


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def corrected_forces(tableau, dt, lam, stages, correction, forces):
    """forces_j <- F_j + A_j^T Lambda_j at the corrected stages, from their values before the
    correction by its Jacobian: F_j - sum_k (delta_jk F_v(j) + dt a_jk K_j) dV_k +
    A_j^T Lambda_j (Lambda corrected already; K_j holds the multipliers' Hessians)."""
    a = tableau[0]
    F, F_v, K, A = stages[1], stages[4], stages[6], stages[8]
    s, n = F.shape
    r, m = lam.shape
    for j in range(s):
        for x in range(n):
            total = F[j, x]
            for y in range(n):
                total -= F_v[j, x, y] * correction[j * n + y]
                along = 0.0
                for k in range(s):
                    along += a[j, k] * correction[k * n + y]
                total -= dt * K[j, x, y] * along
            if j < r:
                for l in range(m):
                    total += A[j, l, x] * lam[j, l]
            forces[j, x] = total


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def weighted(b, rows, x) -> float:
    """sum_i b_i rows[i, x]."""
    total = 0.0
    for i in range(b.size):
        total += b[i] * rows[i, x]
    return total


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def extrapolation(c, ratio, E):
    """E_ij <- l_j(1 + ratio c_i) (l_j the Lagrange polynomials of the nodes c)."""
    s = c.size
    for i in range(s):
        x = 1.0 + ratio * c[i]
        for j in range(s):
            basis = 1.0
            for k in range(s):
                if k != j:
                    basis *= (x - c[k]) / (c[j] - c[k])
            E[i, j] = basis


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def extrapolate(E, V, plain):
    """plain <- E V: the stage velocities of the step before extrapolated to this step's
    nodes."""
    s, n = V.shape
    for i in range(s):
        for y in range(n):
            total = 0.0
            for j in range(s):
                total += E[i, j] * V[j, y]
            plain[i, y] = total


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def couplings(tableau, weights):
    """weights[i, k, j] <- a_hat_ij a_jk, the weights of the stage Hessians in the Jacobian."""
    a, a_hat = tableau[0], tableau[1]
    s = a.shape[0]
    for i in range(s):
        for k in range(s):
            for j in range(s):
                weights[i, k, j] = a_hat[i, j] * a[j, k]


def march_collocation(
    midpoint, legendre, constraints, data, p, schedule, linear, tableau, state, steps, cursor,
    clock, out,
):  # fmt: skip
    """At most ``steps`` steps of the collocation method ``tableau`` = (a, a_hat, b, c,
    lobatto) from the current node: step to the next node, record its output rows.

    Arguments as :func:`lagrangian.numerics.fast.midpoint.march_midpoint`, but ``state`` =
    (q, v, p, h, A, dh/dt, V, Lambda, [previous step], the difference table of the prediction
    errors and its counter (:mod:`lagrangian.numerics.stage_prediction`)).  Returns RUNNING,
    FINISHED or the failure.
    """
    q, v, momentum, h, jacobian, rate, V, lam, previous, history, counters = state
    n, m, s, r = q.size, h.size, V.shape[0], lam.shape[0]
    system = bind((midpoint, legendre, constraints), data, p, n, m)
    vectors, matrices = (np.empty((s, n)), np.empty((s, n)), np.empty((s, n))), (
        np.empty((s, n, n)), np.empty((s, n, n)), np.empty((s, n, n)), np.empty((s, n, n))
    )  # fmt: skip
    rows = (np.empty((s, m)), np.empty((s, m, n)), np.empty((s, m, n, n)), np.empty((s, m)))
    size = s * n + r * m
    owners = (
        vectors, matrices, rows, np.empty((s, n)), np.empty((size, size)), np.empty(size),
        np.empty((4, n)), np.empty(m), np.empty((s, n)), np.empty((n + m, n + m)),
        np.empty(n + m), np.empty((s, s)), np.empty((s, s, s)), np.empty(size, np.int64),
        np.empty((s, n)),
    )  # fmt: skip
    stages = (
        unowned(vectors[0]), unowned(vectors[1]), unowned(vectors[2]),
        unowned(matrices[0]), unowned(matrices[1]), unowned(matrices[2]), unowned(matrices[3]),
        unowned(rows[0]), unowned(rows[1]), unowned(rows[2]), unowned(rows[3]),
    )  # fmt: skip
    work = (
        stages, unowned(owners[3]), unowned(owners[4]), unowned(owners[5]), unowned(owners[13])
    )  # fmt: skip
    spare = (
        unowned(owners[6]), unowned(owners[7]), unowned(owners[8]), unowned(owners[11]),
        unowned(owners[12]), unowned(owners[14]),
    )  # fmt: skip
    velocity_work = (unowned(owners[9]), unowned(owners[10]))
    tableau_views = (
        unowned(tableau[0]), unowned(tableau[1]), unowned(tableau[2]), unowned(tableau[3]),
        tableau[4],
    )  # fmt: skip
    mine = (
        unowned(q), unowned(v), unowned(momentum), unowned(h), unowned(jacobian),
        unowned(rate), unowned(V), unowned(lam), unowned(previous), unowned(history),
        unowned(counters),
    )  # fmt: skip
    place = (unowned(schedule[0]), unowned(schedule[1]), unowned(schedule[2]), schedule[3])
    records = (
        unowned(out[0]), unowned(out[1]), unowned(out[2]), unowned(out[3]), unowned(out[4]),
        unowned(out[5]),
    )  # fmt: skip
    status = collocation_steps(
        unowned_system(system), place, linear, tableau_views, mine, steps, unowned(cursor),
        unowned(clock), records, work, spare, velocity_work,
    )  # fmt: skip
    hold((system, owners))
    return status


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def collocation_steps(
    system, schedule, linear, tableau, state, steps, cursor, clock, out, work, spare,
    velocity_work,
):  # fmt: skip
    """:func:`march_collocation` on arrays that hold no references."""
    q, v, momentum, h, jacobian, rate, V, lam, previous, history, counters = state
    s, m = V.shape[0], h.size
    stages = work[0]
    vectors, mu, plain, E, weights, guess = spare
    couplings(tableau, weights)
    ratio = np.nan  # that of the extrapolation E
    q1, momentum1, v_old = vectors[0], vectors[1], vectors[2]
    matrix, rhs = velocity_work
    solver = (matrix, rhs, v_old)
    begin(schedule, cursor, clock, q, v, h, jacobian, rate, out)
    for _ in range(steps):
        t0, t1 = clock[2], clock[3]
        if t1 == np.inf:
            return FINISHED
        dt = t1 - t0
        predicted = previous[0] > 0.0
        if predicted:
            if compiled_step_ratio(dt, previous[0]) != ratio:  # a step of another size
                ratio = compiled_step_ratio(dt, previous[0])
                extrapolation(tableau[3], ratio, E)
            if ratio != 1.0:
                compiled_forget(counters)
            extrapolate(E, V, plain)
            compiled_corrected_guess(plain, history, counters, V)
            guess[:] = V
        status, evaluations = stage_step(
            system, tableau, weights, q, momentum, t0, dt, V, lam, (q1, momentum1), work
        )
        cursor[EVALUATIONS] += evaluations
        if status != OK:
            return status
        if predicted:
            compiled_remember(V, plain, guess, history, counters)
        momentum[:] = momentum1
        t2 = next_node(schedule, cursor, clock)
        if m > 0 or wants_output(schedule, cursor, t1, t2 == np.inf):
            # the constraints at the corrected q1 (the last stage's Hessians as scratch)
            evaluate_constraints(system, q1, t1, h, jacobian, rate, stages[9][s - 1])
            v[:] = V[s - 1]
            weight = dt * tableau[2][s - 1]
            status, evaluations = velocity_step(
                system, q1, momentum, t1, weight, (jacobian, rate), linear, v, mu, solver
            )
            cursor[EVALUATIONS] += evaluations
            if status != OK:
                return status
        q[:] = q1
        previous[0] = dt
        arrive(schedule, cursor, clock, t2, q, v, h, jacobian, rate, out)
    return RUNNING
