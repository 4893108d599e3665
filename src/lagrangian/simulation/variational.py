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
(:func:`lagrangian.simulation.dynamics.start_on_constraints`).

Not integrated (refused by :class:`lagrangian.simulation.options.Options`): velocity and
unilateral constraints, events, coordinates without inertia.

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.5}, 10.0, method="variational",
...                       dt=0.01)
>>> trajectory.method, trajectory.drift()["energy_relative"] < 1e-4
('variational', True)
"""

from __future__ import annotations

import dataclasses

import numpy as np

from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.simulation.dynamics import ConstrainedMotion
from lagrangian.simulation.events import EventWatch
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integration import Integration, Progress
from lagrangian.simulation.variational_march import march


@dataclasses.dataclass(frozen=True)
class DiscreteDynamics(ConstrainedMotion[DiscreteMechanics]):
    """The formulation the variational integrator steps: the compiled discrete mechanics of
    the midpoint rule with the holonomic constraints, at the parameters p (x = [q; q_dot])."""

    multiplier_names: tuple[str, ...] = ()

    def constraint_rows(self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray) -> None:
        return None  # the march computes them on the way (Integration.multipliers)


@dataclasses.dataclass(frozen=True)
class VariationalIntegrator:
    """The midpoint-rule variational integrator over the grid of :func:`step_grid`."""

    def run(
        self,
        dynamics: DiscreteDynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        grid, outputs = step_grid(inputs)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            run = march(dynamics.form, inputs.x0, inputs.p, grid, outputs, progress)
        x = np.hstack((run.q, run.q_dot))
        steps = max(int(np.searchsorted(grid, run.reached)), 1)
        constrained = bool(dynamics.multiplier_names)
        return Integration(
            t=grid[run.outputs],
            x=x,
            t_reached=run.reached,
            x_reached=x[-1] if len(x) else np.asarray(inputs.x0, dtype=float),
            failure=run.failure,
            interrupted=run.interrupted,
            multipliers=run.multipliers if constrained else None,
            constraint_residual=run.constraint_residual if constrained else None,
            note=(
                f"Variational integrator (midpoint rule, dt = {inputs.dt:g}) reached the end of "
                f"the time span ({run.evaluations / steps:.3g} evaluations of the discrete "
                "equations per step)."
            ),
        )


def step_grid(inputs: Inputs) -> tuple[np.ndarray, np.ndarray]:
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
