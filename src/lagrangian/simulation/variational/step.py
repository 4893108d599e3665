"""One step of the variational integrator: the forced, constrained discrete Euler-Lagrange
equations in position-momentum form, solved by Newton's method with their exact Jacobian.

With the midpoint discrete Lagrangian L_d(q0, q1) = dt L(q_m, v_m, t_m) (q_m = (q0 + q1)/2,
v_m = (q1 - q0)/dt, t_m = t0 + dt/2), the midpoint discrete forces f_d^- = f_d^+ =
dt/2 Q(q_m, v_m, t_m) (Q the applied and dissipative forces not in L) and holonomic constraints
h(q, t) = 0 with A = dh/dq, a step (q0, p0) -> (q1, p1) is

    position:  p0 + D1 L_d(q0, q1) + f_d^- + dt/2 A(q0, t0)^T lambda = 0,  h(q1, t1) = 0,
    momentum:  p1 = D2 L_d(q0, q1) + f_d^+ + dt/2 A(q1, t1)^T mu,
    velocity:  p1 = dL/dq_dot(q1, v1, t1),  A(q1, t1) v1 + dh/dt(q1, t1) = 0,

with D1 L_d = dt/2 L_q - L_v and D2 L_d = dt/2 L_q + L_v at the midpoint.  The first line
solves for (q1, lambda), the last two for (v1, mu).  This is the discrete Lagrange-d'Alembert
principle (Marsden & West 2001, Acta Numerica 10, section 3.2: the forced discrete
Euler-Lagrange equations and their position-momentum form) with the constraint forces
lambda_j dh_j/dq split between the two ends of the step, the symmetric choice that makes the
discrete momentum satisfy the hidden constraint A v + dh/dt = 0 (Marsden & West, section 3.5,
constrained systems; for L = q_dot^T M q_dot / 2 - V it is RATTLE, Hairer, Lubich & Wanner,
Geometric Numerical Integration, section VII.1).  lambda and mu carry the sign of the
multiplier form: the constraint force is lambda_j dh_j/dq (docs/architecture.md).

The Jacobian of the position equations in q1 is

    dt/4 (L_qq + Q_q) + (L_qv - L_qv^T)/2 + Q_v/2 - L_vv/dt,

bordered by dt/2 A(q0)^T and A(q1); that of the velocity equations is [[L_vv, -dt/2 A^T],
[A, 0]], exact after one step when L is quadratic in the velocities.  The iteration ends with
a correction below SMALL_CORRECTION of q1 whose residual was within RESIDUAL_GUARD of its
terms: the corrected q1 is exact to rounding (its error is of the correction's square), and
so is its momentum D2 L_d + f_d^+, moved from the last evaluation by its Jacobian in q1,

    dt/4 (L_qq + Q_q) + (L_qv + L_qv^T + Q_v)/2 + L_vv/dt,

so that a step of a smooth motion evaluates the terms twice.

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> p, no_rows = np.array([1.0, 9.81, 1.0]), np.zeros((0, 1))
>>> position = position_step(mechanics, np.array([0.0]), np.array([1.0]), 0.0, 0.01, p,
...                          no_rows, np.array([0.01]), np.zeros(0))
>>> velocity = velocity_step(mechanics, position.q, position.momentum, 0.01, 0.005, p,
...                          no_rows, np.zeros(0), np.array([1.0]))
>>> round(float(position.q[0]), 6), round(float(velocity.v[0]), 4)  # exact 0.009998, 0.9995
(0.009998, 0.9995)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.linalg.lapack import dgesv, dgetrf, dgetrs

from lagrangian.errors import SimulationError
from lagrangian.numerics.discrete_lagrangian import (
    MAX_ITERATIONS,
    RESIDUAL_GUARD,
    SMALL_CORRECTION,
    DiscreteMechanics,
)


class PositionSolution(NamedTuple):
    """(q1, lambda) of the position equations, with what the next parts of the step reuse.

    ``momentum`` is D2 L_d(q0, q1) + f_d^+ (p1 before the constraint impulse of mu);
    ``h``, ``jacobian`` and ``rate`` are h, A and dh/dt at (q1, t1); ``evaluations`` counts
    the evaluations of the midpoint terms (one per Newton correction).
    """

    q: np.ndarray
    multipliers: np.ndarray
    momentum: np.ndarray
    h: np.ndarray
    jacobian: np.ndarray
    rate: np.ndarray
    evaluations: int


class VelocitySolution(NamedTuple):
    """(v1, mu) of the velocity equations, the momentum p1 = D2 L_d + f_d^+ + dt/2 A^T mu, and
    the number of evaluations of the Legendre map it took."""

    v: np.ndarray
    multipliers: np.ndarray
    momentum: np.ndarray
    evaluations: int


def position_step(
    mechanics: DiscreteMechanics,
    q0: np.ndarray,
    p0: np.ndarray,
    t0: float,
    dt: float,
    parameters: np.ndarray,
    jacobian0: np.ndarray,
    q1: np.ndarray,
    multipliers: np.ndarray,
) -> PositionSolution:
    """Solve p0 + D1 L_d(q0, q1) + f_d^- + dt/2 A(q0)^T lambda = 0, h(q1, t0 + dt) = 0 for
    (q1, lambda) by Newton's method from the guesses ``q1``, ``multipliers``; ``jacobian0`` is
    A(q0, t0).  Raises SimulationError when Newton's method does not converge."""
    n, m = len(q0), len(multipliers)
    t_mid, t1 = t0 + dt / 2, t0 + dt
    z = np.concatenate((q1, multipliers))
    matrix = np.zeros((n + m, n + m))
    matrix[:n, n:] = dt / 2 * jacobian0.T
    for iteration in range(MAX_ITERATIONS + 1):
        q1, lam = z[:n], z[n:]
        L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v = mechanics.midpoint(
            (q0 + q1) / 2, (q1 - q0) / dt, t_mid, parameters
        )
        h, a1, rate = mechanics.constraints(q1, t1, parameters)
        force = dt / 2 * (L_q + Q)
        impulse = matrix[:n, n:] @ lam
        momentum_rows = p0 + force - L_v + impulse
        converging = acceptable(momentum_rows, (p0, force, L_v, impulse), h, a1, q1, q0)
        matrix[:n, :n] = dt / 4 * (L_qq + Q_q) + (L_qv - L_qv.T + Q_v) / 2 - L_vv / dt
        matrix[n:, :n] = a1
        correction = solve_correction(matrix, np.concatenate((momentum_rows, h)), "position")
        z = z - correction
        if converging and small_correction(correction[:n], q1, q0):
            # the momentum at the corrected q1 from its Jacobian there: exact to rounding
            slope = dt / 4 * (L_qq + Q_q) + (L_qv + L_qv.T + Q_v) / 2 + L_vv / dt
            momentum = force + L_v - slope @ correction[:n]
            h, a1, rate = mechanics.constraints(z[:n], t1, parameters)
            return PositionSolution(z[:n], z[n:], momentum, h, a1, rate, iteration + 1)
    raise SimulationError(not_converged("position", t0))


def velocity_step(
    mechanics: DiscreteMechanics,
    q1: np.ndarray,
    momentum: np.ndarray,
    t1: float,
    weight: float,
    parameters: np.ndarray,
    jacobian1: np.ndarray,
    rate1: np.ndarray,
    v: np.ndarray,
) -> VelocitySolution:
    """Solve dL/dq_dot(q1, v1, t1) = momentum + weight A1^T mu, A1 v1 + dh/dt = 0 for
    (v1, mu) from the guess ``v``; ``weight`` is the share of the step's constraint impulse
    at its end (dt/2 for the midpoint rule), ``jacobian1``, ``rate1`` are A and dh/dt at
    (q1, t1).  With no constraints this inverts the Legendre map.  Raises SimulationError
    when it fails."""
    n, m = len(q1), len(rate1)
    matrix = np.zeros((n + m, n + m))
    matrix[:n, n:], matrix[n:, :n] = -weight * jacobian1.T, jacobian1
    z = np.concatenate((v, np.zeros(m)))
    small = False
    for iteration in range(MAX_ITERATIONS + 1):
        v, mu = z[:n], z[n:]
        L_v, L_vv = mechanics.legendre(q1, v, t1, parameters)
        impulse = matrix[:n, n:] @ mu
        momentum_rows = L_v - momentum + impulse
        if small and acceptable(momentum_rows, (L_v, momentum), np.zeros(0), jacobian1, v, v):
            return VelocitySolution(v, mu, momentum - impulse, iteration + 1)
        matrix[:n, :n] = L_vv
        residual = np.concatenate((momentum_rows, jacobian1 @ v + rate1))
        correction = solve_correction(matrix, residual, "velocity")
        z = z - correction
        if mechanics.legendre_linear:  # the equations are linear in (v1, mu): solved exactly
            return VelocitySolution(z[:n], z[n:], momentum - matrix[:n, n:] @ z[n:], 1)
        small = small_correction(correction[:n], z[:n], v)
    raise SimulationError(not_converged("velocity", t1))


def not_converged(which: str, t: float) -> str:
    """The message of a Newton iteration that did not converge: of the ``"position"``
    equations of the step from t, or of the ``"velocity"`` (the Legendre map) at t."""
    if which == "velocity":
        return (
            f"Newton's method for the velocity at t = {t:.6g} from the discrete momentum (the "
            f"Legendre map) did not converge in {MAX_ITERATIONS} iterations: try a smaller dt"
        )
    return (
        f"Newton's method for the discrete Euler-Lagrange equations did not converge in "
        f"{MAX_ITERATIONS} iterations from t = {t:.6g}: try a smaller dt"
    )


def singular(which: str) -> str:
    """The message of a singular Jacobian of the ``"position"`` or ``"velocity"``
    equations."""
    return (
        f"the Jacobian of the discrete {which} equations is singular (a coordinate "
        "singularity, dependent constraints, or a coordinate without inertia); try a "
        "smaller dt"
    )


def solve_correction(matrix: np.ndarray, residual: np.ndarray, which: str) -> np.ndarray:
    """matrix^-1 residual by LAPACK's dgesv (a fifth of numpy.linalg.solve's overhead);
    SimulationError (:func:`singular`) when the matrix is singular."""
    *_, solution, info = dgesv(matrix, residual)
    if info != 0 or not np.isfinite(solution).all():
        raise SimulationError(singular(which))
    return solution


def factor_correction(matrix: np.ndarray, which: str) -> tuple[np.ndarray, np.ndarray]:
    """The LU factors of ``matrix`` with partial pivoting (LAPACK's dgetrf), for
    :func:`solve_factored`; SimulationError (:func:`singular`) when the matrix is singular."""
    lu, pivots, info = dgetrf(matrix)
    if info != 0:
        raise SimulationError(singular(which))
    return lu, pivots


def solve_factored(
    factors: tuple[np.ndarray, np.ndarray], residual: np.ndarray, which: str
) -> np.ndarray:
    """matrix^-1 residual from the ``factors`` of :func:`factor_correction` (LAPACK's
    dgetrs); SimulationError (:func:`singular`) when the solution is not finite."""
    solution, info = dgetrs(*factors, residual)
    if info != 0 or not np.isfinite(solution).all():
        raise SimulationError(singular(which))
    return solution


def small_correction(correction: np.ndarray, q1: np.ndarray, q0: np.ndarray) -> bool:
    """Whether a Newton correction of q1 is below SMALL_CORRECTION of the size of q1 and of
    its change from q0 (False for NaN)."""
    size = max(np.abs(q1).max(), np.abs(q1 - q0).max())
    return bool(np.abs(correction).max() <= SMALL_CORRECTION * (size or 1.0))


def acceptable(
    momentum_rows: np.ndarray,
    terms: tuple[np.ndarray, ...],
    h: np.ndarray,
    jacobian: np.ndarray,
    q1: np.ndarray,
    q0: np.ndarray,
) -> bool:
    """Whether the residual is finite and small against its terms: the momentum rows against
    the largest term they add up, the constraints against |A| (|q1| + |q1 - q0|), the size of
    their terms for a quadratic h (False for NaN)."""
    size = max(np.abs(term).max() for term in terms)
    if not np.abs(momentum_rows).max() <= RESIDUAL_GUARD * (size or 1.0):
        return False
    if not len(h):
        return True
    reach = np.abs(jacobian).max() * (np.abs(q1).max() + np.abs(q1 - q0).max())
    return bool(np.abs(h).max() <= RESIDUAL_GUARD * (reach or 1.0))
