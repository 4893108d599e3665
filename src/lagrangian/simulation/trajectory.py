"""Trajectory: the immutable result of :func:`lagrangian.simulation.simulate`.

Rows are output times t_i; columns (docs/architecture.md, output contracts) are ``t``, each
coordinate, each ``NAME_dot``, the multipliers, ``energy`` = T + V, then the conserved quantities
(:mod:`lagrangian.simulation.conserved`).  The drift report compares each quantity C the system
conserves with its initial value, max_i |C(t_i) - C(t_0)| / |C(t_0)|, and says why the others
are not conserved (:mod:`lagrangian.simulation.conservation`): a damped oscillator's energy
gets no drift number, the reason instead.

>>> import numpy as np
>>> trajectory = Trajectory(t=[0.0, 1.0], q=[[1.0], [0.5]], q_dot=[[0.0], [-1.0]],
...                         coordinates=("x",), energy=[2.0, 2.0])
>>> trajectory["x_dot"]
array([ 0., -1.])
>>> trajectory.drift()["energy_relative"]
0.0
>>> damped = Trajectory(t=[0.0, 1.0], q=[[1.0], [0.5]], q_dot=[[0.0], [-1.0]],
...                     coordinates=("x",), energy=[2.0, 1.0],
...                     not_conserved={"energy": "dissipation"})
>>> damped.drift()
{'energy_not_conserved': 'dissipation'}
>>> damped.drift_summary()
'energy not conserved: dissipation'
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple, TextIO

import numpy as np

from lagrangian.errors import Fix, SimulationInputError, Wording
from lagrangian.simulation.files import written_atomically
from lagrangian.simulation.trajectory_csv import DOT, read_columns
from lagrangian.symbolic.expressions import closest_name
from lagrangian.symbolic.frozen import FrozenMapping, reduce_to_fields


class StateRow(Mapping[str, float]):
    """One row of an array read by name, read-only: an event's state, an impact's velocities.

    A gas's run records thousands of impacts of hundreds of velocities each; a row keeps its
    numbers in one array and shares the names' index with every other row, so recording it
    costs no dictionary.  It compares, iterates and converts (``dict(row)``) as a dict does.

    >>> row = StateRow({"x": 0, "x_dot": 1}, np.array([0.5, -1.0]))
    >>> row["x_dot"], dict(row), row == {"x": 0.5, "x_dot": -1.0}
    (-1.0, {'x': 0.5, 'x_dot': -1.0}, True)
    """

    __slots__ = ("_index", "_values")

    def __init__(self, index: Mapping[str, int], values: np.ndarray) -> None:
        self._index, self._values = index, values

    def __getitem__(self, name: str) -> float:
        return float(self._values[self._index[name]])

    def __iter__(self) -> Any:
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __repr__(self) -> str:
        return repr(dict(self))

    def __reduce__(self) -> tuple[Any, ...]:
        return (StateRow, (dict(self._index), np.array(self._values)))

    @property
    def largest(self) -> float:
        """max |value| (0 for no value)."""
        return float(np.max(np.abs(self._values), initial=0.0))


class Event(NamedTuple):
    """An event found during a simulation: its name, time and the state then."""

    name: str
    t: float
    state: Mapping[str, float]


class Impact(NamedTuple):
    """An impact on unilateral constraints: its time, the ``constraints`` that took an impulse
    and their ``impulses`` Lambda (by name), the velocities ``before`` and ``after`` it (by
    ``NAME_dot``), the kinetic energy it took (``energy_lost``, 0 for an elastic impact), and
    the constraints whose bounces accumulated there (``rest``: they stay in contact)."""

    t: float
    constraints: tuple[str, ...]
    impulses: Mapping[str, float]
    before: Mapping[str, float]
    after: Mapping[str, float]
    energy_lost: float
    rest: tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Sampled motion of a system.

    Attributes
    ----------
    t:
        Output times, shape (N,).
    q, q_dot:
        Coordinates and velocities, shape (N, n), columns in the order of ``coordinates``.
    coordinates:
        Coordinate names.
    energy:
        E = T + V at each output time, shape (N,).
    energy_function:
        h = sum q_dot dL/dq_dot - L when it differs from T + V (it is the conserved one when
        L has no explicit time), else None.
    events:
        Events found, in the order of time.
    status, message:
        ``"success"`` or ``"failed"``; what happened (the failure, or a terminal event).
    method:
        Integration method used.
    parameters:
        Parameter values used, by name.
    multipliers, multiplier_names:
        With constraints: the Lagrange multipliers lambda_1, ... at each output time, shape
        (N, m), and their names; else None and ().
    constraint_residual:
        With constraints: max over the constraints of |h| and |A q_dot + b| at each output
        time, shape (N,); else None.
    conserved:
        Constants of the motion at each output time, by name (shape (N,) each): the momenta
        ``p_NAME`` of cyclic coordinates and any quantity asked for.
    not_conserved:
        The columns among ``energy``, ``energy_function`` and ``conserved`` that the system
        does not conserve, each with why (``"dissipation"``, ``"forcing"``, ``"explicit time
        dependence"``, ``"constraints that do work"``...); None when unknown (a Trajectory
        read from a CSV file), and then every one is taken as conserved.
    impacts:
        The impacts on unilateral constraints with a coefficient of restitution, in the order
        of time (each also an event ``impact NAME``).
    message_template:
        ``message`` with the options it names (a failed run's ``max_steps``) kept for each
        interface to word (:meth:`worded_message`), or None; given, ``message`` is it in
        Python's words.
    system_name, units:
        The name of the system simulated and its units by name (``{"l": "m"}``), for titles
        and axis labels ("" and {} when unknown: a Trajectory read from a CSV file).
    """

    t: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    coordinates: tuple[str, ...]
    energy: np.ndarray
    energy_function: np.ndarray | None = None
    events: tuple[Event, ...] = ()
    status: str = "success"
    message: str = ""
    method: str = ""
    parameters: Mapping[str, float] = field(default_factory=dict)
    multipliers: np.ndarray | None = None
    multiplier_names: tuple[str, ...] = ()
    constraint_residual: np.ndarray | None = None
    conserved: Mapping[str, np.ndarray] = field(default_factory=dict)
    not_conserved: Mapping[str, str] | None = None
    impacts: tuple[Impact, ...] = ()
    message_template: Fix | None = None
    system_name: str = ""
    units: Mapping[str, str] = field(default_factory=dict)
    #: Column name -> (array attribute, column) of the coordinates, velocities and
    #: multipliers: one lookup per column, not a search along thousands of contacts' names.
    _where: Mapping[str, tuple[str, int]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n = len(self.coordinates)
        _freeze(self, "t", (-1,))
        rows = len(self.t)
        _freeze(self, "q", (rows, n))
        _freeze(self, "q_dot", (rows, n))
        _freeze(self, "energy", (rows,))
        if self.energy_function is not None:
            _freeze(self, "energy_function", (rows,))
        object.__setattr__(self, "multiplier_names", tuple(self.multiplier_names))
        if self.multipliers is not None:
            _freeze(self, "multipliers", (rows, len(self.multiplier_names)))
        elif self.multiplier_names:
            raise SimulationInputError("Trajectory.multiplier_names are given without multipliers.")
        if self.constraint_residual is not None:
            _freeze(self, "constraint_residual", (rows,))
        object.__setattr__(self, "coordinates", tuple(self.coordinates))
        object.__setattr__(self, "events", tuple(self.events))
        object.__setattr__(self, "parameters", FrozenMapping(dict(self.parameters)))
        object.__setattr__(self, "conserved", FrozenMapping(_frozen_columns(self, rows)))
        if self.not_conserved is not None:
            reasons = {str(k): str(v) for k, v in self.not_conserved.items()}
            object.__setattr__(self, "not_conserved", FrozenMapping(reasons))
        if self.message_template is not None:
            object.__setattr__(self, "message", str(self.message_template))
        object.__setattr__(self, "_where", FrozenMapping(_column_places(self)))

    def __reduce__(self) -> tuple[Any, ...]:
        return reduce_to_fields(self)

    def worded_message(self, wording: Wording) -> str:
        """:attr:`message` with the options it names as ``wording`` names them
        (``--max-steps`` on the command line, ``max_steps=`` in Python)."""
        if self.message_template is None:
            return self.message
        return self.message_template.worded(wording)

    @property
    def success(self) -> bool:
        return self.status == "success"

    @property
    def names(self) -> tuple[str, ...]:
        """Column names: t, the coordinates, their NAME_dot, the multipliers lambda_j (with
        constraints), energy (and energy_function), the conserved quantities."""
        extra = ("energy_function",) if self.energy_function is not None else ()
        velocities = tuple(name + DOT for name in self.coordinates)
        return (
            "t",
            *self.coordinates,
            *velocities,
            *self.multiplier_names,
            "energy",
            *extra,
            *self.conserved,
        )

    def __getitem__(self, name: str) -> np.ndarray:
        """The column ``name``: ``"t"``, a coordinate, ``NAME_dot``, ``"energy"``."""
        if name in ("t", "energy") or (name == "energy_function" and name in self.names):
            return getattr(self, name)
        place = self._where.get(name)
        if place is not None:
            array, column = place
            values: np.ndarray = getattr(self, array)[:, column]
            return values
        if name in self.conserved:
            return self.conserved[name]
        close = closest_name(name, self.names)
        hint = f"did you mean {close!r}? " if close else ""
        raise KeyError(f"No column {name!r} in this trajectory: {hint}columns are {self.names}")

    def columns(self) -> dict[str, np.ndarray]:
        """Every column by name, in the order of :attr:`names`."""
        return {name: self[name] for name in self.names}

    def drift(self) -> Drift:
        """How far each conserved quantity strays from its initial value C0 = C(t_0).

        For the energy E = T + V: ``energy_absolute`` = max |E - E0| and ``energy_relative``
        = that / |E0| (None when E0 = 0 or there are no rows); the same with
        ``energy_function_`` for h when it differs from E, ``conserved_NAME_`` for each
        conserved quantity, and ``constraint_residual_max`` (max of
        :attr:`constraint_residual`) with constraints.  A quantity the system does not
        conserve (:attr:`not_conserved`) gets no number but ``NAME_not_conserved``, the
        reason: ``energy_not_conserved: "dissipation"``.
        """
        reasons = self.not_conserved or {}
        report = Drift(reasons)
        columns = {"energy": self.energy, "energy_function": self.energy_function}
        columns.update((f"conserved_{name}", values) for name, values in self.conserved.items())
        for key, values in columns.items():
            name = key.removeprefix("conserved_")
            if values is None:
                continue
            if name in reasons:
                report[f"{key}_not_conserved"] = reasons[name]
            else:
                report.update(_drift(key, values))
        if self.constraint_residual is not None:
            residual = self.constraint_residual
            report["constraint_residual_max"] = float(np.max(residual)) if len(residual) else None
        return report

    def drift_summary(self) -> str:
        """The drift report in one line, for people: each conserved quantity's largest
        relative change (absolute when it starts at 0), the reason for each that is not
        conserved, and the largest constraint residual."""
        return self.drift().summary()

    def to_csv(self, destination: str | os.PathLike[str] | TextIO) -> None:
        """Write the columns of :attr:`names` as CSV (17 significant digits: exact round
        trip); a file is written atomically (:mod:`lagrangian.simulation.files`)."""
        data = np.column_stack(list(self.columns().values())) if len(self.t) else None
        write_columns(destination, self.names, data)

    @classmethod
    def from_csv(cls, source: str | os.PathLike[str] | TextIO) -> Trajectory:
        """Read a trajectory written by :meth:`to_csv` (arrays only; no events or status);
        anything else is a SimulationInputError naming the line and the column
        (:mod:`lagrangian.simulation.trajectory_csv`)."""
        names, column = read_columns(source)
        coordinates = tuple(name for name in names[1:] if name + DOT in column)
        start = 1 + 2 * len(coordinates)
        multiplier_names = tuple(names[start : names.index("energy")])
        after = names.index("energy") + 1 + ("energy_function" in column)
        multipliers = None
        if multiplier_names:
            multipliers = np.column_stack([column[name] for name in multiplier_names])
        return cls(
            t=column["t"],
            q=np.column_stack([column[c] for c in coordinates]),
            q_dot=np.column_stack([column[c + DOT] for c in coordinates]),
            coordinates=coordinates,
            energy=column["energy"],
            energy_function=column.get("energy_function"),
            multipliers=multipliers,
            multiplier_names=multiplier_names,
            conserved={name: column[name] for name in names[after:]},
        )

    def to_pandas(self) -> Any:
        """The columns as a pandas DataFrame (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as error:
            raise ImportError(
                "Trajectory.to_pandas needs pandas, which is not installed: "
                "pip install pandas (or use to_csv, columns() or the arrays t, q, q_dot)."
            ) from error
        return pd.DataFrame(self.columns())

    def __repr__(self) -> str:
        span = f"t={self.t[0]:.6g}..{self.t[-1]:.6g}" if len(self.t) else "no rows"
        named = f"{self.system_name}: " if self.system_name else ""
        return (
            f"Trajectory({named}{', '.join(self.coordinates)}; {len(self.t)} rows, {span}, "
            f"{self.method or 'unknown method'}, {self.status})"
        )


def _column_places(trajectory: Trajectory) -> dict[str, tuple[str, int]]:
    """Where each coordinate, velocity and multiplier column is, the earlier kinds first
    where names repeat (a coordinate, then a multiplier, then a conserved quantity, then
    NAME_dot: the order Trajectory[name] has always looked in)."""
    places: dict[str, tuple[str, int]] = {}
    for k, name in enumerate(trajectory.coordinates):
        places.setdefault(name, ("q", k))
    if trajectory.multipliers is not None:
        for k, name in enumerate(trajectory.multiplier_names):
            places.setdefault(name, ("multipliers", k))
    for k, name in enumerate(trajectory.coordinates):
        if name + DOT not in trajectory.conserved:
            places.setdefault(name + DOT, ("q_dot", k))
    return places


class Rows(NamedTuple):
    """The core columns of a sampled motion: times, coordinates, velocities, E = T + V and h
    (None where it is E)."""

    t: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    energy: np.ndarray
    energy_function: np.ndarray | None = None


def trajectory_of_rows(coordinates: tuple[str, ...], rows: Rows, **fields: Any) -> Trajectory:
    """The Trajectory of ``rows`` of the ``coordinates``; ``fields`` are its other fields
    (every simulation, stationary path and batch member is built here)."""
    return Trajectory(coordinates=coordinates, **rows._asdict(), **fields)


class Drift(dict[str, "float | str | None"]):
    """The drift report of :meth:`Trajectory.drift`: a dict of numbers by name, and of
    reasons (``NAME_not_conserved``) for the quantities that are not conserved; asking for a
    number a reason replaces says why it is not there."""

    def __init__(self, reasons: Mapping[str, str]) -> None:
        super().__init__()
        self._reasons = dict(reasons)

    def __missing__(self, key: str) -> Any:
        column = key.rsplit("_", 1)[0]
        name = column.removeprefix("conserved_")
        if name in self._reasons:
            raise KeyError(
                f"{key!r}: {name} is not conserved here ({self._reasons[name]}), so it has no "
                f"drift; the report says why under {column}_not_conserved"
            )
        raise KeyError(key)

    def summary(self) -> str:
        """The report in one line (see :meth:`Trajectory.drift_summary`)."""
        parts = []
        h_conserved = "energy_function_relative" in self
        for key, value in self.items():
            if key == "energy_function_not_conserved" and value == self.get("energy_not_conserved"):
                continue  # h changes for the same reason as T + V: said once
            if key.endswith("_not_conserved"):
                name = key.removesuffix("_not_conserved").removeprefix("conserved_")
                label = "T + V" if name == "energy" and h_conserved else _LABELS.get(name, name)
                parts.append(f"{label} not conserved: {value}")
            elif key.endswith("_relative"):
                name = key.removesuffix("_relative")
                change = _change(name, value, self.get(f"{name}_absolute"))
                if name == "energy_function" and "energy_not_conserved" in self:
                    change += " (h is the conserved energy)"
                parts.append(change)
        if "constraint_residual_max" in self:
            parts.append(f"max constraint residual {_number(self['constraint_residual_max'])}")
        return "; ".join(parts)


#: How the summary names the columns.
_LABELS = {"energy": "energy", "energy_function": "energy function h"}


def _change(name: str, relative: Any, absolute: Any) -> str:
    """``max |dE/E0| = 1e-12`` (or the absolute change when E0 = 0)."""
    symbol = {"energy": "E", "energy_function": "h"}.get(name, name.removeprefix("conserved_"))
    if relative is not None:
        return f"max |d{symbol}/{symbol}0| = {_number(relative)}"
    return f"max |{symbol} - {symbol}0| = {_number(absolute)}"


def _number(value: Any) -> str:
    return "n/a (no rows)" if value is None else f"{value:.3g}"


def _freeze(trajectory: Trajectory, name: str, shape: tuple[int, ...]) -> None:
    """Store a read-only float copy of an array field, checking its shape."""
    array = np.array(getattr(trajectory, name), dtype=float)
    if len(shape) == 2 and array.size == 0:
        array = array.reshape(shape)
    if array.ndim != len(shape) or any(s not in (-1, a) for s, a in zip(shape, array.shape)):
        raise SimulationInputError(f"Trajectory.{name} has shape {array.shape}, expected {shape}.")
    array.setflags(write=False)
    object.__setattr__(trajectory, name, array)


def _frozen_columns(trajectory: Trajectory, rows: int) -> dict[str, np.ndarray]:
    """Read-only float copies of the conserved-quantity columns, checked to have ``rows``."""
    columns = {}
    for name, values in dict(trajectory.conserved).items():
        array = np.array(values, dtype=float)
        if array.shape != (rows,):
            raise SimulationInputError(
                f"Trajectory.conserved[{name!r}] has shape {array.shape}, expected ({rows},)."
            )
        array.setflags(write=False)
        columns[str(name)] = array
    return columns


def _drift(prefix: str, values: np.ndarray) -> dict[str, float | None]:
    if len(values) == 0:
        return {f"{prefix}_absolute": None, f"{prefix}_relative": None}
    initial = float(values[0])
    absolute = float(np.max(np.abs(values - initial)))
    relative = absolute / abs(initial) if initial != 0 else None
    return {f"{prefix}_absolute": absolute, f"{prefix}_relative": relative}


def write_columns(
    destination: str | os.PathLike[str] | TextIO, names: tuple[str, ...], data: np.ndarray | None
) -> None:
    """Named columns as CSV: a header, then the rows of ``data`` (None: none) with 17
    significant digits (an exact round trip); a file is written atomically."""
    if isinstance(destination, (str, os.PathLike)):
        with (
            written_atomically(destination) as temporary,
            open(temporary, "w", encoding="utf-8", newline="") as stream,
        ):
            _write_csv(stream, names, data)
    else:
        _write_csv(destination, names, data)


def _write_csv(stream: TextIO, names: tuple[str, ...], data: np.ndarray | None) -> None:
    stream.write(",".join(names) + "\n")
    if data is not None:
        np.savetxt(stream, data, delimiter=",", fmt="%.17g")
