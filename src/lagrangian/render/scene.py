"""One scene of a simulated System, computed once and drawn by every front end (the
matplotlib animations, the HTML player, the playground's canvas, Jupyter).

A :class:`Scene` is plain data: panels of elements that name the physics (a particle, a rod,
a spring with its rest length, a disc with the radius line that shows its rotation, the wire
a bead runs on, a pulley and its strings, a 3-D body's outline and axes, a circuit's
resistor...), each drawn as a few *shapes* in the panel's plane; the numbers of a shape that
moves are given for every frame.  A front end needs no physics to draw it: lines, circles,
dots and text in 2-D (a 3-D system comes projected, :mod:`lagrangian.render.projection`).

``Scene.to_dict()`` is JSON (format ``"lagrangian-scene"``, version 1)::

    {"format": "lagrangian-scene", "version": 1, "name": str,
     "times": [t_0, ..., t_F-1],          # the time of each frame
     "fps": float,                         # frames per second of the playback
     "impacts": [{"frame": k, "label": str}],   # flash these frames (impacts, transitions)
     "panels": [{"title": str, "bounds": [xmin, xmax, ymin, ymax], "equal": bool,
                 "labels": [x label, y label] or null,
                 "elements": [{"kind": str, "name": str, "info": {...}, "shapes": [shape...]}]}]}

    shape = {"type": "line", "points": P, "color": "#rrggbb", "width": px, "dash": bool?,
             "moving": [keys]}                  # P: [[x, y], ...]; per frame [[[x, y], ...], ...]
          | {"type": "circle", "centre": [x, y], "radius": r, "color", "width", "moving"}
          | {"type": "dot", "at": [x, y], "size": px, "color", "trail": n, "moving"}
                                                # trail: also draw the dot's last n places
          | {"type": "text", "at": [x, y], "text": S, "color", "moving"}

``moving`` lists the keys given per frame (frames first: ``points[k]`` is the polyline at
frame k, ``text[k]`` its words then); a key not listed holds for every frame.

``kind`` is one of :data:`KINDS`; ``info`` holds its physical numbers (a spring's
``rest_length`` and ``stiffness``, a disc's ``radius``, a rod's ``length``, a wire's
``curve`` ("circle", "line", "parabola"), a capacitor's ``capacitance``...).  Widths and
sizes are in pixels of a 400-pixel panel; everything else is in the panel's own units.

>>> import lagrangian as lg
>>> system = lg.examples.simple_pendulum()
>>> scene = scene_of(system, lg.simulate(system, t_span=1.0, samples=11), frames=5)
>>> [element.kind for element in scene.panels[0].elements]
['rod', 'particle']
>>> scene.to_dict()["panels"][0]["elements"][1]["shapes"][0]["type"]
'dot'
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lagrangian.model import System
from lagrangian.simulation.trajectory import Trajectory

#: The kinds of element a scene holds.
KINDS = (
    "particle", "rod", "spring", "damper", "disc", "body", "body_axes", "wire", "ground",
    "pulley", "string", "resistor", "inductor", "capacitor", "source", "mutual", "wire_circuit",
    "current", "coordinates", "wall",
)  # fmt: skip

#: Significant digits kept in the JSON (a pixel of a 1000-pixel picture is 3).
DIGITS = 5


#: The key of each shape type that is given per frame when the shape moves.
MOVING_KEYS = {"line": ("points",), "circle": ("centre",), "dot": ("at",), "text": ("text",)}


@dataclass(frozen=True)
class Shape:
    """One drawn primitive: ``type`` line, circle, dot or text, its ``data`` and its
    ``style`` (color, width, ...); ``moving`` names the keys of ``data`` given per frame
    (frames first), True for the type's usual one (:data:`MOVING_KEYS`)."""

    type: str
    data: Mapping[str, Any]
    style: Mapping[str, Any] = field(default_factory=dict)
    moving: bool | tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.moving, bool):
            keys = MOVING_KEYS[self.type] if self.moving else ()
            object.__setattr__(self, "moving", keys)

    @property
    def moving_keys(self) -> tuple[str, ...]:
        """The keys of ``data`` given per frame."""
        return self.moving if isinstance(self.moving, tuple) else ()

    def at(self, key: str, frame: int) -> Any:
        """``data[key]`` at ``frame`` (the same at every frame when it does not move)."""
        value = self.data[key]
        return value[frame] if key in self.moving_keys else value

    def to_dict(self) -> dict[str, Any]:
        data = {key: _plain(value) for key, value in self.data.items()}
        return {"type": self.type, **data, **dict(self.style), "moving": list(self.moving_keys)}


@dataclass(frozen=True)
class Element:
    """A piece of the system as it is drawn: its ``kind`` (:data:`KINDS`), ``name``, the
    numbers that describe it (``info``) and its ``shapes``."""

    kind: str
    shapes: tuple[Shape, ...]
    name: str = ""
    info: Mapping[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "name": self.name,
            "info": {key: _plain(value) for key, value in self.info.items()},
            "shapes": [shape.to_dict() for shape in self.shapes],
        }


@dataclass(frozen=True)
class Panel:
    """A drawing area: its ``title``, its ``bounds`` (xmin, xmax, ymin, ymax), whether its
    axes have ``equal`` scales (space) or not (coordinates), axis ``labels`` and
    ``elements`` (drawn in order)."""

    title: str
    bounds: tuple[float, float, float, float]
    elements: tuple[Element, ...]
    equal: bool = True
    labels: tuple[str, str] | None = None

    def __post_init__(self) -> None:
        if self.equal:  # a square panel shows equal scales edge to edge
            xmin, xmax, ymin, ymax = self.bounds
            half = max(xmax - xmin, ymax - ymin) / 2
            x, y = (xmin + xmax) / 2, (ymin + ymax) / 2
            object.__setattr__(self, "bounds", (x - half, x + half, y - half, y + half))

    def to_dict(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "bounds": [_round(b) for b in self.bounds],
            "equal": self.equal,
            "labels": list(self.labels) if self.labels else None,
            "elements": [element.to_dict() for element in self.elements],
        }

    def kinds(self) -> list[str]:
        """The kinds of its elements, in drawing order."""
        return [element.kind for element in self.elements]


@dataclass(frozen=True)
class Scene:
    """The whole picture of a run: ``panels`` drawn side by side at the frame ``times``,
    played at ``fps``, with the ``impacts`` (frame, label) flashed."""

    name: str
    times: np.ndarray
    panels: tuple[Panel, ...]
    fps: float = 25.0
    impacts: tuple[tuple[int, str], ...] = ()

    @property
    def frames(self) -> int:
        return len(self.times)

    def elements(self, kind: str) -> list[Element]:
        """Every element of ``kind``, in every panel."""
        return [e for panel in self.panels for e in panel.elements if e.kind == kind]

    def to_dict(self) -> dict[str, Any]:
        """The scene as JSON-able data (the format in this module's docstring)."""
        return {
            "format": "lagrangian-scene",
            "version": 1,
            "name": self.name,
            "times": _plain(self.times),
            "fps": float(self.fps),
            "impacts": [{"frame": int(k), "label": label} for k, label in self.impacts],
            "panels": [panel.to_dict() for panel in self.panels],
        }

    def to_json(self) -> str:
        """:meth:`to_dict` as compact JSON text."""
        return json.dumps(self.to_dict(), separators=(",", ":"), allow_nan=False)


def _round(value: float) -> float:
    if not np.isfinite(value):
        return 0.0  # JSON has no NaN: a point that left the run is drawn at the origin
    return float(f"{value:.{DIGITS}g}")


def _plain(value: Any) -> Any:
    """Arrays as nested lists of rounded floats; strings and lists of strings as they are."""
    if isinstance(value, str) or value is None or isinstance(value, bool):
        return value
    if isinstance(value, (list, tuple)) and value and isinstance(value[0], str):
        return list(value)
    array = np.asarray(value, dtype=float)
    if array.ndim == 0:
        return _round(float(array))
    return _significant(array).tolist()


def _significant(array: np.ndarray) -> np.ndarray:
    """:func:`_round` of every number at once: n = x / 10^e rounded to an integer of DIGITS
    digits, then n * 10^e (or n / 10^-e) with an exact power of ten, which IEEE arithmetic
    rounds to the double nearest the decimal, as ``float(f"{x:.5g}")`` does."""
    out = np.zeros(array.shape)
    usable = np.isfinite(array) & (array != 0)
    x = array[usable]
    e = np.floor(np.log10(np.abs(x))).astype(int) - (DIGITS - 1)
    exact = np.abs(e) <= 22  # the powers of ten a double holds exactly
    r = np.array([_round(v) for v in x[~exact]]) if (~exact).any() else np.empty(0)
    rounded = np.empty_like(x)
    rounded[~exact] = r
    down, up = exact & (e < 0), exact & (e >= 0)
    scale = 10.0 ** -e[down]
    rounded[down] = np.round(x[down] * scale) / scale
    scale = 10.0 ** e[up]
    rounded[up] = np.round(x[up] / scale) * scale
    out[usable] = rounded
    return out


def scene_of(
    system: System,
    trajectory: Trajectory,
    *,
    frames: int | None = None,
    fps: float | None = None,
    projection: str = "auto",
    rows: Sequence[int] | np.ndarray | None = None,
) -> Scene:
    """The scene of ``trajectory``: ``frames`` evenly spaced times (default: from the
    motion's time scale, :func:`lagrangian.render.timing.frame_count`), or the run's own
    samples at ``rows`` (indices into ``trajectory.t``, increasing: frame k is sample
    ``rows[k]``, as a player whose time slider walks the samples needs), played at ``fps``
    (default :data:`~lagrangian.render.timing.FPS`); a 3-D system seen in ``projection``
    ("auto", "xy", "xz", "yz", "isometric").  Mechanical parts, the circuit and the
    coordinates without geometry each get a panel; a system with none gets the coordinates."""
    from lagrangian.render.scene_circuit import circuit_panel
    from lagrangian.render.scene_coordinates import coordinates_panel, loose_coordinates
    from lagrangian.render.scene_mechanics import mechanics_panel
    from lagrangian.render.timing import (
        FPS,
        frame_count,
        frame_states,
        impact_frames,
        sample_states,
    )

    if rows is not None:
        if frames is not None:
            raise ValueError("scene_of takes frames or rows, not both: leave one out")
        states = sample_states(trajectory, rows)
    else:
        states = frame_states(trajectory, frames if frames is not None else frame_count(trajectory))
    panels = [
        panel
        for panel in (
            mechanics_panel(system, states, projection),
            circuit_panel(system, states),
        )
        if panel is not None
    ]
    loose = loose_coordinates(system)
    if loose or not panels:
        panels.append(coordinates_panel(system, states, loose or _all_names(system)))
    name = system.name or "system"
    return Scene(
        name, states.t, tuple(panels), float(fps or FPS), impact_frames(trajectory, states)
    )


def _all_names(system: System) -> Sequence[str]:
    return [q.name for q in system.coordinates]


def shapes_of(scene: Scene, kind: str) -> list[Shape]:
    """Every shape of the elements of ``kind`` (for tests and front ends that pick)."""
    return [shape for element in scene.elements(kind) for shape in element.shapes]


__all__ = ["KINDS", "Element", "Panel", "Scene", "Shape", "scene_of", "shapes_of"]


def style(color: str = "#4d4d4d", width: float = 1.5, **more: Any) -> dict[str, Any]:
    """A shape's style: its ``color`` (hex), ``width`` in pixels and any more keys."""
    return {"color": color, "width": width, **more}


#: The colours of the particles, in order (matplotlib's default cycle, as hex for the web).
PALETTE = (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
)  # fmt: skip
