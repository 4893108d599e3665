"""``simulate(..., method="variational", dt=...)``: a variational integrator (midpoint rule).

The motion is the stationary point of the discrete action sum_k L_d(q_k, q_{k+1}) with the
midpoint discrete Lagrangian of :mod:`lagrangian.simulation.action`,

    L_d(q0, q1) = dt L((q0 + q1)/2, (q1 - q0)/dt, t + dt/2),

under the discrete Lagrange-d'Alembert principle for the forces not in L (applied generalized
forces, forces at points, Rayleigh dissipation -dF/dq_dot, each evaluated at the midpoint) and
with holonomic constraints h(q, t) = 0 held at every step (Marsden & West 2001, sections 3.2
and 3.5).  :mod:`lagrangian.simulation.variational_step` gives the equations of one step
(q_k, p_k) -> (q_{k+1}, p_{k+1}), from p_0 = dL/dq_dot(q_0, q_dot_0, t_0):

    p_k + D1 L_d(q_k, q_{k+1}) + f_d^- + dt/2 A_k^T lambda_k = 0,     h(q_{k+1}, t_{k+1}) = 0,
    p_{k+1} = D2 L_d(q_k, q_{k+1}) + f_d^+ + dt/2 A_{k+1}^T mu_k
            = dL/dq_dot(q_{k+1}, q_dot_{k+1}, t_{k+1}),              A_{k+1} q_dot_{k+1} + h_t = 0.

On a conservative system the map is symplectic and second order: the energy error stays
bounded by O(dt^2) over long runs instead of drifting (RK4's does).  The constraints hold to
the tolerance of Newton's method (about 1e-15) at every step, positions and velocities alike.
q_dot at the outputs is the velocity of the last line (the inverse Legendre map).

The multipliers reported at t_k combine the two halves lambda_k, mu_{k-1} of the constraint
impulse at q_k into a second-order value of lambda(t_k)
(:func:`lagrangian.simulation.variational_march.node_multipliers`); they carry the sign of the
multiplier form, the constraint force being lambda_j dh_j/dq (docs/architecture.md).  An
initial state off the constraints is refused, or projected onto them with
``project_initial=True``, as in the multiplier form
(:mod:`lagrangian.simulation.constrained_start`).

Not integrated (refused with a SimulationError): velocity and unilateral constraints, events,
coordinates without inertia.

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.5}, 10.0, method="variational",
...                       dt=0.01)
>>> trajectory.method, trajectory.drift()["energy_relative"] < 1e-4
('variational', True)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from lagrangian.constraints import multiplier_symbols
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationError, raise_if_problems
from lagrangian.model import Holonomic, System
from lagrangian.model.constraints import label, statement
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics, compile_discrete_mechanics
from lagrangian.simulation.constrained_start import start_on_constraints
from lagrangian.simulation.events import EventFunction
from lagrangian.simulation.inputs import Inputs, resolve_inputs
from lagrangian.simulation.run import trajectory_of
from lagrangian.simulation.stepping import Integration
from lagrangian.simulation.trajectory import Trajectory
from lagrangian.simulation.variational_march import Run, march


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
    project_initial: bool = False,
) -> Trajectory:
    """The body of ``simulate`` for ``method="variational"`` (arguments as collected there)."""
    constraints = _holonomic_constraints(system)
    _require_supported(eom, events)
    compiled = compile_equations(eom)
    mechanics = compile_discrete_mechanics(eom, [c.expression for c in constraints])
    inputs = resolve_inputs(compiled, given, fallback_initial, settings)
    if system is not None and constraints:
        inputs = _on_constraints(system, mechanics, inputs, project_initial)
    grid, outputs = _grid(inputs)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        run = march(mechanics, inputs.x0, inputs.p, grid, outputs, progress)
    trajectory = _trajectory(compiled, inputs, grid, run)
    if constraints:
        names = tuple(s.name for s in multiplier_symbols(len(constraints)))
        trajectory = dataclasses.replace(
            trajectory,
            multipliers=run.multipliers,
            multiplier_names=names,
            constraint_residual=run.constraint_residual,
        )
    if run.failure is not None and raise_on_failure:
        raise SimulationError(
            f"{trajectory.message} Pass raise_on_failure=False to keep the trajectory computed "
            "up to the failure."
        )
    return trajectory


def _holonomic_constraints(system: System | None) -> tuple[Holonomic, ...]:
    """The System's constraints, all holonomic, or raise naming those that are not."""
    if system is None:
        return ()
    problems = [
        Problem(
            label(i, c),
            f"the {c.kind} constraint {statement(c)} is not holonomic; method='variational' "
            "holds holonomic constraints h(q, t) = 0 only",
            "use another method (RK45, DOP853, ...), which integrates it in the multiplier form",
        )
        for i, c in enumerate(system.constraints)
        if not isinstance(c, Holonomic)
    ]
    raise_if_problems(problems, "Cannot integrate variationally", SimulationError)
    return tuple(c for c in system.constraints if isinstance(c, Holonomic))


def _require_supported(eom: EquationsOfMotion, events: Sequence[EventFunction]) -> None:
    if events:
        raise SimulationError(
            "method='variational' does not locate events yet: use another method with events=."
        )
    if any(order != 2 for order in eom.coordinate_orders.values()):
        raise SimulationError(
            "method='variational' needs every coordinate to have inertia (a regular Legendre "
            "map p = dL/dq_dot): use another method."
        )


def _on_constraints(
    system: System, mechanics: DiscreteMechanics, inputs: Inputs, project_initial: bool
) -> Inputs:
    """``inputs`` with an initial state on the constraints (projected when asked), or raise,
    as the multiplier form does."""
    n, t0 = len(mechanics.coordinates), inputs.t_span[0]
    h, c = mechanics.residuals(inputs.x0[:n], inputs.x0[n:], t0, inputs.p)
    residual = float(np.max(np.abs(np.concatenate((h, c))), initial=0.0))
    return start_on_constraints(system, mechanics.coordinates, inputs, residual, project_initial)


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


def _trajectory(
    compiled: CompiledEquations,
    inputs: Inputs,
    grid: np.ndarray,
    run: Run,
) -> Trajectory:
    """The march as a Trajectory, built as every integration's is (:func:`trajectory_of`:
    energies from the state x = [q; q_dot]), with the variational integrator's message."""
    x = np.hstack((run.q, run.q_dot))
    last = x[-1] if len(x) else np.asarray(inputs.x0, dtype=float)
    integration = Integration(grid[run.outputs], x, (), run.failure, run.reached, last, None)
    if run.failure is not None:
        message = f"Integration failed after t = {run.reached:.6g}: {run.failure}."
    else:
        steps = max(int(np.searchsorted(grid, run.reached)), 1)
        message = (
            f"Variational integrator (midpoint rule, dt = {inputs.dt:g}) reached the end of "
            f"the time span ({run.evaluations / steps:.3g} evaluations of the discrete "
            "equations per step)."
        )
    trajectory = trajectory_of(compiled, inputs, integration, None)
    return dataclasses.replace(trajectory, message=message)
