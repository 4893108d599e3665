"""The one place where an integration becomes a Trajectory, and where a failure or an
interruption is decided.

Every integrator returns an :class:`~lagrangian.simulation.integration.Integration`; here its
rows get their velocities, energies (E = T + V, and h where it differs), multipliers and
constraint residuals, the conserved quantities asked for, the events by name, which columns
the system conserves (:mod:`lagrangian.simulation.conservation`) and a message; a run that
reached a gimbal lock is cut there.  Then, with ``raise_on_failure``:

* a failed run raises SimulationError (the message says where it stopped and why);
* a run interrupted by Ctrl-C raises :class:`SimulationInterrupted`, a KeyboardInterrupt
  (a script still stops) that carries the Trajectory computed up to there.

Without it the Trajectory is returned, with status ``"failed"`` or ``"interrupted"``.
"""

from __future__ import annotations

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.simulation.conservation import not_conserved
from lagrangian.simulation.conserved import (
    compile_conserved,
    conserved_columns,
    momentum_obstructions,
)
from lagrangian.simulation.integration import Integration, Motion
from lagrangian.simulation.setup import RunSetup
from lagrangian.simulation.trajectory import Event, Rows, Trajectory, trajectory_of_rows

#: What every message about a run that did not reach its end adds, in the Python API.
KEEP_HINT = "Pass raise_on_failure=False to keep the trajectory computed up to the failure."


class SimulationInterrupted(KeyboardInterrupt):
    """Ctrl-C during a simulation.  ``trajectory`` holds the rows computed before it (status
    ``"interrupted"``); it is a KeyboardInterrupt, so an interrupted script still stops."""

    def __init__(self, trajectory: Trajectory) -> None:
        super().__init__(f"{trajectory.message} The rows so far are in this error's .trajectory.")
        self.trajectory = trajectory


def conclude(
    setup: RunSetup, motion: Motion, run: Integration, raise_on_failure: bool
) -> Trajectory:
    """The Trajectory of ``run`` (module docstring); raises on a failure or an interruption
    when ``raise_on_failure``."""
    trajectory = setup.guard.finish(trajectory_of(setup, motion, run))
    if raise_on_failure and trajectory.status == "failed":
        raise SimulationError(f"{trajectory.message} {KEEP_HINT}")
    if raise_on_failure and trajectory.status == "interrupted":
        raise SimulationInterrupted(trajectory)
    return trajectory


def trajectory_of(setup: RunSetup, motion: Motion, run: Integration) -> Trajectory:
    """Every column of the Trajectory at the rows of ``run``."""
    compiled, inputs, eom = setup.compiled, setup.inputs, setup.eom
    n, p = len(compiled.coordinates), inputs.p
    t, x = run.t, run.x
    q = x[:, :n]
    q_dot = compiled.velocities(t, x, p) if len(t) else np.zeros((0, n))
    multipliers, residual = run.multipliers, run.constraint_residual
    if multipliers is None and motion.multiplier_names:
        multipliers, residual = motion.constraint_rows(t, q, q_dot) or (None, None)
    function = compile_conserved(eom, setup.quantities)
    columns = conserved_columns(function, tuple(setup.quantities), q, q_dot, t, p)
    momenta = momentum_obstructions(eom, setup.system, inputs.parameters)
    events = tuple(
        Event(name, time, state_by_name(compiled, time, state, p))
        for name, time, state in run.events
    )
    return trajectory_of_rows(
        compiled.coordinates,
        rows_with_energies(compiled, p, t, q, q_dot),
        events=events,
        status=run.status,
        message=message(compiled, run),
        method=inputs.method,
        parameters=inputs.parameters,
        multipliers=multipliers,
        multiplier_names=motion.multiplier_names if multipliers is not None else (),
        constraint_residual=residual,
        conserved=columns,
        not_conserved=not_conserved(
            eom, inputs.parameters, compiled.energy_function_differs, momenta
        ),
    )


def rows_with_energies(
    compiled: CompiledEquations, p: np.ndarray, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray
) -> Rows:
    """The rows (t, q, q_dot) with E = T + V, and h where it differs from E."""
    differs = compiled.energy_function_differs
    if not len(t):
        return Rows(t, q, q_dot, np.zeros(0), np.zeros(0) if differs else None)
    energy = compiled.energy(q, q_dot, t, p)
    if not differs:
        return Rows(t, q, q_dot, energy)
    return Rows(t, q, q_dot, energy, compiled.energy_function(q, q_dot, t, p))


def state_by_name(
    compiled: CompiledEquations, t: float, x: np.ndarray, p: np.ndarray
) -> dict[str, float]:
    """Every coordinate and velocity at state x, by name."""
    q_dot = compiled.velocities(t, x, p)
    values = dict(zip(compiled.coordinates, x[: len(compiled.coordinates)].tolist()))
    values.update((name + "_dot", float(v)) for name, v in zip(compiled.coordinates, q_dot))
    return values


def message(compiled: CompiledEquations, run: Integration) -> str:
    """How the run ended, in one sentence: where it failed or was interrupted (time and
    state), the terminal event that stopped it, or the integrator's note on reaching the end."""
    where = ", ".join(f"{n}={v:.6g}" for n, v in zip(compiled.state_names, run.x_reached))
    if run.failure is not None:
        return f"Integration failed at t = {run.t_reached:.6g} ({where}): {run.failure}"
    if run.interrupted:
        return f"Interrupted (Ctrl-C) at t = {run.t_reached:.6g} ({where})."
    if run.stopped_by is not None:
        return f"Stopped by the terminal event {run.stopped_by} at t = {run.events[-1][1]:.6g}."
    return run.note or "The integration reached the end of the time span."
