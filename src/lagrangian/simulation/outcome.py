"""The one place where an integration becomes a Trajectory, and where a failure or an
interruption is decided.

Every integrator returns an :class:`~lagrangian.simulation.integrators.protocol.Integration`; here
its
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

import dataclasses
from collections.abc import Mapping, Sequence

import numpy as np

from lagrangian.errors import Fix, SimulationError
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.status import Outcome
from lagrangian.simulation.conservation import not_conserved
from lagrangian.simulation.conserved import (
    compile_conserved,
    conserved_columns,
    momentum_obstructions,
)
from lagrangian.simulation.impacts import ImpactRecord
from lagrangian.simulation.integrators.protocol import Integration, Motion
from lagrangian.simulation.methods import backend_note
from lagrangian.simulation.setup import RunSetup
from lagrangian.simulation.trajectory import (
    Event,
    Impact,
    Rows,
    StateRow,
    Trajectory,
    trajectory_of_rows,
)

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
    if raise_on_failure and trajectory.status == Outcome.FAILED:
        raise SimulationError(f"{trajectory.message} {KEEP_HINT}")
    if raise_on_failure and trajectory.status == Outcome.INTERRUPTED:
        raise SimulationInterrupted(trajectory)
    return trajectory


def trajectory_of(setup: RunSetup, motion: Motion, run: Integration) -> Trajectory:
    """Every column of the Trajectory at the rows of ``run``; a run whose state, energies,
    multipliers or conserved quantities stop being finite numbers is cut at the first such row
    and fails there, naming the quantity (never NaN or inf in a Trajectory)."""
    trajectory = _columns(setup, motion, run)
    found = first_non_finite(trajectory)
    if found is None:
        return trajectory
    row, name = found
    t_bad = float(run.t[row])
    keep = slice(0, row)
    cut = dataclasses.replace(
        run,
        t=run.t[keep],
        x=run.x[keep],
        multipliers=None if run.multipliers is None else run.multipliers[keep],
        constraint_residual=(
            None if run.constraint_residual is None else run.constraint_residual[keep]
        ),
        events=tuple(e for e in run.events if e[1] < t_bad),
        stopped_by=None,
        interrupted=False,
        t_reached=t_bad,
        x_reached=run.x[row],
        failure=f"{name} is not a finite number at t = {t_bad:.6g} (the rows before it are kept)",
    )
    return _columns(setup, motion, cut)


def first_non_finite(trajectory: Trajectory) -> tuple[int, str] | None:
    """(first row, column name) where a column of ``trajectory`` is NaN or infinite, or None."""
    first: tuple[int, str] | None = None
    inactive = set(trajectory.multiplier_names)  # NaN is an inactive unilateral constraint
    for name, values in trajectory.columns().items():
        if name in inactive:
            continue
        bad = np.flatnonzero(~np.isfinite(np.asarray(values, dtype=float)))
        if len(bad) and (first is None or bad[0] < first[0]):
            first = (int(bad[0]), _quantity(name))
    return first


def _quantity(column: str) -> str:
    return {"energy": "the energy E = T + V", "energy_function": "the energy function h"}.get(
        column, column
    )


def _columns(setup: RunSetup, motion: Motion, run: Integration) -> Trajectory:
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
    events = events_of(compiled, p, run.events)
    impacts = impacts_of(compiled, p, run.impacts)
    reasons = not_conserved(eom, inputs.parameters, compiled.energy_function_differs, momenta)
    said = _with_note(message(compiled, run), backend_note(setup.options.backend))
    return trajectory_of_rows(
        compiled.coordinates,
        rows_with_energies(compiled, p, t, q, q_dot),
        events=events,
        status=run.status,
        message=str(said),
        message_template=said if isinstance(said, Fix) else None,
        method=inputs.method,
        parameters=inputs.parameters,
        multipliers=multipliers,
        multiplier_names=motion.multiplier_names if multipliers is not None else (),
        constraint_residual=residual,
        conserved=columns,
        not_conserved=with_impacts(reasons, impacts, compiled.energy_function_differs),
        impacts=impacts,
        system_name=setup.system.name,
        units=dict(setup.system.units),
    )


def impacts_of(
    compiled: CompiledEquations, p: np.ndarray, records: Sequence[ImpactRecord]
) -> tuple[Impact, ...]:
    """The Impacts a user reads from what the integration recorded: velocities by name and
    the energy E = T + V lost (the positions do not jump, so the kinetic energy's loss).
    Evaluated for every impact at once (a gas's run has thousands)."""
    if not records:
        return ()
    n = len(compiled.coordinates)
    t = np.array([record.t for record in records])
    states = np.array([(record.before, record.after) for record in records], dtype=float)
    q = states[:, 0, :n]
    before = compiled.velocities(t, states[:, 0], p)
    after = compiled.velocities(t, states[:, 1], p)
    lost = compiled.energy(q, before, t, p) - compiled.energy(q, after, t, p)
    index = {f"{name}_dot": i for i, name in enumerate(compiled.coordinates)}
    return tuple(
        Impact(
            record.t,
            record.constraints,
            dict(zip(record.constraints, record.impulses)),
            StateRow(index, jump_before),
            StateRow(index, jump_after),
            lost_here,
            record.rest,
        )
        for record, jump_before, jump_after, lost_here in zip(
            records, before, after, np.atleast_1d(lost).tolist()
        )
    )


def events_of(
    compiled: CompiledEquations, p: np.ndarray, recorded: Sequence[tuple[str, float, np.ndarray]]
) -> tuple[Event, ...]:
    """Each recorded (name, time, state) as an Event with the state by name, the velocities
    of every event evaluated at once."""
    if not recorded:
        return ()
    n = len(compiled.coordinates)
    t = np.array([time for _, time, _ in recorded])
    x = np.array([state for _, _, state in recorded], dtype=float)
    states = np.concatenate([x[:, :n], compiled.velocities(t, x, p)], axis=1)
    names = [*compiled.coordinates, *(f"{name}_dot" for name in compiled.coordinates)]
    index = {name: i for i, name in enumerate(names)}
    return tuple(
        Event(name, time, StateRow(index, row)) for (name, time, _), row in zip(recorded, states)
    )


#: An impact that loses more than this share of the energy scale makes E not conserved.
LOSS_TOLERANCE = 1e-9


def with_impacts(
    reasons: dict[str, str], impacts: tuple[Impact, ...], has_energy_function: bool
) -> dict[str, str]:
    """The reasons a column is not conserved, with the ``impacts`` that changed the energy
    added to the energy's (and to h's, when it is a column): ``impacts (e < 1)`` (a coefficient
    of restitution below 1), ``transitions`` (a reset of the state)."""
    scale = max((_largest(i.before) for i in impacts), default=0.0) ** 2
    changed = [i for i in impacts if abs(i.energy_lost) > LOSS_TOLERANCE * max(scale, 1e-300)]
    causes = [cause for cause, kind in (("impacts (e < 1)", True), ("transitions", False))
              if any(bool(i.impulses) == kind for i in changed)]  # fmt: skip
    if not causes:
        return reasons
    found = dict(reasons)
    for column in ("energy", "energy_function")[: 1 + has_energy_function]:
        found[column] = ", ".join([*filter(None, [reasons.get(column)]), *causes])
    return found


def _largest(values: Mapping[str, float]) -> float:
    if isinstance(values, StateRow):
        return values.largest
    return max(map(abs, values.values()), default=0.0)


def _with_note(sentence: str | Fix, note: str) -> str | Fix:
    return sentence + f" {note}" if note else sentence


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


#: What a collapsed step size usually means, added to the integrator's words.
COLLAPSED_STEP = (
    " The step size collapsed: the equations are probably singular there (a division by "
    "zero, a collision, a force without bound) or stiff (try method Radau or BDF)."
)


def message(compiled: CompiledEquations, run: Integration) -> str | Fix:
    """How the run ended, in one sentence: where it failed or was interrupted (time and
    state), the terminal event that stopped it, or the integrator's note on reaching the end.
    A failure whose fix names options stays a Fix, for each front end to word."""
    where = ", ".join(f"{n}={v:.6g}" for n, v in zip(compiled.state_names, run.x_reached))
    if run.failure is not None:
        failure = run.failure
        if "step size is less than spacing" in str(failure):  # SciPy's words, the C loop's
            failure += COLLAPSED_STEP
        return f"Integration failed at t = {run.t_reached:.6g} ({where}): " + failure
    if run.interrupted:
        return f"Interrupted (Ctrl-C) at t = {run.t_reached:.6g} ({where})."
    if run.stopped_by is not None:
        return f"Stopped by the terminal event {run.stopped_by} at t = {run.events[-1][1]:.6g}."
    return run.note or "The integration reached the end of the time span."
