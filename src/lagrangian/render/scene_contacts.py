"""What a planar system's unilateral constraints say about the shapes in contact: the disks and
the walls of a gas of hard disks, a ball's floor.

Two forms are read from the constraints themselves, never from a model's names:

- *a distance kept*: ``g = |P_a - P_b|^2 - d^2 >= 0`` between two particles (``g`` minus the
  squared distance of their positions is free of the coordinates) makes each a disk of radius
  d / 2 (the least such d when there are several);
- *a wall*: ``g = n . P_a + c >= 0``, affine in the position of one particle whose position
  components are coordinates (or constants): the particle's centre stays on one side of the
  line ``n . X + c = 0``, so the wall itself is that line moved by the particle's radius
  against n.  Walls that coincide (the box of every disk) are drawn once.

A particle with a radius is drawn as a disk of that radius (``particle`` elements of
:mod:`~lagrangian.render.scene_mechanics`), a wall as a ``wall`` element: a segment across the
box the walls and the disks span.

>>> import lagrangian as lg
>>> contacts = contacts_of(lg.examples.hard_disk_gas(2))
>>> sorted(contacts.radii.items())
[('disk1', 0.1), ('disk2', 0.1)]
>>> sorted({wall.normal for wall in contacts.walls})
[(-1.0, 0.0), (0.0, -1.0), (0.0, 1.0), (1.0, 0.0)]
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from itertools import combinations
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.model import System, Unilateral
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t

#: Digits to which two walls are the same wall.
SAME_WALL = 9


@dataclass(frozen=True)
class Wall:
    """The line ``normal . X = offset`` (unit normal) that a particle of radius ``radius``
    stays on the side of ``normal`` of, its centre ``radius`` away: ``particle`` names it."""

    normal: tuple[float, float]
    offset: float
    particle: str


@dataclass(frozen=True)
class Contacts:
    """The particles' ``radii`` (name -> radius) and the ``walls`` their constraints give."""

    radii: Mapping[str, float]
    walls: tuple[Wall, ...]


def contacts_of(system: System) -> Contacts:
    """The disks and walls the unilateral constraints of a planar ``system`` describe, at
    its parameters' values (none for a 3-D system, or one without particles)."""
    positions = {p.name: tuple(to_sympy(x) for x in p.position) for p in system.particles}
    if not positions or any(len(position) != 2 for position in positions.values()):
        return Contacts({}, ())
    values = {s: v for s, v in system.parameters.items() if v is not None}
    coordinates = set(system.coordinates)
    uses = {name: _coordinates_in(position, coordinates) for name, position in positions.items()}
    radii: dict[str, float] = {}
    affine: list[tuple[str, sp.Expr]] = []
    for constraint in system.constraints:
        if not isinstance(constraint, Unilateral):
            continue
        g = to_sympy(constraint.expression)
        involved = _coordinates_in((g,), coordinates)
        if not involved or t in g.free_symbols:
            continue
        touching = [name for name, used in uses.items() if used & involved]
        if len(touching) == 2 and uses[touching[0]] | uses[touching[1]] >= involved:
            distance = _kept_distance(g, positions[touching[0]], positions[touching[1]], values)
            if distance is not None:  # two disks in contact at d: each of radius d / 2
                for name in touching:
                    radii[name] = min(radii.get(name, math.inf), distance / 2)
        elif len(touching) == 1 and uses[touching[0]] >= involved:
            affine.append((touching[0], g))
    walls = [_wall(g, positions[name], name, values) for name, g in affine]
    found = {_wall_key(w, radii): w for w in walls if w is not None}
    return Contacts(radii, tuple(found.values()))


def _coordinates_in(expressions: Any, coordinates: set[sp.Symbol]) -> frozenset[sp.Symbol]:
    return frozenset(s for e in expressions for s in e.free_symbols if s in coordinates)


def _kept_distance(
    g: sp.Expr, a: tuple[sp.Expr, ...], b: tuple[sp.Expr, ...], values: dict[Any, Any]
) -> float | None:
    """d when ``g = |a - b|^2 - d^2`` with d a positive constant, else None."""
    squared = sum(((x - y) ** 2 for x, y in zip(a, b)), sp.Integer(0))
    rest = sp.expand(g - squared)
    if rest.free_symbols - set(values):
        return None
    number = -float(rest.subs(values))
    return math.sqrt(number) if number > 0 else None


def _wall(g: sp.Expr, position: tuple[sp.Expr, ...], name: str, values: dict[Any, Any]) -> Any:
    """The wall ``g >= 0`` puts on the particle ``name``, when g is affine in its position
    and its position components are coordinates or constants; else None."""
    normal = []
    for component in position:
        if component.free_symbols - set(values) and not component.is_Symbol:
            return None
        slope = sp.diff(g, component) if component.is_Symbol else sp.Integer(0)
        if slope.free_symbols - set(values):
            return None  # not affine in the position
        normal.append(float(slope.subs(values)))
    size = math.hypot(*normal)
    if size == 0:
        return None
    at_zero = g.subs({c: 0 for c in position if c.is_Symbol}).subs(values)
    if at_zero.free_symbols:
        return None
    unit = (normal[0] / size, normal[1] / size)
    # n . X + c >= 0 for the centre: n . X >= -c / |n|, with the unit normal
    return Wall(unit, -float(at_zero) / size, name)


def _wall_key(wall: Wall, radii: Mapping[str, float]) -> tuple[float, float, float]:
    """Where the wall itself is: its normal and its offset less the particle's radius."""
    face = wall.offset - radii.get(wall.particle, 0.0)
    return (round(wall.normal[0], SAME_WALL), round(wall.normal[1], SAME_WALL), round(face, 6))


def wall_segments(
    contacts: Contacts, centres: Mapping[str, np.ndarray]
) -> list[tuple[Wall, np.ndarray]]:
    """Each wall's face as a segment (2, 2) across the box that the disks (``centres``: name
    -> (F, 2) over the run) and the walls' faces span."""
    faces = [(w, w.offset - contacts.radii.get(w.particle, 0.0)) for w in contacts.walls]
    low, high = _disks_box(contacts, centres)
    for wall, face in faces:  # a wall along an axis bounds the box on its side
        nx, ny = wall.normal
        if abs(nx) > 1 - 1e-12:
            low[0], high[0] = min(low[0], face * nx), max(high[0], face * nx)
        if abs(ny) > 1 - 1e-12:
            low[1], high[1] = min(low[1], face * ny), max(high[1], face * ny)
    made = []
    for wall, face in faces:
        segment = _clipped(np.array(wall.normal), face, low, high)
        if segment is not None:
            made.append((wall, segment))
    return made


def _disks_box(
    contacts: Contacts, centres: Mapping[str, np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    low, high = np.full(2, np.inf), np.full(2, -np.inf)
    for name, path in centres.items():
        finite = path[np.all(np.isfinite(path), axis=1)]
        if len(finite):
            reach = contacts.radii.get(name, 0.0)
            low = np.minimum(low, finite.min(axis=0) - reach)
            high = np.maximum(high, finite.max(axis=0) + reach)
    return low, high


def _clipped(normal: np.ndarray, face: float, low: np.ndarray, high: np.ndarray) -> Any:
    """The part of the line normal . X = face inside the box [low, high] (None if none)."""
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
        return None
    corners = [(low[0], low[1]), (high[0], low[1]), (high[0], high[1]), (low[0], high[1])]
    points = []
    for a, b in combinations(np.array(corners), 2):
        if not (a[0] == b[0] or a[1] == b[1]):
            continue  # a diagonal, not an edge
        da, db = normal @ a - face, normal @ b - face
        if da == db:
            if abs(da) < 1e-12:
                points += [a, b]
            continue
        s = da / (da - db)
        if -1e-12 <= s <= 1 + 1e-12:
            points.append(a + s * (b - a))
    if len(points) < 2:
        return None
    ordered = sorted(points, key=lambda p: float(p @ np.array([-normal[1], normal[0]])))
    return np.array([ordered[0], ordered[-1]])
