"""The members of a sweep: the product of the varied axes, times the random samples.

Each varied NAME is a parameter or an initial value (a coordinate or a velocity) of the
System.  Its dimension in the result is the parameter's own name, or ``NAME_0`` for an
initial value (``theta`` -> ``theta_0``, ``theta_dot`` -> ``theta_dot_0``).  The grid is the
product of the ``vary`` axes, in the order given; ``random`` names share one more dimension,
``sample``, of N members drawn uniformly (seeded, so a resumed sweep draws the same).

>>> import lagrangian as lg
>>> grid = build_grid(lg.examples.simple_pendulum(), {"theta": [0.1, 0.2], "l": [1, 2, 3]})
>>> grid.dims, grid.shape, grid.size
(('theta_0', 'l'), (2, 3), 6)
>>> grid.columns((slice(1, 2), slice(0, 2)))
({'theta': array([0.2, 0.2])}, {'l': array([1., 2.])})
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from lagrangian.errors import Fix, Problem, Setting, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.symbolic.symbols import name_of

#: The dimension shared by the names drawn at random.
SAMPLE = "sample"
#: One block of the grid: a slice along each dimension.
Region = tuple[slice, ...]


@dataclass(frozen=True)
class Axis:
    """One varied name: what it is (``initial`` or ``parameter``), its dimension, its values."""

    name: str
    kind: str
    dimension: str
    values: np.ndarray


@dataclass(frozen=True)
class Grid:
    """The members of a sweep: ``axes`` (one dimension each), then the ``random`` names (all
    along the dimension ``sample``).  Member order is C order over :attr:`shape`."""

    axes: tuple[Axis, ...]
    random: tuple[Axis, ...] = ()

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(a.dimension for a in self.axes) + ((SAMPLE,) if self.random else ())

    @property
    def shape(self) -> tuple[int, ...]:
        sizes = tuple(len(a.values) for a in self.axes)
        return sizes + ((len(self.random[0].values),) if self.random else ())

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    def columns(self, region: Region) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
        """The initial values and parameters of the members in ``region``, by name, arrays of
        the region's size (C order): simulate_batch's ``initial`` and ``parameters``."""
        ranges = [a.values[s] for a, s in zip(self.axes, region)]
        if self.random:
            ranges.append(np.arange(len(self.random[0].values))[region[-1]])
        mesh = np.meshgrid(*ranges, indexing="ij") if ranges else []
        initial: dict[str, np.ndarray] = {}
        parameters: dict[str, np.ndarray] = {}
        for axis, values in zip(self.axes, mesh):
            target = initial if axis.kind == "initial" else parameters
            target[axis.name] = values.ravel().astype(float)
        if self.random:
            index = mesh[-1].ravel()
            for axis in self.random:
                target = initial if axis.kind == "initial" else parameters
                target[axis.name] = axis.values[index].astype(float)
        return initial, parameters


def build_grid(
    system: System,
    vary: Mapping[Any, ArrayLike] | None,
    random: Mapping[Any, tuple[float, float, int]] | None = None,
    seed: int = 0,
    labels: Mapping[str, str] | None = None,
) -> Grid:
    """The Grid of ``vary`` (name -> values) and ``random`` (name -> (low, high, N)).

    ``labels`` names the field of each name in errors (default ``vary['NAME']``, ``random[
    'NAME']``; the command line passes its flags).  Every problem is raised at once as a
    SimulationInputError.
    """
    labels = labels or {}
    kinds = _kinds(system)
    problems: list[Problem] = []
    seen: set[str] = set()
    axes = []
    for key, values in (vary or {}).items():
        name = name_of(key)
        field = labels.get(name, f"vary[{name!r}]")
        axis = _axis(name, field, values, kinds, seen, problems)
        if axis is not None:
            axes.append(axis)
    drawn = _random_axes(random or {}, seed, labels, kinds, seen, problems)
    if not axes and not drawn and not problems:
        ranges = (Setting("vary", entry="NAME"), Setting("random", entry="NAME"))
        problems.append(Problem("vary", "nothing to sweep over", Fix("give {} or {}", ranges)))
    raise_if_problems(problems, "Cannot sweep", SimulationInputError)
    return Grid(tuple(axes), tuple(drawn))


def _kinds(system: System) -> dict[str, str]:
    kinds = {p.name: "parameter" for p in system.parameters}
    kinds.update((q.name, "initial") for q in (*system.coordinates, *system.velocities))
    return kinds


def dimension_name(name: str, kind: str) -> str:
    """The dimension of a varied name: ``NAME_0`` for an initial value, else the name."""
    return f"{name}_0" if kind == "initial" else name


def _axis(
    name: str,
    field: str,
    values: Any,
    kinds: Mapping[str, str],
    seen: set[str],
    problems: list[Problem],
) -> Axis | None:
    """The checked axis of one name, or None with its problems recorded."""
    if name not in kinds:
        fix = "choose a parameter, coordinate or velocity: " + ", ".join(sorted(kinds))
        problems.append(Problem(field, f"{name!r} is not a name of the system", fix))
        return None
    if name in seen:
        problems.append(Problem(field, f"{name!r} is swept twice", "give each name once"))
        return None
    seen.add(name)
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        problems.append(Problem(field, f"{values!r} is not a list of numbers"))
        return None
    if array.ndim != 1 or array.size == 0 or not np.all(np.isfinite(array)):
        fix = "give a non-empty 1-d list of finite numbers"
        problems.append(Problem(field, "bad values", fix))
        return None
    return Axis(name, kinds[name], dimension_name(name, kinds[name]), array)


def _random_axes(
    random: Mapping[Any, Any],
    seed: int,
    labels: Mapping[str, str],
    kinds: Mapping[str, str],
    seen: set[str],
    problems: list[Problem],
) -> list[Axis]:
    """The random names, each drawn uniformly in [low, high), all N long."""
    generator = np.random.default_rng(seed)
    axes: list[Axis] = []
    counts: dict[str, int] = {}
    for key, spec in random.items():
        name = name_of(key)
        field = labels.get(name, f"random[{name!r}]")
        low, high, count = _range(spec, field, problems)
        axis = _axis(name, field, [0.0], kinds, seen, problems)
        if axis is None or count is None:
            continue
        counts[field] = count
        values = generator.uniform(low, high, count)
        axes.append(Axis(name, axis.kind, axis.dimension, values))
    if len(set(counts.values())) > 1:
        sizes = ", ".join(f"{field}: {n}" for field, n in counts.items())
        fix = "draw the same number N for every random name (they share the dimension sample)"
        problems.append(Problem("random", f"different sample counts ({sizes})", fix))
    return axes


def _range(spec: Any, field: str, problems: list[Problem]) -> tuple[float, float, int | None]:
    """(low, high, N) of a random name, N None when the spec is wrong."""
    fix = "give (low, high, N): low < high, finite, and a whole number N >= 1"
    try:
        low, high, count = spec
        low, high = float(low), float(high)
    except (TypeError, ValueError):
        problems.append(Problem(field, f"{spec!r} is not (low, high, N)", fix))
        return 0.0, 0.0, None
    whole = isinstance(count, (int, np.integer)) and not isinstance(count, bool)
    if not (math.isfinite(low) and math.isfinite(high) and low < high) or not whole or count < 1:
        problems.append(Problem(field, f"bad range {spec!r}", fix))
        return 0.0, 0.0, None
    return low, high, int(count)
