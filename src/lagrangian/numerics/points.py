"""Positions of a System's named points (particles, body centres) as one NumPy function of
(q, t, p), for animation and for reading forces at points along a trajectory.

>>> import numpy as np, lagrangian as lg
>>> points = compile_points(lg.examples.simple_pendulum())
>>> points.names, points.dimension
(('bob',), 2)
>>> np.round(points([0.0], 0.0, points.defaults), 6)
array([[ 0., -1.]])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lagrangian.model import System
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t


@dataclass(frozen=True)
class PointPositions:
    """r_i(q, t, p) of every named point; calling it gives shape (points, dimension), or
    (k, points, dimension) for a batch of k states."""

    names: tuple[str, ...]
    dimension: int
    parameters: tuple[str, ...]
    defaults: tuple[float, ...]
    function: NumericFunction

    def __call__(self, q: Any, time: Any, p: Any) -> np.ndarray:
        return self.function(q, time, p)

    def parameter_vector(self, values: dict[str, float]) -> np.ndarray:
        """Parameter values by name (missing ones from the defaults)."""
        return np.array([values.get(n, d) for n, d in zip(self.parameters, self.defaults)])


def compile_points(system: System) -> PointPositions:
    """The positions of ``system``'s particles and rigid-body centres as a NumPy function."""
    points = {name: r for name, r in system.points().items() if name != "origin"}
    dimension = system.dimension
    expressions = [to_sympy(x) for r in points.values() for x in r]
    defaults = tuple(float("nan") if v is None else float(v) for v in system.parameters.values())
    function = NumericFunction(
        (list(system.coordinates), t, list(system.parameters)),
        expressions,
        shape=(len(points), dimension),
    )
    return PointPositions(
        tuple(points), dimension, tuple(p.name for p in system.parameters), defaults, function
    )
