"""One step of the collocation integrators in NumPy: the stage equations of
:mod:`lagrangian.simulation.variational.collocation` solved by simplified Newton iterations,
their exact Jacobian factored at the first iterate and kept while the iteration contracts as
Newton's does (:mod:`lagrangian.numerics.stage_newton`).

The unknowns are the stage velocities V_1..V_s and, with constraints (the Lobatto pair), the
scaled multipliers h Lambda_1..h Lambda_{s-1}; the equations are the momenta at every stage
and, divided by h, the constraints at stages 2..s:

    r_i = dL/dq_dot(Q_i, V_i, t_i) - p0 - h sum_j a_hat_ij (F_j + A_j^T Lambda_j) = 0,
    g_i = h(Q_i, t_i) / h = 0.

With K_j = L_qq + Q_q + sum_l Lambda_jl d2h_l/dq2 at stage j, the Jacobian is

    dr_i/dV_k = delta_ik L_vv(i) + h a_ik L_qv(i)^T - h a_hat_ik (L_qv + Q_v)(k)
                - h^2 sum_j a_hat_ij a_jk K_j,
    dr_i/d(h Lambda_k) = -a_hat_ik A_k^T,      dg_i/dV_k = a_ik A_i,

((L_qv)_ab = d2L/dq_a dv_b).  The scaling keeps both blocks of size 1 as h shrinks.  The
iteration stops as the midpoint rule's does (:mod:`lagrangian.simulation.variational.step`):
with a correction of the stage positions below SMALL_CORRECTION of their size whose residual
was within RESIDUAL_GUARD of its terms (and the constraints within it of |A| |Q|), and, after
a reused Jacobian, with the error its rate of contraction leaves below rounding
(:func:`lagrangian.numerics.stage_newton.settled`).  Before a correction by the Jacobian at
the same iterate (Newton's step, which leaves a residual of the square of the one before it)
the momentum rows are taken against NEWTON_RESIDUAL_GUARD = RESIDUAL_GUARD^(1/2) instead
(:mod:`lagrangian.numerics.stage_prediction`).  The corrected stages are then exact to
rounding, and so are the forces at them, moved from the last evaluation by their Jacobian,

    F_j + A_j^T Lambda_j  <-  F_j - (L_qv + Q_v)(j) dV_j - h K_j sum_k a_jk dV_k + A_j^T Lambda_j

(Lambda corrected): a step of a smooth motion evaluates the stages twice, not three times,
and once where its guess (:mod:`lagrangian.numerics.stage_prediction`) is within
SMALL_CORRECTION already.

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> from lagrangian.simulation.variational.collocation import gauss
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> stage = stage_step(mechanics, gauss(2), np.array([0.0]), np.array([1.0]), 0.0, 0.1,
...                    np.array([1.0, 9.81, 1.0]), np.ones((2, 1)), np.zeros((0, 0)))
>>> # a small swing from theta = 0 at unit speed: near sin(w dt)/w, cos(w dt), w = sqrt(g/l)
>>> round(float(stage.q[0]), 6), round(float(stage.momentum[0]), 6)
(0.098373, 0.95139)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.discrete_lagrangian import (
    MAX_ITERATIONS,
    RESIDUAL_GUARD,
    SMALL_CORRECTION,
    DiscreteMechanics,
)
from lagrangian.numerics.stage_newton import REFRESH_RATE, settled
from lagrangian.numerics.stage_prediction import NEWTON_RESIDUAL_GUARD
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.step import factor_correction, not_converged, solve_factored


class StageSolution(NamedTuple):
    """The solved stages: V (s, n), the multipliers Lambda_1..Lambda_{s-1} (s-1, m; (0, m)
    without the Lobatto pair), q1, the momentum p0 + h sum b_i (F_i + A_i^T Lambda_i) before
    the impulse of Lambda_s, h, A and dh/dt at the last stage (q1, t1 for the Lobatto pair),
    and the number of stage evaluations."""

    V: np.ndarray
    multipliers: np.ndarray
    q: np.ndarray
    momentum: np.ndarray
    h: np.ndarray
    jacobian: np.ndarray
    rate: np.ndarray
    evaluations: int


class _Stages(NamedTuple):
    """The terms at every stage: Q, F = L_q + Q_f, L_v, L_qv, L_qv + Q_v, L_vv, L_qq + Q_q
    ((s, n) and (s, n, n)), h, A, Hessians ((s, m), (s, m, n), (s, m, n, n)), dh/dt."""

    Q: np.ndarray
    F: np.ndarray
    L_v: np.ndarray
    L_qv: np.ndarray
    F_v: np.ndarray
    L_vv: np.ndarray
    F_q: np.ndarray
    h: np.ndarray
    A: np.ndarray
    H: np.ndarray
    rate: np.ndarray


def stage_step(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    q0: np.ndarray,
    p0: np.ndarray,
    t0: float,
    dt: float,
    parameters: np.ndarray,
    V: np.ndarray,
    multipliers: np.ndarray,
) -> StageSolution:
    """Solve the stage equations (module docstring) of the step of size ``dt`` from
    (q0, p0, t0), from the guesses ``V`` (s, n) and ``multipliers`` (s-1, m, or (0, m)).
    Raises SimulationError when Newton's method fails."""
    s, n, m = tableau.stages, len(q0), mechanics.constraint_count
    r = s - 1 if tableau.lobatto and m else 0
    V, lam = V.astype(float), multipliers.astype(float).reshape(r, m)
    factors, rate, last = None, 0.0, 0.0  # the Jacobian's LU, made at the first iterate
    for iteration in range(MAX_ITERATIONS + 1):
        stages = _evaluate(mechanics, tableau, q0, t0, dt, parameters, V)
        forces = stages.F.copy()
        forces[:r] += np.einsum("jmn,jm->jn", stages.A[:r], lam)
        pushed = dt * tableau.a_hat @ forces
        rows = stages.L_v - p0 - pushed
        g = stages.h[1 : r + 1] / dt
        fresh = factors is None
        guard = NEWTON_RESIDUAL_GUARD if fresh else RESIDUAL_GUARD
        converging = _acceptable(rows, (stages.L_v, p0, pushed), guard, g, stages, q0, r)
        K = _hessians(stages, lam, r)
        if factors is None:
            factors = factor_correction(_jacobian(tableau, dt, stages, K, lam, r), "position")
        residual = np.concatenate((rows.ravel(), g.ravel()))
        correction = solve_factored(factors, residual, "position")
        size = max(np.abs(stages.Q).max(), np.abs(stages.Q - q0).max())
        dV = correction[: s * n].reshape(s, n)
        V = V - dV
        lam = lam - correction[s * n :].reshape(r, m) / dt
        change = dt * float(np.abs(dV).max())
        rate = 0.0 if fresh else change / last if last else 0.0
        if (
            converging
            and change <= SMALL_CORRECTION * (size or 1.0)
            and settled(rate, change, size)
        ):
            # the forces at the corrected stages from their Jacobian: exact to rounding
            forces = stages.F - np.einsum("jab,jb->ja", stages.F_v, dV)
            forces -= dt * np.einsum("jab,jb->ja", K, tableau.a @ dV)
            forces[:r] += np.einsum("jmn,jm->jn", stages.A[:r], lam)
            q1 = q0 + dt * tableau.b @ V  # the last stage of the Lobatto pair (a_s = b)
            momentum = p0 + dt * tableau.b @ forces
            last_constraints = mechanics.constraints(q1, t0 + dt, parameters)
            return StageSolution(V, lam, q1, momentum, *last_constraints, (iteration + 1) * s)
        if not rate <= REFRESH_RATE:  # Newton's rate lost: a new Jacobian at the next iterate
            factors = None
        last = change
    raise SimulationError(not_converged("position", t0))


def _evaluate(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    q0: np.ndarray,
    t0: float,
    dt: float,
    parameters: np.ndarray,
    V: np.ndarray,
) -> _Stages:
    """The terms at the stages Q_i = q0 + dt sum_j a_ij V_j, t_i = t0 + c_i dt."""
    Q = q0 + dt * tableau.a @ V
    times = t0 + tableau.c * dt
    terms = [mechanics.midpoint(Qi, Vi, ti, parameters) for Qi, Vi, ti in zip(Q, V, times)]
    L_q, L_v, Q_f, L_qq, L_qv, L_vv, Q_q, Q_v = (np.array(column) for column in zip(*terms))
    constraints = [mechanics.constraints(Qi, ti, parameters) for Qi, ti in zip(Q, times)]
    h, A, rate = (np.array(column) for column in zip(*constraints))
    H = np.array([mechanics.constraint_hessians(Qi, ti, parameters) for Qi, ti in zip(Q, times)])
    return _Stages(Q, L_q + Q_f, L_v, L_qv, L_qv + Q_v, L_vv, L_qq + Q_q, h, A, H, rate)


def _hessians(stages: _Stages, lam: np.ndarray, r: int) -> np.ndarray:
    """K_j = L_qq + Q_q + sum_l Lambda_jl d2h_l/dq2 at every stage j."""
    K = stages.F_q.copy()
    K[:r] += np.einsum("jm,jmab->jab", lam, stages.H[:r])
    return K


def _jacobian(
    tableau: Tableau, dt: float, stages: _Stages, K: np.ndarray, lam: np.ndarray, r: int
) -> np.ndarray:
    """The Jacobian of the stage equations in (V, dt Lambda) (module docstring), K of
    :func:`_hessians`."""
    a, a_hat = tableau.a, tableau.a_hat
    s, n = stages.Q.shape
    m = lam.shape[1]
    velocity = (
        np.einsum("ik,iab->ikab", np.eye(s), stages.L_vv)
        + dt * np.einsum("ik,iba->ikab", a, stages.L_qv)
        - dt * np.einsum("ik,kab->ikab", a_hat, stages.F_v)
        - dt**2 * np.einsum("ij,jk,jab->ikab", a_hat, a, K)
    )
    matrix = np.zeros((s * n + r * m, s * n + r * m))
    matrix[: s * n, : s * n] = velocity.transpose(0, 2, 1, 3).reshape(s * n, s * n)
    if r:
        impulse = -np.einsum("ik,kmb->ibkm", a_hat[:, :r], stages.A[:r])
        matrix[: s * n, s * n :] = impulse.reshape(s * n, r * m)
        drift = np.einsum("ik,imb->imkb", a[1 : r + 1], stages.A[1 : r + 1])
        matrix[s * n :, : s * n] = drift.reshape(r * m, s * n)
    return matrix


def _acceptable(
    rows: np.ndarray,
    terms: tuple[np.ndarray, ...],
    guard: float,
    g: np.ndarray,
    stages: _Stages,
    q0: np.ndarray,
    r: int,
) -> bool:
    """Whether the momentum rows are within ``guard`` of their terms and the constraints
    within RESIDUAL_GUARD of |A| (|Q| + |Q - q0|) (False for NaN)."""
    size = max(float(np.abs(term).max()) for term in terms)
    if not np.abs(rows).max() <= guard * (size or 1.0):
        return False
    if not r:
        return True
    Q = stages.Q[1 : r + 1]
    reach = np.abs(stages.A[1 : r + 1]).max() * (np.abs(Q).max() + np.abs(Q - q0).max())
    dt_g = np.abs(stages.h[1 : r + 1]).max()
    return bool(dt_g <= RESIDUAL_GUARD * (reach or 1.0))
