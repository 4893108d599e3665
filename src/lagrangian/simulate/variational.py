"""``simulate(..., method="variational", dt=...)``: a variational integrator (midpoint rule).

With the midpoint discrete Lagrangian of :mod:`lagrangian.simulate.action`,

    L_d(q0, q1) = h L((q0 + q1)/2, (q1 - q0)/h, t + h/2),

the position-momentum form of the discrete Euler-Lagrange equations (Marsden & West 2001)
advances (q_k, p_k) by

    p_k = -D1 L_d(q_k, q_{k+1})    solved for q_{k+1} (scipy.optimize.root, hybr),
    p_{k+1} = D2 L_d(q_k, q_{k+1}),

from p_0 = dL/dq_dot(q_0, q_dot_0, t_0).  The map is symplectic and second order: on a
conservative system the energy error stays bounded by O(dt^2) over long runs instead of
drifting (RK4's does).  q_dot at the samples comes from the Legendre map p = dL/dq_dot, solved
by Newton's method with the mass matrix (one exact step when L is quadratic in q_dot); where that
does not converge, the central difference (q_{k+1} - q_{k-1}) / (t_{k+1} - t_{k-1}) is used.

Only unconstrained conservative systems: dissipation or applied generalized forces (refused when
their expressions are not identically zero, whatever the parameter values) need the forced
discrete equations, and constraints the constrained ones, neither implemented yet.

>>> import lagrangian as lg
>>> from lagrangian.simulate import simulate
>>> trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.5}, 10.0, method="variational",
...                       dt=0.01)
>>> trajectory.method, trajectory.drift()["energy_relative"] < 1e-4
('variational', True)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import sympy as sp
from scipy.optimize import root

from lagrangian.derive import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.simulate.discrete import LagrangianFunctions, prepare, residual_converged
from lagrangian.simulate.events import EventFunction
from lagrangian.simulate.inputs import VARIATIONAL, Inputs, resolve_inputs
from lagrangian.simulate.trajectory import Trajectory


def simulate_variational(
    eom: EquationsOfMotion,
    system: System | None,
    given: Mapping[str, Any],
    fallback_initial: Mapping[Any, float],
    settings: Mapping[str, Any],
    *,
    events: Sequence[EventFunction] = (),
    raise_on_failure: bool = True,
    progress: Callable[[float], None] | None = None,
) -> Trajectory:
    """The body of ``simulate`` for ``method="variational"`` (arguments as collected there)."""
    _require_supported(eom, system, events)
    compiled, functions = prepare(eom)
    inputs = resolve_inputs(compiled, given, fallback_initial, settings)
    grid, outputs = _grid(inputs)
    n, p = len(compiled.coordinates), inputs.p
    q = np.empty((len(grid), n))
    q[0] = inputs.x0[:n]
    slope = inputs.x0[n:]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        momentum = functions.dL_dq_dot(q[0], slope, grid[0], p)
        reached, failure = 0, None
        for k in range(len(grid) - 1):
            h = float(grid[k + 1] - grid[k])
            try:
                q[k + 1], momentum = _step(functions, q[k], momentum, slope, grid[k], h, p)
            except SimulationError as error:
                failure = str(error)
                break
            slope = (q[k + 1] - q[k]) / h
            reached = k + 1
            if progress is not None:
                progress(float(grid[k + 1]))
        outputs = outputs[outputs <= reached]
        q_dot = _velocities(compiled, functions, grid[: reached + 1], q[: reached + 1], outputs, p)
    trajectory = _trajectory(compiled, inputs, grid[outputs], q[outputs], q_dot, failure)
    if failure is not None and raise_on_failure:
        raise SimulationError(
            f"{trajectory.message} Pass raise_on_failure=False to keep the trajectory computed "
            "up to the failure."
        )
    return trajectory


def _require_supported(
    eom: EquationsOfMotion, system: System | None, events: Sequence[EventFunction]
) -> None:
    if system is not None and system.constraints:
        raise SimulationError(
            "Variational integration of constrained systems is not implemented yet: use "
            "another method (RK45, DOP853, ...)."
        )
    if events:
        raise SimulationError(
            "method='variational' does not locate events yet: use another method with events=."
        )
    if any(order != 2 for order in eom.coordinate_orders.values()):
        raise SimulationError(
            "method='variational' needs every coordinate to have inertia (a regular Legendre "
            "map p = dL/dq_dot): use another method."
        )
    kinds = []
    if sp.simplify(eom.dissipation_function) != 0:
        kinds.append("dissipation (a Rayleigh function, dampers or resistors)")
    if any(sp.simplify(force) != 0 for force in eom.generalized_forces):
        kinds.append("applied generalized forces")
    if kinds:
        raise SimulationError(
            f"method='variational' integrates conservative systems only, and this one has "
            f"{' and '.join(kinds)}: the forced discrete Euler-Lagrange equations are not "
            "implemented yet. Use another method (RK45, DOP853, RK4, ...)."
        )


def _grid(inputs: Inputs) -> tuple[np.ndarray, np.ndarray]:
    """The step times (steps of dt, a shorter last one, plus every output time) and the indices
    of the output times in them (every step when no output times are asked for)."""
    t0, t1 = inputs.t_span
    dt = float(inputs.dt or t1 - t0)
    count = max(int(np.ceil((t1 - t0) / dt - 1e-9)), 1)
    grid = np.minimum(t0 + dt * np.arange(count + 1), t1)
    grid[-1] = t1
    if inputs.t_out is None:
        return grid, np.arange(len(grid))
    grid = np.union1d(grid, inputs.t_out)
    grid = grid[np.concatenate(([True], np.diff(grid) > 1e-9 * dt))]
    outputs = np.searchsorted(grid, inputs.t_out - 1e-9 * dt)
    return grid, np.clip(outputs, 0, len(grid) - 1)


def _step(
    functions: LagrangianFunctions,
    q0: np.ndarray,
    momentum: np.ndarray,
    slope: np.ndarray,
    t: float,
    h: float,
    p: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """(q_{k+1}, p_{k+1}) from (q_k, p_k): p_k = -D1 L_d(q_k, q_{k+1}), p_{k+1} = D2 L_d."""
    midpoint_time = t + h / 2

    def derivatives(q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        midpoint, velocity = (q0 + q1) / 2, (q1 - q0) / h
        return (
            functions.dL_dq(midpoint, velocity, midpoint_time, p),
            functions.dL_dq_dot(midpoint, velocity, midpoint_time, p),
        )

    def terms(q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The two parts of p_k + D1 L_d(q_k, q1) = (p_k + h/2 dL/dq) - dL/dq_dot."""
        dq, dv = derivatives(q1)
        return momentum + h / 2 * dq, -dv

    solution = root(lambda q1: np.add(*terms(q1)), q0 + h * slope, method="hybr")
    converged, worst = residual_converged(terms(solution.x))
    if not (converged or (solution.success and np.isfinite(worst))):
        raise SimulationError(
            f"the discrete Euler-Lagrange equation has no solution near q_k + dt q_dot_k "
            f"({solution.message}; residual {worst:.3g}); try a smaller dt"
        )
    dq, dv = derivatives(solution.x)
    return solution.x, h / 2 * dq + dv


def _velocities(
    compiled: CompiledEquations,
    functions: LagrangianFunctions,
    t: np.ndarray,
    q: np.ndarray,
    outputs: np.ndarray,
    p: np.ndarray,
) -> np.ndarray:
    """q_dot at the output samples from the Legendre map p_k = dL/dq_dot(q_k, q_dot_k, t_k).

    p_k is recomputed from the neighbouring steps (D2 L_d of the step before, -D1 L_d of the
    one after; equal up to the solver's tolerance); Newton's method with the mass matrix as the
    Jacobian starts from the central difference, which is kept where Newton does not converge.
    """
    if len(t) < 2:
        return np.zeros((len(outputs), q.shape[1]))
    h = np.diff(t)
    midpoints, slopes = (q[1:] + q[:-1]) / 2, np.diff(q, axis=0) / h[:, None]
    mid_times = t[:-1] + h / 2
    dq = functions.dL_dq(midpoints, slopes, mid_times, p)
    dv = functions.dL_dq_dot(midpoints, slopes, mid_times, p)
    after = -(h[:, None] / 2 * dq - dv)  # -D1 L_d of step k, the momentum at its start
    before = h[:, None] / 2 * dq + dv  # D2 L_d of step k, the momentum at its end
    momenta = np.vstack((after[:1], before))
    central = np.gradient(q, t, axis=0, edge_order=2 if len(t) > 2 else 1)
    q_dot = central[outputs].copy()
    for row, k in enumerate(outputs):
        guess = q_dot[row]
        for _ in range(20):
            residual = momenta[k] - functions.dL_dq_dot(q[k], guess, t[k], p)
            if not np.all(np.isfinite(residual)):
                break
            if np.max(np.abs(residual)) <= 1e-12 * max(np.max(np.abs(momenta[k])), 1.0):
                q_dot[row] = guess
                break
            mass = compiled.mass_matrix(q[k], t[k], p, qd=guess)
            try:
                guess = guess + np.linalg.solve(mass, residual)
            except np.linalg.LinAlgError:
                break
    return q_dot


def _trajectory(
    compiled: CompiledEquations,
    inputs: Inputs,
    t: np.ndarray,
    q: np.ndarray,
    q_dot: np.ndarray,
    failure: str | None,
) -> Trajectory:
    p = inputs.p
    energy_function = None
    if compiled.energy_function_differs:
        energy_function = compiled.energy_function(q, q_dot, t, p) if len(t) else np.zeros(0)
    if failure is not None:
        message = f"Integration failed after t = {t[-1]:.6g}: {failure}."
    else:
        message = (
            f"Variational integrator (midpoint rule, dt = {inputs.dt:g}) reached the end of "
            "the time span."
        )
    return Trajectory(
        t=t,
        q=q,
        q_dot=q_dot,
        coordinates=compiled.coordinates,
        energy=compiled.energy(q, q_dot, t, p) if len(t) else np.zeros(0),
        energy_function=energy_function,
        status="failed" if failure is not None else "success",
        message=message,
        method=VARIATIONAL,
        parameters=inputs.parameters,
    )
