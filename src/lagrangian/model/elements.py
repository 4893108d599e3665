"""Mechanical elements a System is built from: particles, rigid bodies (planar or 3-D),
springs, dampers, and forces and torques applied at points.

Each element is an immutable value holding SymPy expressions.  A *point* is named by the
particle or body it belongs to (the body's centre of mass), by ``"origin"``, or given as a
position vector (a fixed anchor, or one that moves with time).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, is_dataclass
from typing import Any

import sympy as sp

from lagrangian.model.inertia import Shape
from lagrangian.model.rotation import Orientation, as_orientation

#: A point: the name of a particle or body, ``"origin"``, or a position vector.
PointRef = str | tuple[sp.Expr, ...]

ORIGIN = "origin"


def as_expression(value: Any) -> Any:
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
        return tuple(as_expression(v) for v in value)
    except TypeError:
        return value


def _point(value: Any) -> Any:
    return value if isinstance(value, str) else _vector(value)


def _points(value: Any) -> Any:
    """The two ends of a spring or damper; anything but a list is kept for the validator."""
    if isinstance(value, (list, tuple)):
        return tuple(_point(p) for p in value)
    return value


@dataclass(frozen=True)
class Particle:
    """A point mass at ``position`` (1, 2 or 3 components, functions of q and t).

    T = 1/2 m |dr/dt|^2; a uniform gravity field g adds V = -m g.r.
    """

    name: str
    mass: sp.Expr
    position: tuple[sp.Expr, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", as_expression(self.mass))
        object.__setattr__(self, "position", _vector(self.position))


def _matrix(value: Any) -> Any:
    """A matrix (SymPy or nested lists of expressions and numbers) as an ImmutableMatrix;
    anything else is kept for the validator to judge (text is never evaluated)."""
    if isinstance(value, sp.MatrixBase):
        return sp.ImmutableMatrix(value)
    rows = value if isinstance(value, (list, tuple)) else None
    if rows and all(isinstance(r, (list, tuple)) and len(r) == len(rows[0]) for r in rows):
        entries = [[as_expression(v) for v in r] for r in rows]
        if all(isinstance(v, sp.Expr) for r in entries for v in r):
            return sp.ImmutableMatrix(entries)
    return value


def _inertia(value: Any) -> Any:
    return value if isinstance(value, Shape) else as_expression(_matrix(value))


def orientation_value(value: Any) -> Any:
    """An Orientation from an Orientation or a 3x3 matrix; None and anything else kept (for
    the validator to judge)."""
    if value is None or isinstance(value, Orientation):
        return value
    matrix = _matrix(value)
    return as_orientation(matrix) if isinstance(matrix, sp.MatrixBase) else value


def as_rotations(value: Any) -> Any:
    """Simple rotations ``[(axis, angle), ...]`` as a tuple of pairs, the angles as
    expressions and the axes as given (a name or a vector, judged by the validator);
    anything else is kept for the validator."""
    if not isinstance(value, (list, tuple)):
        return value
    pairs = []
    for item in value:
        if isinstance(item, (list, tuple)) and len(item) == 2:
            axis, angle = item
            axis = axis if isinstance(axis, str) else _vector(axis)
            pairs.append((axis, as_expression(angle)))
        else:
            pairs.append(item)
    return tuple(pairs)


@dataclass(frozen=True)
class RigidBody:
    """A rigid body: planar (a scalar inertia and an ``angle``) or 3-D (an ``orientation``).

    Planar: the centre of mass at ``position`` (2 components), the moment of inertia about
    it, and the orientation angle: T = 1/2 m |dr_c/dt|^2 + 1/2 I (d angle/dt)^2.

    3-D: the centre at ``position`` (3 components), the rotation R(q, t) of the body axes
    (``orientation``: an :class:`~lagrangian.model.rotation.Orientation` or a 3x3 matrix,
    body -> world), and ``inertia`` about the centre in body axes (a 3x3 matrix or a
    :class:`~lagrangian.model.inertia.Shape`, whose tensor follows from the mass):

        T = 1/2 m v_c . v_c + 1/2 omega_b^T I omega_b,   omega_b = vee(R^T R_dot).

    A 3-D body may instead be oriented relative to a ``parent`` (the name of a 3-D body or a
    :class:`~lagrangian.model.frames.Frame`; the world when None) by ``rotations``, simple
    rotations ``[("z", psi), ("x", theta), ...]`` about its own successive axes:
    R = R_parent R1(psi) R2(theta) ..., and omega is composed from the parent's
    (:func:`~lagrangian.model.rotation.rotation_sequence`).  The System fills ``orientation``
    with that composed rotation; ``position`` stays in world axes.
    """

    name: str
    mass: sp.Expr
    inertia: Any  # planar: sp.Expr; 3-D: a 3x3 sp.ImmutableMatrix or a Shape
    position: tuple[sp.Expr, ...]
    angle: sp.Expr | None = None
    orientation: Orientation | None = None
    parent: str | None = None
    rotations: tuple[tuple[Any, sp.Expr], ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", as_expression(self.mass))
        object.__setattr__(self, "inertia", _inertia(self.inertia))
        object.__setattr__(self, "position", _vector(self.position))
        object.__setattr__(self, "angle", None if self.angle is None else as_expression(self.angle))
        object.__setattr__(self, "orientation", orientation_value(self.orientation))
        object.__setattr__(self, "rotations", as_rotations(self.rotations))

    @property
    def relative(self) -> bool:
        """True when the body is oriented by ``rotations`` relative to a parent (or the world)."""
        return self.parent is not None or bool(self.rotations)

    @property
    def planar(self) -> bool:
        """True for a planar body (given an angle), False for a 3-D one (an orientation)."""
        return self.orientation is None and not self.relative

    @property
    def inertia_tensor(self) -> sp.ImmutableMatrix:
        """The 3x3 inertia about the centre of mass in body axes (a shape's, from the mass)."""
        if self.planar:
            raise ValueError(f"the planar body {self.name!r} has a scalar moment of inertia")
        if isinstance(self.inertia, Shape):
            return self.inertia.tensor(self.mass)
        if isinstance(self.inertia, sp.ImmutableMatrix):
            return self.inertia  # a value: the same matrix, not a copy built again
        return sp.ImmutableMatrix(self.inertia)


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
        object.__setattr__(self, "between", _points(self.between))
        object.__setattr__(self, "stiffness", as_expression(self.stiffness))
        object.__setattr__(self, "rest_length", as_expression(self.rest_length))


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
        object.__setattr__(self, "between", _points(self.between))
        object.__setattr__(self, "coefficient", as_expression(self.coefficient))


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
    """A torque on a rigid body, turned into generalized forces by virtual work.

    Planar body: a scalar tau, Q_j = tau * d(angle)/dq_j.  3-D body: a 3-vector in world
    axes, Q_j = tau . d(omega_s)/d(q_dot_j), omega_s the spatial angular velocity.  It may
    depend on q, the velocities and t.
    """

    body: str
    torque: Any  # planar: sp.Expr; 3-D: tuple of 3 expressions (world axes)
    name: str = field(default="")

    def __post_init__(self) -> None:
        value = self.torque
        vector = isinstance(value, (list, tuple, sp.MatrixBase))
        object.__setattr__(self, "torque", _vector(value) if vector else as_expression(value))


def as_tuple(items: Sequence[Any] | None) -> tuple[Any, ...]:
    """``None`` or a sequence as a tuple (a single element becomes a 1-tuple)."""
    if items is None:
        return ()
    if is_dataclass(items) and not isinstance(items, type):  # a single element
        return (items,)
    return tuple(items)
