"""What a Dask worker does with one block: integrate its members, then make the store's
arrays of them.

The System arrives once per worker (the sweep sends it as one task's result, which the
scheduler computes again if its worker is lost); :func:`lagrangian.derive` and the compilation
are cached by its identity, so each worker derives and compiles once, whatever the number of
blocks it runs.  A block runs as one compiled batch (:func:`lagrangian.
simulate_batch`; constrained systems, ``SweepVariables.per_member``, too: the multiplier form
with project_initial), or, where the batch refuses the block (unilateral constraints, a member
that starts off the constraints), member by member with :func:`lagrangian.simulate`, so that
each member records its own reason.  Both give one Trajectory per member
(:mod:`lagrangian.sweeps.members`), and
:func:`chunk_of_members` makes the arrays of those, so the two paths store the same things.
The result holds plain arrays, ready to be written.

>>> import lagrangian as lg
>>> from lagrangian.sweeps.variables import sweep_variables
>>> system = lg.examples.simple_pendulum()
>>> settings = ChunkSettings(1.0, sweep_variables(system), (0.0, 0.5, 1.0), {"samples": 3})
>>> result = run_chunk(system, {"theta": [0.1, 0.2]}, {}, settings)
>>> result.series["theta"].shape, result.status
((2, 3), ('success', 'success'))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.simulation.batch.result import Batch
from lagrangian.simulation.batch.run import StopCondition, simulate_batch
from lagrangian.simulation.trajectory import Trajectory
from lagrangian.sweeps.members import (
    batch_members,
    impact_count,
    rest_time,
    simulate_member,
    stop_time,
)
from lagrangian.sweeps.variables import SweepVariables


@dataclass(frozen=True)
class ChunkSettings:
    """How every block is integrated: the time span, what is stored (``variables``), the
    output times ``t``, the stepping keywords (method, rtol, atol, samples...), the stop
    condition, the backend, and ``project_initial`` (constrained systems only: the batch and
    the members run by simulate refuse it without constraints)."""

    t_span: float | tuple[float, float] | None
    variables: SweepVariables
    t: tuple[float, ...]
    stepping: Mapping[str, Any] = field(default_factory=dict)
    stop_when: StopCondition | None = None
    backend: str = "numpy"
    project_initial: bool = False


@dataclass(frozen=True)
class ChunkResult:
    """The members of one block, in C order: ``series`` by variable name (k, T) — the
    coordinates, ``NAME_dot``, multipliers and ``energy`` — and per member (k,) the status,
    message, stop time (NaN: did not stop), ``drifts`` by variable name (NaN where the
    quantity is not conserved, or unknown), ``not_conserved`` (why, in words; empty when
    every stored quantity is conserved), the number of ``impacts`` and the ``rest_time``
    (NaN: no contact came to rest), which the store keeps for systems with impacts."""

    series: Mapping[str, np.ndarray]
    status: tuple[str, ...]
    message: tuple[str, ...]
    stop_time: np.ndarray
    drifts: Mapping[str, np.ndarray]
    not_conserved: tuple[str, ...]
    impacts: np.ndarray
    rest_time: np.ndarray


def run_chunk(
    system: System,
    initial: Mapping[str, Any],
    parameters: Mapping[str, Any],
    settings: ChunkSettings,
) -> ChunkResult:
    """Integrate the members given by ``initial`` and ``parameters`` (arrays, one value per
    member).  Bad input for the whole block raises SimulationInputError; a member that cannot
    be integrated is recorded as ``failed`` with the reason, and the others keep their
    results."""
    if settings.variables.per_member:
        members = _constrained_batch(system, initial, parameters, settings) or [
            simulate_member(
                system,
                _values(initial, i),
                _values(parameters, i),
                settings.t_span,
                _stepping(settings),
                settings.stop_when,
                backend=settings.backend,
                project_initial=settings.project_initial,
            )
            for i in range(_count(initial, parameters))
        ]
        return chunk_of_members(members, settings)
    return _batch_chunk(system, initial, parameters, settings)


def _constrained_batch(
    system: System,
    initial: Mapping[str, Any],
    parameters: Mapping[str, Any],
    settings: ChunkSettings,
) -> list[Trajectory] | None:
    """The members of a constrained system's block as one batch (the multiplier form), or
    None where the batch refuses or fails as a whole (then simulate runs each member)."""
    try:
        batch = _simulate_block(system, initial, parameters, settings)
    except Exception:  # each member then runs alone and records its own reason
        return None
    return batch_members(system, batch)


def _batch_chunk(
    system: System,
    initial: Mapping[str, Any],
    parameters: Mapping[str, Any],
    settings: ChunkSettings,
) -> ChunkResult:
    """The block as one compiled batch; a batch that raises as a whole is run again member
    by member, so that only the member that cannot be integrated is recorded as failed."""
    try:
        batch = _simulate_block(system, initial, parameters, settings)
    except SimulationInputError:
        raise
    except Exception as error:  # one member's failure must not take the block with it
        k = _count(initial, parameters)
        if k == 1:
            return failed_chunk(1, settings, f"Integration failed: {type(error).__name__}: {error}")
        return joined(
            [
                _batch_chunk(system, _member(initial, i), _member(parameters, i), settings)
                for i in range(k)
            ]
        )
    return chunk_of_members(batch_members(system, batch), settings)


def _simulate_block(
    system: System,
    initial: Mapping[str, Any],
    parameters: Mapping[str, Any],
    settings: ChunkSettings,
) -> Batch:
    """The members of a block integrated as one :func:`lagrangian.simulate_batch` with the
    block's settings.  ``settings.project_initial`` is passed as it is: the sweep sets it
    only for constrained systems (it refuses it without constraints, as the batch does)."""
    return simulate_batch(
        system,
        dict(initial),
        settings.t_span,
        parameters=dict(parameters),
        stop_when=settings.stop_when,
        backend=settings.backend,
        project_initial=settings.project_initial,
        **_stepping(settings),
    )


def _count(initial: Mapping[str, Any], parameters: Mapping[str, Any]) -> int:
    columns = {**initial, **parameters}
    return len(np.asarray(next(iter(columns.values())))) if columns else 1


def _member(columns: Mapping[str, Any], i: int) -> dict[str, Any]:
    return {name: np.asarray(values)[i : i + 1] for name, values in columns.items()}


def _values(columns: Mapping[str, Any], i: int) -> dict[str, float]:
    return {name: float(np.asarray(values)[i]) for name, values in columns.items()}


def _stepping(settings: ChunkSettings) -> dict[str, Any]:
    """The stepping keywords of simulate and simulate_batch: without output times, the
    store's times ``settings.t`` (the ends of the span)."""
    stepping = dict(settings.stepping)
    if stepping.get("samples") is None and stepping.get("t_eval") is None:
        stepping["t_eval"] = np.asarray(settings.t)
    return stepping


def chunk_of_members(members: Sequence[Trajectory], settings: ChunkSettings) -> ChunkResult:
    """The arrays of the store for ``members``: each member's rows put at the output times
    ``settings.t`` (NaN where it has none: after a stop or a failure)."""
    variables, t = settings.variables, np.asarray(settings.t, dtype=float)
    k, T = len(members), len(t)
    names = (*variables.series, "energy")
    series = {name: np.full((k, T), np.nan) for name in names}
    drifts = {name: np.full(k, np.nan) for name in variables.drifts}
    for i, member in enumerate(members):
        rows, places = _rows_at(member.t, t)
        for name in names:
            column = _column(member, name, variables)
            if column is not None:
                series[name][i, places] = column[rows]
        for name, value in _drifts(member, variables).items():
            drifts[name][i] = value
    return ChunkResult(
        series=series,
        status=tuple(_status(member) for member in members),
        message=tuple(_message(member) for member in members),
        stop_time=np.array([stop_time(member) for member in members], dtype=float),
        drifts=drifts,
        not_conserved=tuple(_reasons(member, variables) for member in members),
        impacts=np.array([impact_count(member) for member in members], dtype=np.int64),
        rest_time=np.array([rest_time(member) for member in members], dtype=float),
    )


def _rows_at(times: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows of ``times`` that are output times, their places in ``t``)."""
    if len(times) <= len(t) and np.array_equal(times, t[: len(times)]):
        return np.arange(len(times)), np.arange(len(times))  # the first rows: most members
    order = np.argsort(t, kind="stable")
    places = order[np.clip(np.searchsorted(t, times, sorter=order), 0, len(t) - 1)]
    rows = np.flatnonzero(t[places] == times) if len(t) else np.zeros(0, dtype=int)
    return rows, places[rows]


def _column(member: Trajectory, name: str, variables: SweepVariables) -> np.ndarray | None:
    """The member's column for the variable ``name`` (``energy``: h where it is stored)."""
    if name == "energy":
        stored = member.energy_function if variables.energy_function else member.energy
        return stored if stored is not None else member.energy
    if name in member.names:
        return member[name]
    return None  # a multiplier of a member without rows


def _drifts(member: Trajectory, variables: SweepVariables) -> dict[str, float]:
    """The member's drift numbers by variable, from :meth:`Trajectory.drift` (which leaves
    out the quantities the system does not conserve)."""
    report = member.drift()
    energy = "energy_function" if variables.energy_function else "energy"
    keys = {"energy_drift": f"{energy}_absolute", "constraint_drift": "constraint_residual_max"}
    keys.update((f"{name}_drift", f"conserved_{name}_absolute") for name in variables.momenta)
    found = {}
    for name in variables.drifts:
        value = report.get(keys[name])
        found[name] = float("nan") if value is None or isinstance(value, str) else float(value)
    return found


def _reasons(member: Trajectory, variables: SweepVariables) -> str:
    """Why stored quantities are not conserved: ``energy: dissipation; p_x: forcing``."""
    reasons = dict(member.not_conserved or {})
    energy = "energy_function" if variables.energy_function else "energy"
    found = [f"energy: {reasons[energy]}"] if energy in reasons else []
    found += [f"{name}: {reasons[name]}" for name in variables.momenta if name in reasons]
    return "; ".join(found)


def _status(member: Trajectory) -> str:
    if member.status != "success":
        return "failed"
    return "stopped" if np.isfinite(stop_time(member)) else "success"


def _message(member: Trajectory) -> str:
    t_stop = stop_time(member)
    if member.status == "success" and np.isfinite(t_stop):
        return f"Stopped by stop_when at t = {t_stop:.6g}."
    return member.message


def joined(parts: list[ChunkResult]) -> ChunkResult:
    """The members of ``parts``, in order, as one result."""
    first = parts[0]
    return ChunkResult(
        series={name: np.concatenate([p.series[name] for p in parts]) for name in first.series},
        status=sum((p.status for p in parts), ()),
        message=sum((p.message for p in parts), ()),
        stop_time=np.concatenate([p.stop_time for p in parts]),
        drifts={name: np.concatenate([p.drifts[name] for p in parts]) for name in first.drifts},
        not_conserved=sum((p.not_conserved for p in parts), ()),
        impacts=np.concatenate([p.impacts for p in parts]),
        rest_time=np.concatenate([p.rest_time for p in parts]),
    )


def failed_chunk(members: int, settings: ChunkSettings, message: str) -> ChunkResult:
    """Every member failed for ``message``: NaN rows, status ``failed``."""
    variables, T = settings.variables, len(settings.t)
    return ChunkResult(
        series={name: np.full((members, T), np.nan) for name in (*variables.series, "energy")},
        status=("failed",) * members,
        message=(message,) * members,
        stop_time=np.full(members, np.nan),
        drifts={name: np.full(members, np.nan) for name in variables.drifts},
        not_conserved=("",) * members,
        impacts=np.full(members, -1, dtype=np.int64),  # not computed, as the store says
        rest_time=np.full(members, np.nan),
    )
