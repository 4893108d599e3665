"""What simulate_batch is told, checked at the boundary: scalars or arrays, one length k.

Every initial value and parameter may be a number (the same for every member) or an array of
k numbers (one per member); arrays of different lengths are refused, naming both fields.  The
rest (names, missing values, method, tolerances, time span) is checked as
:func:`lagrangian.simulation.inputs.checked_inputs` checks a single run, on member 0, and every
problem is reported at once.  Output times as for a single run: ``samples`` or ``t_eval``, else
the System's own ``samples``; with none of them (where a single run keeps every step, which k
members cannot share) :data:`DEFAULT_SAMPLES` evenly spaced times, fewer when the batch would
hold more than :data:`DEFAULT_NUMBERS` numbers (never fewer than the two ends).

>>> import lagrangian as lg
>>> from lagrangian.numerics.compile import compile_equations
>>> compiled = compile_equations(lg.derive(lg.examples.simple_pendulum()))
>>> given = {"initial": {"theta": [0.1, 0.2], "theta_dot": 0.0}, "t_span": 1.0}
>>> batch, problems = checked_batch(compiled, given, Fallbacks())
>>> batch.X0
array([[0.1, 0. ],
       [0.2, 0. ]])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from lagrangian.errors import Problem
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.simulation.inputs import Fallbacks, Inputs, checked_inputs
from lagrangian.simulation.options import Options
from lagrangian.symbolic.symbols import name_of


@dataclass(frozen=True)
class BatchInputs:
    """Checked inputs of a batch: member 0's Inputs, one state and parameter row per member,
    the output times, and the checked options (None until the caller has checked them)."""

    inputs: Inputs
    X0: np.ndarray
    P: np.ndarray
    t_out: np.ndarray
    options: Options | None = None

    @property
    def size(self) -> int:
        return len(self.X0)


def checked_batch(
    compiled: CompiledEquations,
    given: Mapping[str, Any],
    fallbacks: Fallbacks,
    ends_only: bool = False,
) -> tuple[BatchInputs, list[Problem]]:
    """The inputs of ``given`` (simulate_batch's arguments) and every problem with them
    (placeholders stand where a value is wrong), for the caller to raise once.
    ``ends_only``: a sweep's default output times (:func:`checked_inputs`)."""
    problems: list[Problem] = []
    initial = _arrays("initial", given.get("initial") or {}, problems)
    parameters = _arrays("parameters", given.get("parameters") or {}, problems)
    k = _common_length(
        {**_fields("initial", initial), **_fields("parameters", parameters)}, problems
    )
    first = dict(given)
    first["initial"] = {name: values[0] for name, values in initial.items()}
    first["parameters"] = {name: values[0] for name, values in parameters.items()}
    inputs, found = checked_inputs(compiled, first, fallbacks, ends_only)
    problems.extend(found)
    k = 0 if problems else k  # no rows from arrays that do not fit together
    X0 = _rows(inputs.x0, compiled.state_names, initial, k)
    P = _rows(inputs.p, compiled.parameters, parameters, k)
    t_out = inputs.t_out
    if t_out is None:
        t_out = default_times(inputs.t_span, X0.shape)
    return BatchInputs(inputs, X0, P, t_out), problems


#: Output times of a batch given neither samples nor t_eval (as many as a plot needs) ...
DEFAULT_SAMPLES = 1000
#: ... unless the members' states at them would exceed this many numbers (128 MiB).
DEFAULT_NUMBERS = 2**24


def default_times(t_span: tuple[float, float], states: tuple[int, ...]) -> np.ndarray:
    """Evenly spaced output times for ``states`` (k members x n state variables): as many
    as a plot needs, fewer for a batch too large to keep them, at least the two ends.

    >>> len(default_times((0.0, 1.0), (3, 2))), len(default_times((0.0, 1.0), (10**7, 4)))
    (1000, 2)
    """
    k, n = states
    fitting = DEFAULT_NUMBERS // max(1, k * n)
    return np.linspace(*t_span, int(min(DEFAULT_SAMPLES, max(2, fitting))))


def _arrays(
    field: str, values: Mapping[Any, Any], problems: list[Problem]
) -> dict[str, np.ndarray]:
    """Each value as a 1-d float array (a number: length 1), by name; bad ones reported."""
    arrays: dict[str, np.ndarray] = {}
    for key, value in values.items():
        name = name_of(key)
        where = f"{field}[{name!r}]"
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            problems.append(Problem(where, f"{value!r} is not a number or an array of numbers"))
            continue
        if array.ndim > 1 or array.size == 0:
            problems.append(
                Problem(
                    where, f"has shape {array.shape}", "give a number or a 1-d array of k numbers"
                )
            )
            continue
        if not np.all(np.isfinite(array)):
            problems.append(Problem(where, "holds a value that is not a finite number"))
            continue
        arrays[name] = np.atleast_1d(array)
    return arrays


def _fields(field: str, arrays: Mapping[str, np.ndarray]) -> dict[str, int]:
    return {f"{field}[{name!r}]": len(values) for name, values in arrays.items()}


def _common_length(lengths: Mapping[str, int], problems: list[Problem]) -> int:
    """k: the length shared by every array (numbers count as length 1 and broadcast)."""
    arrays = {where: n for where, n in lengths.items() if n != 1}
    if not arrays:
        return 1
    (first, k), *others = arrays.items()
    for where, n in others:
        if n != k:
            problems.append(
                Problem(
                    where,
                    f"has {n} values, but {first} has {k}",
                    "give every array the same length k (one value per member), or a number",
                )
            )
    return k


def _rows(
    row: np.ndarray, names: tuple[str, ...], arrays: Mapping[str, np.ndarray], k: int
) -> np.ndarray:
    """``row`` repeated k times, with the columns given as arrays replaced."""
    table = np.tile(np.asarray(row, dtype=float), (k, 1))
    for j, name in enumerate(names):
        if name in arrays and k:
            table[:, j] = np.broadcast_to(arrays[name], (k,))
    return table
