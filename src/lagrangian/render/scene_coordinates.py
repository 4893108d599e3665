"""The panel of coordinates that are not positions in space: of a model given by its energies
alone (a mass on a spring written as T and V, the Hénon–Heiles star), or a circuit's
mechanical part (a servo's rotor angle).  They are drawn moving, never as nothing:

- one coordinate: a point on a vertical axis at its value, its past as a trace running left
  (a strip chart: the last :data:`WINDOW` of the run);
- two: the point (q1, q2) in the configuration plane, with a trail;
- more: a bar per coordinate, each over the largest value it reaches, with its recent values
  trailing below it.

>>> import lagrangian as lg
>>> from lagrangian.render.scene import scene_of
>>> system = lg.examples.henon_heiles()
>>> scene = scene_of(system, lg.simulate(system, t_span=2.0, samples=21), frames=5)
>>> scene.panels[0].labels, scene.panels[0].kinds()
(('x', 'y'), ['coordinates'])
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from lagrangian.model import System
from lagrangian.render.scene import PALETTE, Element, Panel, Shape, style
from lagrangian.render.timing import FrameStates
from lagrangian.symbolic.conversion import to_sympy

#: The share of the run a strip chart shows, and the frames a trail keeps.
WINDOW = 0.25
TRAIL = 40


def loose_coordinates(system: System) -> list[str]:
    """Coordinates that neither place a point nor are a circuit's charge: drawn as themselves
    (every coordinate of a model with nothing else to draw)."""
    placed: set[str] = set()
    for position in system.points().values():
        for x in position:
            placed |= {s.name for s in to_sympy(x).free_symbols}
    for body in system.rigid_bodies:  # a body's angles turn its drawn shape
        if body.angle is not None:
            placed |= {s.name for s in to_sympy(body.angle).free_symbols}
        if body.orientation is not None:
            placed |= {s.name for s in to_sympy(body.orientation.matrix).free_symbols}
    for element in system.circuit:
        for key in ("current", "charge", "coordinate"):
            value = getattr(element, key, None)
            if value is not None:
                placed |= {s.name.removesuffix("_dot") for s in to_sympy(value).free_symbols}
        for current in getattr(element, "currents", ()):
            placed |= {s.name.removesuffix("_dot") for s in to_sympy(current).free_symbols}
    if not [n for n in system.points() if n != "origin"] and not system.circuit:
        return []  # nothing else: the caller draws them all
    return [q.name for q in system.coordinates if q.name not in placed]


def coordinates_panel(system: System, states: FrameStates, names: Sequence[str]) -> Panel:
    """The panel of ``names`` (see the module's docstring)."""
    values = np.stack([states.column(name) for name in names], axis=1)  # (F, k)
    if len(names) == 1:
        return _strip(states, names[0], values[:, 0])
    if len(names) == 2:
        dot = Shape("dot", {"at": values}, {"color": PALETTE[0], "size": 8.0, "trail": TRAIL},
                    moving=True)  # fmt: skip
        element = Element("coordinates", (dot,), ", ".join(names), {"names": list(names)})
        return Panel("configuration space", _box(values[:, 0], values[:, 1]), (element,),
                     equal=False, labels=(names[0], names[1]))  # fmt: skip
    return _bars(names, values)


def _box(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float, float]:
    def range_of(v: np.ndarray) -> tuple[float, float]:
        finite = v[np.isfinite(v)]
        low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
        pad = 0.1 * (high - low) or 0.1 * max(abs(low), 1.0)
        return low - pad, high + pad

    return (*range_of(x), *range_of(y))


def _strip(states: FrameStates, name: str, value: np.ndarray) -> Panel:
    """One coordinate: the point at its value, its last WINDOW of the run trailing left."""
    frames = len(value)
    window = max(round(WINDOW * frames), 2)
    span = float(states.t[min(window, frames) - 1] - states.t[0]) or 1.0  # the time it shows
    trace = np.empty((frames, window, 2))
    for k in range(frames):
        past = np.arange(k - window + 1, k + 1).clip(0)
        trace[k, :, 0] = states.t[past] - states.t[k]
        trace[k, :, 1] = value[past]
    at = np.stack([np.zeros(frames), value], axis=1)
    shapes = (
        Shape("line", {"points": trace}, style(PALETTE[0], 1.5), moving=True),
        Shape("dot", {"at": at}, {"color": PALETTE[0], "size": 9.0, "trail": 0}, moving=True),
    )
    element = Element("coordinates", shapes, name, {"names": [name]})
    box = _box(np.array([-span, 0.0]), value)
    return Panel(f"{name} (its last {span:.3g} s trailing left)", (-span * 1.05, span * 0.15,
                 box[2], box[3]), (element,), equal=False, labels=("t - now", name))  # fmt: skip


def _bars(names: Sequence[str], values: np.ndarray) -> Panel:
    """A bar per coordinate over its largest |value|, the recent values trailing below."""
    largest = np.nanmax(np.abs(values), axis=0)
    largest[~(largest > 0)] = 1.0
    scaled = values / largest
    frames = len(values)
    shapes: list[Shape] = []
    for i, name in enumerate(names):
        row = -float(i)
        bar = np.zeros((frames, 2, 2))
        bar[:, :, 1] = row
        bar[:, 1, 0] = scaled[:, i]
        trail = np.empty((frames, TRAIL, 2))
        for k in range(frames):
            past = np.arange(k - TRAIL + 1, k + 1).clip(0)
            trail[k, :, 0] = scaled[past, i]
            trail[k, :, 1] = row - 0.4 * (k - np.arange(k - TRAIL + 1, k + 1)) / TRAIL
        color = PALETTE[i % len(PALETTE)]
        shapes += [
            Shape("line", {"points": trail}, style(color, 1.0), moving=True),
            Shape("line", {"points": bar}, style(color, 8.0), moving=True),
            Shape("text", {"at": np.array([-1.25, row]), "text": name}, {"color": "#333333"}),
        ]
    axis = Shape("line", {"points": np.array([[0.0, 0.5], [0.0, -len(names) + 0.5]])},
                 style("#4d4d4d", 1.0))  # fmt: skip
    element = Element("coordinates", (axis, *shapes), ", ".join(names), {"names": list(names)})
    return Panel("coordinates / largest |value|", (-1.35, 1.1, -len(names) + 0.3, 0.7),
                 (element,), equal=False)  # fmt: skip
