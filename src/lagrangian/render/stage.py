"""The numbers a mechanical scene is built from: every named point in world axes at every
frame, any expression of the state evaluated at every frame, and the view that flattens
world points onto the page.

World points are 3-D: a planar system's have z = 0, a 1-D system's lie along x, or along the
vertical y when gravity acts along its axis (a mass hanging on a spring is drawn hanging).

>>> import lagrangian as lg
>>> from lagrangian.render.timing import frame_states
>>> system = lg.examples.simple_pendulum()
>>> stage = stage_of(system, frame_states(lg.simulate(system, t_span=1.0, samples=3), 3), "auto")
>>> stage.world.shape, stage.flat(stage.world).shape
((3, 1, 3), (3, 1, 2))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.model import System
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.numerics.points import compile_points
from lagrangian.render.projection import chosen_projection
from lagrangian.render.timing import FrameStates
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t


@dataclass(frozen=True)
class Stage:
    """``system`` at the frames ``states``: its points' names and ``world`` positions (F, P,
    3), the parameter vector ``p``, the ``view`` (2 x 3) and its name, whether the system is
    3-D, and ``span``, the half-width of the region the points reach."""

    system: System
    states: FrameStates
    names: tuple[str, ...]
    world: np.ndarray
    p: np.ndarray
    view: np.ndarray
    view_name: str
    three_d: bool
    span: float
    vertical: bool = False  # a 1-D system drawn along y

    @property
    def frames(self) -> int:
        return len(self.states.t)

    def flat(self, world: np.ndarray) -> np.ndarray:
        """World points (..., 3) on the page (..., 2)."""
        return np.asarray(world) @ self.view.T

    def point(self, name: str) -> np.ndarray:
        """A named point at every frame, (F, 3); the origin is 0."""
        if name == "origin":
            return np.zeros((self.frames, 3))
        return self.world[:, self.names.index(name)]

    def evaluate(self, expressions: list[Any]) -> np.ndarray:
        """``expressions`` of (q, t, p) at every frame, (F, len(expressions))."""
        return self.at_states(expressions, self.states.q, self.states.t)

    def at_states(self, expressions: list[Any], q: np.ndarray, times: np.ndarray) -> np.ndarray:
        """``expressions`` at the states ``q`` (K, n) and ``times`` (K,), (K, len)."""
        return values_at(self.system, expressions, q, times, self.p)

    def anchor(self, ref: Any) -> np.ndarray:
        """The world position (F, 3) of an end of a spring or damper: a point's name, or a
        position such as (a, 0) whose parameters (and state, if it moves) are put in."""
        if isinstance(ref, str):
            return self.point(ref)
        return self.lift(self.evaluate(list(ref)))

    def lift(self, values: np.ndarray) -> np.ndarray:
        """Positions in the system's own dimension (F, d) as world points (F, 3)."""
        padded = np.zeros((values.shape[0], 3))
        if self.vertical:
            padded[:, 1] = values[:, 0]
        else:
            padded[:, : values.shape[1]] = values
        return padded

    def number(self, expression: Any) -> float:
        """An expression of the parameters alone as a number (NaN when it is not one)."""
        values = {sp.Symbol(k): v for k, v in self.states.parameters.items()}
        try:
            return float(to_sympy(expression).subs(values))
        except (TypeError, ValueError):
            return float("nan")

    def pixels(self, fraction: float) -> float:
        """A length on the page: ``fraction`` of the scene's half-width."""
        return fraction * self.span


def values_at(
    system: System, expressions: list[Any], q: np.ndarray, times: np.ndarray, p: np.ndarray
) -> np.ndarray:
    """``expressions`` of (q, t, p) at the states ``q`` (K, n), ``times`` (K,) and the
    parameter vector ``p`` (in the order of ``system.parameters``), (K, len(expressions))."""
    groups = (list(system.coordinates), t, list(system.parameters))
    function = NumericFunction(groups, [to_sympy(e) for e in expressions],
                               shape=(len(expressions),))  # fmt: skip
    return np.asarray(function(q, times, p), dtype=float).reshape(len(q), -1)


def frame_values(system: System, states: FrameStates, expressions: list[Any]) -> np.ndarray:
    """``expressions`` of (q, t, p) at every frame of ``states`` with the run's parameters,
    (F, len(expressions)): what a picture without points needs (a circuit's charges)."""
    p = np.array([states.parameters.get(s.name, np.nan) for s in system.parameters])
    return values_at(system, expressions, states.q, states.t, p)


def stage_of(system: System, states: FrameStates, projection: str) -> Stage:
    """The :class:`Stage` of ``system`` at ``states``, seen in ``projection``."""
    points = compile_points(system)
    p = points.parameter_vector(states.parameters)
    raw = np.asarray(points(states.q, states.t, p), dtype=float)
    raw = raw.reshape(len(states.t), len(points.names), points.dimension)
    vertical = points.dimension == 1 and system.gravity is not None
    world = np.zeros((*raw.shape[:2], 3))
    if vertical:
        world[..., 1] = raw[..., 0]
    else:
        world[..., : points.dimension] = raw
    three_d = points.dimension == 3
    name, view = chosen_projection(projection, world) if three_d else ("xy", _plane())
    finite = world[np.isfinite(world)]
    span = float(np.max(np.abs(finite), initial=0.0)) or 1.0
    return Stage(system, states, points.names, world, p, view, name, three_d, span, vertical)


def _plane() -> np.ndarray:
    return np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
