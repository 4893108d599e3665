"""``simulate(..., method="variational", dt=...)``: a variational integrator (midpoint rule).

The motion is the stationary point of the discrete action sum_k L_d(q_k, q_{k+1}) with the
midpoint discrete Lagrangian of :mod:`lagrangian.simulation.variational.action`,

    L_d(q0, q1) = dt L((q0 + q1)/2, (q1 - q0)/dt, t + dt/2),

under the discrete Lagrange-d'Alembert principle for the forces not in L (applied generalized
forces, forces at points, Rayleigh dissipation -dF/dq_dot, each evaluated at the midpoint) and
with holonomic constraints h(q, t) = 0 held at every step (Marsden & West 2001, sections 3.2
and 3.5).  :mod:`lagrangian.simulation.variational.step` gives the equations of one step
(q_k, p_k) -> (q_{k+1}, p_{k+1}), from p_0 = dL/dq_dot(q_0, q_dot_0, t_0):

    p_k + D1 L_d(q_k, q_{k+1}) + f_d^- + dt/2 A_k^T lambda_k = 0,     h(q_{k+1}, t_{k+1}) = 0,
    p_{k+1} = D2 L_d(q_k, q_{k+1}) + f_d^+ + dt/2 A_{k+1}^T mu_k
            = dL/dq_dot(q_{k+1}, q_dot_{k+1}, t_{k+1}),              A_{k+1} q_dot_{k+1} + h_t = 0.

On a conservative system the map is symplectic and second order: the energy error stays
bounded by O(dt^2) over long runs instead of drifting (RK4's does).  The constraints hold to
the tolerance of Newton's method (about 1e-15) at every step, positions and velocities alike.
q_dot at the outputs is the velocity of the last line (the inverse Legendre map).

Where numba is installed (``pip install lagrangian[fast]``) the steps run in a loop compiled
once per machine, calling the system's terms compiled by SymEngine's LLVM backend
(:mod:`lagrangian.simulation.variational.compiled`: the same iterations, the same trajectory to
rounding, about 200 times faster for a double pendulum); otherwise, or where the terms cannot
be compiled, in NumPy, stepped by the one Python loop with the step and wall-time budget
(:mod:`lagrangian.simulation.variational.stepper`).  The same integrator runs the symplectic
collocation methods of order 4 and 6, ``method="gauss4"`` and ``"gauss6"``
(:mod:`lagrangian.simulation.variational.collocation`), on the same discrete mechanics.

The multipliers reported at t_k combine the two halves lambda_k, mu_{k-1} of the constraint
impulse at q_k into a second-order value of lambda(t_k)
(:func:`lagrangian.simulation.variational.march.node_multipliers`); they carry the sign of the
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

from lagrangian.constraints import constrained_equations
from lagrangian.errors import SimulationError
from lagrangian.numerics.constrained import compile_constrained
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.numerics.fast import numba_available
from lagrangian.simulation.dynamics import ConstrainedMotion, MultiplierDynamics
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.events import EventWatch
from lagrangian.simulation.integrators.protocol import Integration, Progress
from lagrangian.simulation.methods import VARIATIONAL, engine_for
from lagrangian.simulation.variational.collocation import Tableau, tableau_for
from lagrangian.simulation.variational.collocation_march import collocation_march
from lagrangian.simulation.variational.march import Run, StepSchedule, march

#: Whether to run the compiled marches where numba is installed (False: always the NumPy
#: marches; tests compare the two).
COMPILED = True


@dataclasses.dataclass(frozen=True)
class DiscreteDynamics(ConstrainedMotion[DiscreteMechanics]):
    """The formulation the variational integrators step: the compiled discrete mechanics
    with the holonomic constraints, at the parameters p (x = [q; q_dot])."""

    multiplier_names: tuple[str, ...] = ()

    def constraint_rows(
        self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The multipliers of the multiplier form at every output state, and the largest
        residual (for the collocation integrators; the midpoint rule gives its own)."""
        if not self.multiplier_names:
            return None
        form = compile_constrained(constrained_equations(self.system))
        return MultiplierDynamics(self.system, form, self.p).constraint_rows(t, q, q_dot)


@dataclasses.dataclass(frozen=True)
class VariationalIntegrator:
    """The variational integrator ``method`` over the nodes of :func:`step_schedule`: the midpoint
    rule (``"variational"``) or a collocation method (``"gauss4"``, ``"gauss6"``, see
    :mod:`lagrangian.simulation.variational.collocation`)."""

    method: str = VARIATIONAL

    def run(
        self,
        dynamics: DiscreteDynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        schedule = step_schedule(inputs)
        constrained = bool(dynamics.multiplier_names)
        tableau = None if self.method == VARIATIONAL else tableau_for(self.method, constrained)
        # the grid's steps are counted before the run (dt and max_steps are checked
        # together); the budget here holds the wall time
        nodes = schedule.count + 1 + (0 if schedule.t_out is None else len(schedule.t_out))
        budget = Budget(
            self.method, max(inputs.max_steps, nodes), inputs.max_wall_time, start=schedule.t0
        )
        engine = engine_here(self.method)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            run = discrete_march(
                dynamics.form, tableau, inputs.x0, inputs.p, schedule, None, progress, budget,
                engine,
            )  # fmt: skip
        x = np.hstack((run.q, run.q_dot))
        steps = max(int(np.ceil((run.reached - schedule.t0) / schedule.dt - 1e-9)), 1)
        own_rows = constrained and tableau is None  # else the multiplier form's (constraint_rows)
        name = "midpoint rule" if tableau is None else tableau.name
        return Integration(
            t=run.t,
            x=x,
            t_reached=run.reached,
            x_reached=x[-1] if len(x) else np.asarray(inputs.x0, dtype=float),
            failure=run.failure,
            interrupted=run.interrupted,
            multipliers=run.multipliers if own_rows else None,
            constraint_residual=run.constraint_residual if own_rows else None,
            note=(
                f"Variational integrator ({name}, dt = {inputs.dt:g}) reached the end of "
                f"the time span ({run.evaluations / steps:.3g} evaluations of the discrete "
                "equations per step)."
            ),
        )


def engine_here(method: str) -> str:
    """The engine that runs the variational ``method`` on this machine (methods.py's table):
    the numba marches where numba is installed (and :data:`COMPILED`), else the Python loop."""
    return engine_for(method, {"numba": COMPILED and numba_available()})


def step_schedule(inputs: Inputs) -> StepSchedule:
    """The nodes of the run: steps of dt, a shorter last one, plus every output time (every
    node an output when no output times are asked for)."""
    t0, t1 = inputs.t_span
    return StepSchedule(float(t0), float(t1), float(inputs.dt or t1 - t0), inputs.t_out)


def discrete_march(
    mechanics: DiscreteMechanics,
    tableau: Tableau | None,
    x0: np.ndarray,
    parameters: np.ndarray,
    nodes: np.ndarray | StepSchedule,
    outputs: np.ndarray | None,
    progress: Progress | None,
    budget: Budget | None = None,
    engine: str | None = None,
) -> Run:
    """The march of the midpoint rule (``tableau`` None) or of a collocation method over the
    ``nodes`` (a grid with the ``outputs`` indices into it, or a StepSchedule): compiled where
    numba is installed and the terms compile (the nodes made as the march reaches them), else
    stepped in NumPy by the one Python loop over the grid, within ``budget`` (module
    docstring)."""
    if (engine or engine_here(VARIATIONAL)) == "numba":
        from lagrangian.simulation.variational import compiled as variational_fast  # numba

        try:
            if tableau is None:
                return variational_fast.fast_march(
                    mechanics, x0, parameters, nodes, outputs, progress
                )
            return variational_fast.fast_collocation_march(
                mechanics, tableau, x0, parameters, nodes, outputs, progress
            )
        except SimulationError:  # a term with no compiled form: nothing was integrated yet
            pass
    if isinstance(nodes, StepSchedule):
        grid, outputs = nodes.grid()
    else:
        grid = nodes
        outputs = np.arange(len(grid)) if outputs is None else outputs
    if tableau is None:
        return march(mechanics, x0, parameters, grid, outputs, progress, budget)
    return collocation_march(mechanics, tableau, x0, parameters, grid, outputs, progress, budget)
