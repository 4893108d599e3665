"""What a Dask worker does with one block: integrate its members as one compiled batch.

The System arrives once per worker (the sweep scatters it); :func:`lagrangian.derive` and the
compilation are cached by its identity, so each worker derives and compiles once, whatever
the number of blocks it runs.  The result holds plain arrays, ready to be written.

>>> import lagrangian as lg
>>> settings = ChunkSettings(1.0, {"method": "DOP853", "samples": 3}, None, "numpy", 3)
>>> result = run_chunk(lg.examples.simple_pendulum(), {"theta": [0.1, 0.2]}, {}, settings)
>>> result.q.shape, result.status
((2, 3, 1), ('success', 'success'))
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.simulation.batch import StopCondition, simulate_batch
from lagrangian.simulation.batch_result import Batch


@dataclass(frozen=True)
class ChunkSettings:
    """How every block is integrated: simulate_batch's t_span, stepping keywords (method,
    rtol, atol, samples...), stop condition and backend, and the number of output times."""

    t_span: float | tuple[float, float] | None
    stepping: Mapping[str, Any] = field(default_factory=dict)
    stop_when: StopCondition | None = None
    backend: str = "numpy"
    times: int = 2


@dataclass(frozen=True)
class ChunkResult:
    """The members of one block, in C order: q, q_dot (k, T, n), energy (k, T), per member
    status, message, stop time (NaN: did not stop) and energy drift max |E - E(t0)|."""

    q: np.ndarray
    q_dot: np.ndarray
    energy: np.ndarray
    status: tuple[str, ...]
    message: tuple[str, ...]
    stop_time: np.ndarray
    energy_drift: np.ndarray


def run_chunk(
    system: System,
    initial: Mapping[str, np.ndarray],
    parameters: Mapping[str, np.ndarray],
    settings: ChunkSettings,
) -> ChunkResult:
    """Integrate the members given by ``initial`` and ``parameters`` (arrays, one value per
    member).  Bad input raises SimulationInputError.  A batch that raises as a whole is run
    again member by member, so that a member that cannot be integrated is recorded as
    ``failed`` with the reason and the others keep their results."""
    try:
        return chunk_result(
            simulate_batch(
                system,
                dict(initial),
                settings.t_span,
                parameters=dict(parameters),
                stop_when=settings.stop_when,
                backend=settings.backend,
                **settings.stepping,
            )
        )
    except SimulationInputError:
        raise
    except Exception as error:  # one member's failure must not take the block with it
        columns = {**initial, **parameters}
        k = len(next(iter(columns.values()))) if columns else 1
        if k == 1:
            reason = f"Integration failed: {type(error).__name__}: {error}"
            return failed_chunk(1, settings.times, len(system.coordinates), reason)
        members = [
            run_chunk(system, _member(initial, i), _member(parameters, i), settings)
            for i in range(k)
        ]
        return joined(members)


def _member(columns: Mapping[str, np.ndarray], i: int) -> dict[str, np.ndarray]:
    return {name: np.asarray(values)[i : i + 1] for name, values in columns.items()}


def joined(parts: list[ChunkResult]) -> ChunkResult:
    """The members of ``parts``, in order, as one result."""
    return ChunkResult(
        q=np.concatenate([p.q for p in parts]),
        q_dot=np.concatenate([p.q_dot for p in parts]),
        energy=np.concatenate([p.energy for p in parts]),
        status=sum((p.status for p in parts), ()),
        message=sum((p.message for p in parts), ()),
        stop_time=np.concatenate([p.stop_time for p in parts]),
        energy_drift=np.concatenate([p.energy_drift for p in parts]),
    )


def chunk_result(batch: Batch) -> ChunkResult:
    """The arrays of a Batch (its energy drift over the sampled rows and the final state)."""
    start = batch.energy[:, :1]
    energies = np.hstack([batch.energy, batch.final_energy[:, None]])
    with np.errstate(invalid="ignore"):
        change = np.abs(energies - start)
    finite = np.isfinite(change)
    drift = np.where(finite.any(axis=1), np.max(np.where(finite, change, 0.0), axis=1), np.nan)
    return ChunkResult(
        q=np.asarray(batch.q),
        q_dot=np.asarray(batch.q_dot),
        energy=np.asarray(batch.energy),
        status=batch.status,
        message=batch.message,
        stop_time=np.asarray(batch.stop_time),
        energy_drift=drift,
    )


def failed_chunk(members: int, times: int, coordinates: int, message: str) -> ChunkResult:
    """Every member failed for ``message``: NaN rows, status ``failed``."""
    rows = np.full((members, times, coordinates), np.nan)
    return ChunkResult(
        q=rows,
        q_dot=rows.copy(),
        energy=np.full((members, times), np.nan),
        status=("failed",) * members,
        message=(message,) * members,
        stop_time=np.full(members, np.nan),
        energy_drift=np.full(members, np.nan),
    )
