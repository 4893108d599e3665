"""Batch: the immutable result of :func:`lagrangian.simulation.batch.run.simulate_batch`.

Member i has the rows ``q[i]``, ``q_dot[i]``, ``energy[i]`` at the shared output times ``t``
(NaN after it stopped or failed), a status (``success``, ``stopped`` or ``failed``), and a final
state: at the end of the time span, at its stop (``stop_time``), or at its last step.  A batch
of a constrained system also holds the multipliers ``multipliers[i]`` (lambda_j at each row)
and the constraint residual of every row and of the final state.

>>> import numpy as np
>>> batch = Batch(t=[0.0, 1.0], q=np.zeros((2, 2, 1)), q_dot=np.zeros((2, 2, 1)),
...               energy=np.zeros((2, 2)), coordinates=("x",), status=("success", "stopped"),
...               message=("", "Stopped by stop_when at t = 0.5."), final_t=[1.0, 0.5],
...               final_q=np.zeros((2, 1)), final_q_dot=np.zeros((2, 1)),
...               final_energy=np.zeros(2))
>>> len(batch), batch.stop_time
(2, array([nan, 0.5]))
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.status import Outcome
from lagrangian.simulation.trajectory import DOT, Event, Rows, Trajectory, trajectory_of_rows
from lagrangian.symbolic.frozen import FrozenMapping, reduce_to_fields


@dataclass(frozen=True, eq=False)
class ConstraintRows:
    """The constraint columns of a batch's members (the fields of :class:`Batch` of the same
    names): multipliers (k, T, m) and residuals (k, T) at the output rows, NaN where a
    member has no row, and both at each member's final state, (k, m) and (k,)."""

    multiplier_names: tuple[str, ...]
    multipliers: np.ndarray
    constraint_residual: np.ndarray
    final_multipliers: np.ndarray
    final_constraint_residual: np.ndarray


@dataclass(frozen=True, eq=False)
class Batch:
    """k members integrated together (see the module docstring).

    Attributes
    ----------
    t:
        Output times, shape (T,), shared by every member.
    q, q_dot:
        Shape (k, T, n); NaN after a member stopped or failed.
    energy:
        E = T + V, shape (k, T).
    status, message:
        Per member: ``success``, ``stopped`` or ``failed``, and what happened.
    final_t, final_q, final_q_dot, final_energy:
        Where each member ended: t1, its stop time, or its last step before a failure.
    initial, parameters:
        The initial state and the parameter values of every member, by name, arrays (k,).
    method, backend:
        How it was integrated.
    multiplier_names, multipliers, constraint_residual:
        With constraints: the names lambda_1, ..., the multipliers, shape (k, T, m), and the
        largest constraint residual max(|h|, |A q_dot + b|), shape (k, T); else (), None.
    final_multipliers, final_constraint_residual:
        With constraints: both at the final state, shapes (k, m) and (k,); else None.

    Unlike a single simulation's Trajectory, a batch does not evaluate the energy function h
    (where it differs from T + V); ``trajectory(i)`` carries E = T + V only.
    """

    t: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    energy: np.ndarray
    coordinates: tuple[str, ...]
    status: tuple[str, ...]
    message: tuple[str, ...]
    final_t: np.ndarray
    final_q: np.ndarray
    final_q_dot: np.ndarray
    final_energy: np.ndarray
    initial: Mapping[str, np.ndarray] = field(default_factory=dict)
    parameters: Mapping[str, np.ndarray] = field(default_factory=dict)
    method: str = ""
    backend: str = "numpy"
    multiplier_names: tuple[str, ...] = ()
    multipliers: np.ndarray | None = None
    constraint_residual: np.ndarray | None = None
    final_multipliers: np.ndarray | None = None
    final_constraint_residual: np.ndarray | None = None

    def __post_init__(self) -> None:
        k, n = len(self.status), len(self.coordinates)
        rows, m = len(np.asarray(self.t)), len(self.multiplier_names)
        optional = {
            "multipliers": (k, rows, m),
            "constraint_residual": (k, rows),
            "final_multipliers": (k, m),
            "final_constraint_residual": (k,),
        }
        given = [name for name in optional if getattr(self, name) is not None]
        if (given and len(given) < len(optional)) or bool(given) != bool(m):
            raise SimulationError(
                "Batch takes multiplier_names, multipliers, constraint_residual, "
                "final_multipliers and final_constraint_residual together, or none of them."
            )
        shapes = {
            "t": (rows,),
            "q": (k, rows, n),
            "q_dot": (k, rows, n),
            "energy": (k, rows),
            "final_t": (k,),
            "final_q": (k, n),
            "final_q_dot": (k, n),
            "final_energy": (k,),
            **{name: optional[name] for name in given},
        }
        for name, shape in shapes.items():
            array = np.array(getattr(self, name), dtype=float)
            if array.shape != shape:
                raise SimulationError(f"Batch.{name} has shape {array.shape}, expected {shape}.")
            array.setflags(write=False)
            object.__setattr__(self, name, array)
        for name in ("initial", "parameters"):
            columns = {key: _frozen(values) for key, values in getattr(self, name).items()}
            object.__setattr__(self, name, FrozenMapping(columns))
        object.__setattr__(self, "coordinates", tuple(self.coordinates))
        object.__setattr__(self, "status", tuple(Outcome(s) for s in self.status))
        object.__setattr__(self, "message", tuple(self.message))
        object.__setattr__(self, "multiplier_names", tuple(self.multiplier_names))

    def __reduce__(self) -> tuple[Any, ...]:
        return reduce_to_fields(self)

    def __len__(self) -> int:
        return len(self.status)

    @property
    def stop_time(self) -> np.ndarray:
        """The time each member stopped at, NaN for those that did not stop."""
        stopped = np.array([s is Outcome.STOPPED for s in self.status], dtype=bool)
        return np.where(stopped, self.final_t, np.nan)

    @property
    def final(self) -> dict[str, np.ndarray]:
        """The final state by name: ``t``, each coordinate and each ``NAME_dot``, arrays (k,)."""
        columns = {"t": self.final_t}
        columns.update((name, self.final_q[:, j]) for j, name in enumerate(self.coordinates))
        columns.update(
            (name + DOT, self.final_q_dot[:, j]) for j, name in enumerate(self.coordinates)
        )
        return columns

    def trajectory(self, i: int) -> Trajectory:
        """Member i as a Trajectory: its rows up to its end, then its stop as the last row
        and an event named ``stop_when`` (as a terminal event ends a single simulation)."""
        if not -len(self) <= i < len(self):
            raise IndexError(f"Batch has {len(self)} members; there is no member {i}.")
        rows = np.flatnonzero(np.all(np.isfinite(self.q[i]), axis=1) & (self.t <= self.final_t[i]))
        t, q, q_dot, energy = (
            self.t[rows],
            self.q[i, rows],
            self.q_dot[i, rows],
            self.energy[i, rows],
        )
        constraints = self._constraint_rows(i, rows)
        events: tuple[Event, ...] = ()
        if self.status[i] is Outcome.STOPPED:
            state = dict(zip(self.coordinates, self.final_q[i].tolist()))
            state.update((c + DOT, float(v)) for c, v in zip(self.coordinates, self.final_q_dot[i]))
            events = (Event("stop_when", float(self.final_t[i]), state),)
            if not len(t) or self.final_t[i] > t[-1]:
                t = np.append(t, self.final_t[i])
                q, q_dot = np.vstack([q, self.final_q[i]]), np.vstack([q_dot, self.final_q_dot[i]])
                energy = np.append(energy, self.final_energy[i])
                constraints = self._constraint_rows(i, rows, final=True)
        return trajectory_of_rows(
            self.coordinates,
            Rows(t, q, q_dot, energy),
            events=events,
            status=Outcome.FAILED if self.status[i] is Outcome.FAILED else Outcome.SUCCESS,
            message=self.message[i],
            method=self.method,
            parameters={name: float(values[i]) for name, values in self.parameters.items()},
            **constraints,
        )

    def _constraint_rows(self, i: int, rows: np.ndarray, final: bool = False) -> dict[str, Any]:
        """The Trajectory fields of member i's multipliers and residuals at ``rows`` (and at
        its final state); none without constraints."""
        if self.multipliers is None or self.constraint_residual is None:
            return {}
        assert self.final_multipliers is not None and self.final_constraint_residual is not None
        multipliers, residual = self.multipliers[i, rows], self.constraint_residual[i, rows]
        if final:
            multipliers = np.vstack([multipliers, self.final_multipliers[i]])
            residual = np.append(residual, self.final_constraint_residual[i])
        return {
            "multipliers": multipliers,
            "multiplier_names": self.multiplier_names,
            "constraint_residual": residual,
        }

    def __repr__(self) -> str:
        counts = {
            s: self.status.count(s) for s in (Outcome.SUCCESS, Outcome.STOPPED, Outcome.FAILED)
        }
        summary = ", ".join(f"{n} {s}" for s, n in counts.items() if n)
        return (
            f"Batch({', '.join(self.coordinates)}; {len(self)} members, {len(self.t)} times, "
            f"{self.method or 'unknown method'}, {self.backend}: {summary or 'empty'})"
        )


def _frozen(values: Any) -> np.ndarray:
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array
