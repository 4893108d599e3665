"""Mechanical elements a System is built from: particles, planar rigid bodies, springs,
dampers, and forces and torques applied at points.

Each element is an immutable value holding SymPy expressions.  A *point* is named by the
particle or body it belongs to (the body's centre of mass), by ``"origin"``, or given as a
position vector (a fixed anchor, or one that moves with time).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, is_dataclass
from typing import Any

import sympy as sp

#: A point: the name of a particle or body, ``"origin"``, or a position vector.
PointRef = str | tuple[sp.Expr, ...]

ORIGIN = "origin"


def _expr(value: Any) -> Any:
    """Numbers become SymPy numbers; everything else is kept for the validator to judge."""
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        return sp.nsimplify(value, rational=True) if isinstance(value, float) else sp.Integer(value)
    return value


def _vector(value: Any) -> Any:
    if isinstance(value, (str, sp.Basic)) and not isinstance(value, sp.MatrixBase):
        return value  # not a vector; the validator says so
    try:
        return tuple(_expr(v) for v in value)
    except TypeError:
        return value


def _point(value: Any) -> Any:
    return value if isinstance(value, str) else _vector(value)


@dataclass(frozen=True)
class Particle:
    """A point mass at ``position`` (1, 2 or 3 components, functions of q and t).

    T = 1/2 m |dr/dt|^2; a uniform gravity field g adds V = -m g.r.
    """

    name: str
    mass: sp.Expr
    position: tuple[sp.Expr, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _expr(self.mass))
        object.__setattr__(self, "position", _vector(self.position))


@dataclass(frozen=True)
class RigidBody:
    """A planar rigid body: mass, moment of inertia about its centre of mass, the position
    of the centre (2 components) and its orientation angle.

    T = 1/2 m |dr_c/dt|^2 + 1/2 I (d angle/dt)^2.
    """

    name: str
    mass: sp.Expr
    inertia: sp.Expr
    position: tuple[sp.Expr, ...]
    angle: sp.Expr

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _expr(self.mass))
        object.__setattr__(self, "inertia", _expr(self.inertia))
        object.__setattr__(self, "position", _vector(self.position))
        object.__setattr__(self, "angle", _expr(self.angle))


@dataclass(frozen=True)
class Spring:
    """A linear spring between two points: V = 1/2 k (d - rest_length)^2.

    d is the distance |r_b - r_a|; in one dimension it is the signed x_b - x_a, so a spring
    keeps its order along the line.  With ``rest_length`` 0 the potential is 1/2 k |r_b - r_a|^2.
    """

    between: tuple[PointRef, PointRef]
    stiffness: sp.Expr
    rest_length: sp.Expr = sp.Integer(0)
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "between", tuple(_point(p) for p in self.between))
        object.__setattr__(self, "stiffness", _expr(self.stiffness))
        object.__setattr__(self, "rest_length", _expr(self.rest_length))


@dataclass(frozen=True)
class Damper:
    """A linear viscous damper between two points, acting along the line joining them.

    Rayleigh function F = 1/2 c (dd/dt)^2 with d the distance; in one dimension
    F = 1/2 c (v_b - v_a)^2.
    """

    between: tuple[PointRef, PointRef]
    coefficient: sp.Expr
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "between", tuple(_point(p) for p in self.between))
        object.__setattr__(self, "coefficient", _expr(self.coefficient))


@dataclass(frozen=True)
class Force:
    """A force applied at a point, turned into generalized forces by virtual work:
    Q_j = F . dr/dq_j.  The force may depend on q, the velocities and t.
    """

    at: PointRef
    force: tuple[sp.Expr, ...]
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "at", _point(self.at))
        object.__setattr__(self, "force", _vector(self.force))


@dataclass(frozen=True)
class Torque:
    """A torque on a planar rigid body: Q_j = tau * d(angle)/dq_j."""

    body: str
    torque: sp.Expr
    name: str = field(default="")

    def __post_init__(self) -> None:
        object.__setattr__(self, "torque", _expr(self.torque))


def as_tuple(items: Sequence[Any] | None) -> tuple[Any, ...]:
    """``None`` or a sequence as a tuple (a single element becomes a 1-tuple)."""
    if items is None:
        return ()
    if is_dataclass(items) and not isinstance(items, type):  # a single element
        return (items,)
    return tuple(items)
