"""Inertia of rigid bodies in 3-D: tensors of common shapes about the centre of mass, rotated
and shifted (parallel-axis theorem), bodies combined, and the 6x6 generalized inertia matrix
in body and spatial frames (Murray, Li & Sastry 1994, ch. 4).

    I = integral rho (|r|^2 1 - r r^T) dV      (about the centre of mass, body axes)
    T = 1/2 m v_c . v_c + 1/2 omega_b^T I omega_b = 1/2 V_b^T M^b V_b,  M^b = diag(m 1, I)

Twists are ordered (v, omega) as in MLS94 ch. 2, and M^s = Ad_g^-T M^b Ad_g^-1.

>>> import sympy as sp
>>> m, r, h = sp.symbols("m r h")
>>> cylinder(m, r, h)
Matrix([
[h**2*m/12 + m*r**2/4,                    0,        0],
[                   0, h**2*m/12 + m*r**2/4,        0],
[                   0,                    0, m*r**2/2]])
"""

from __future__ import annotations

import difflib
import random
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.errors import ModelError, Problem, raise_if_problems
from lagrangian.model.rotation import (
    as_expression,
    as_orientation,
    evaluate_matrix,
)
from lagrangian.model.twist import adjoint_inverse
from lagrangian.symbolic.conversion import to_matrix, to_sympy

AXES = ("x", "y", "z")


def _values(*values: Any) -> list[sp.Expr]:
    return [as_expression(v, "inertia") for v in values]


def _axial(along: Any, across: Any, axis: str) -> sp.ImmutableMatrix:
    """A body symmetric about ``axis``: moment ``along`` about it, ``across`` about the others."""
    index = AXES.index(axis)
    return sp.ImmutableMatrix(sp.diag(*[along if i == index else across for i in range(3)]))


def rod(mass: Any, length: Any, axis: str = "z") -> sp.ImmutableMatrix:
    """Thin rod along ``axis``: m L^2/12 about the perpendicular axes, 0 along it."""
    mass, length = _values(mass, length)
    return _axial(0, mass * length**2 / 12, axis)


def disc(mass: Any, radius: Any, axis: str = "z") -> sp.ImmutableMatrix:
    """Thin disc with normal ``axis``: m r^2/2 about it, m r^2/4 about a diameter."""
    mass, radius = _values(mass, radius)
    return _axial(mass * radius**2 / 2, mass * radius**2 / 4, axis)


def ring(mass: Any, radius: Any, axis: str = "z") -> sp.ImmutableMatrix:
    """Thin ring (hoop) with normal ``axis``: m r^2 about it, m r^2/2 about a diameter."""
    mass, radius = _values(mass, radius)
    return _axial(mass * radius**2, mass * radius**2 / 2, axis)


def solid_sphere(mass: Any, radius: Any) -> sp.ImmutableMatrix:
    """Solid ball: 2/5 m r^2 about every axis."""
    mass, radius = _values(mass, radius)
    return sp.ImmutableMatrix(sp.eye(3) * sp.Rational(2, 5) * mass * radius**2)


def hollow_sphere(mass: Any, radius: Any) -> sp.ImmutableMatrix:
    """Thin spherical shell: 2/3 m r^2 about every axis."""
    mass, radius = _values(mass, radius)
    return sp.ImmutableMatrix(sp.eye(3) * sp.Rational(2, 3) * mass * radius**2)


def cylinder(mass: Any, radius: Any, length: Any, axis: str = "z") -> sp.ImmutableMatrix:
    """Solid cylinder along ``axis``: m r^2/2 about it, m (3 r^2 + L^2)/12 across."""
    mass, radius, length = _values(mass, radius, length)
    return _axial(mass * radius**2 / 2, mass * radius**2 / 4 + mass * length**2 / 12, axis)


def box(mass: Any, length_x: Any, length_y: Any, length_z: Any) -> sp.ImmutableMatrix:
    """Solid box with sides along the body axes: I_x = m (b^2 + c^2)/12, and so on."""
    mass, a, b, c = _values(mass, length_x, length_y, length_z)
    return sp.ImmutableMatrix(sp.diag(b**2 + c**2, a**2 + c**2, a**2 + b**2) * mass / 12)


#: Shape name -> (tensor function, its dimensions in order, whether it takes an axis).
SHAPES: dict[str, tuple[Callable[..., sp.ImmutableMatrix], tuple[str, ...], bool]] = {
    "rod": (rod, ("length",), True),
    "disc": (disc, ("radius",), True),
    "ring": (ring, ("radius",), True),
    "solid_sphere": (solid_sphere, ("radius",), False),
    "hollow_sphere": (hollow_sphere, ("radius",), False),
    "cylinder": (cylinder, ("radius", "length"), True),
    "box": (box, ("length_x", "length_y", "length_z"), False),
}


@dataclass(frozen=True)
class Shape:
    """A homogeneous body of a common shape; its inertia tensor follows from the body's mass.

    Build one with :func:`shape`; ``dimensions`` are (name, value) pairs in the order of
    :data:`SHAPES`, ``axis`` the body axis of symmetry of a rod, disc, ring or cylinder.
    """

    kind: str
    dimensions: tuple[tuple[str, Any], ...]
    axis: str = "z"

    def tensor(self, mass: Any) -> sp.ImmutableMatrix:
        """The inertia tensor about the centre of mass, in body axes."""
        function, _, axial = SHAPES[self.kind]
        sizes = [value for _, value in self.dimensions]
        return function(mass, *sizes, axis=self.axis) if axial else function(mass, *sizes)

    def map(self, function: Callable[[Any], Any]) -> Shape:
        """The same shape with ``function`` applied to every dimension."""
        dimensions = tuple((name, function(value)) for name, value in self.dimensions)
        return Shape(self.kind, dimensions, self.axis)


def shape(kind: str, *, axis: str = "z", **dimensions: Any) -> Shape:
    """A :class:`Shape` (rod, disc, ring, solid_sphere, hollow_sphere, cylinder, box) with its
    dimensions by name; ModelError lists every problem.

    >>> shape("cylinder", radius=1, length=2).tensor(12)[2, 2]
    6
    """
    if kind not in SHAPES:
        close = difflib.get_close_matches(str(kind), SHAPES, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        problem = Problem("shape", f"unknown shape {kind!r}", hint + "use " + ", ".join(SHAPES))
        raise ModelError(f"Unknown shape {kind!r}", [problem])
    _, names, axial = SHAPES[kind]
    problems = [
        Problem(name, f"a {kind} needs its {name}", f"give {', '.join(names)}")
        for name in names
        if name not in dimensions
    ]
    problems += [
        Problem(name, f"a {kind} has no dimension {name!r}", f"a {kind} has {', '.join(names)}")
        for name in dimensions
        if name not in names
    ]
    if axis not in AXES or (axis != "z" and not axial):
        fix = "give x, y or z" if axial else f"a {kind} has no axis of symmetry to choose"
        problems.append(Problem("axis", f"axis {axis!r} is not allowed", fix))
    raise_if_problems(problems, f"The {kind} is not described fully", ModelError)
    values = tuple((name, as_expression(dimensions[name], name)) for name in names)
    return Shape(kind, values, axis)


# -- rotated, shifted, combined ----------------------------------------------------------------


def rotated(inertia: Any, rotation: Any) -> sp.ImmutableMatrix:
    """The tensor in rotated axes: I' = R I R^T (I in body axes -> world axes for R = R_wb).

    >>> rotated(rod(1, 1, "x"), sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]))[0, 0]
    1/12
    """
    R = as_orientation(rotation).matrix
    return sp.ImmutableMatrix((R * to_matrix(inertia) * R.T).applyfunc(sp.expand))


def parallel_axis(inertia_centre: Any, mass: Any, offset: Sequence[Any]) -> sp.ImmutableMatrix:
    """Inertia about a point at ``offset`` d from the centre of mass (parallel-axis theorem):
    I = I_c + m (|d|^2 1 - d d^T).

    >>> parallel_axis(rod(1, 1), 1, [0, 0, 1])[0, 0]
    13/12
    """
    d = to_matrix(list(offset))
    shifted = to_matrix(inertia_centre) + to_sympy(mass) * (d.dot(d) * sp.eye(3) - d * d.T)
    return sp.ImmutableMatrix(shifted.applyfunc(sp.expand))


def central_inertia(inertia_about: Any, mass: Any, centre: Sequence[Any]) -> sp.ImmutableMatrix:
    """The inertia about the centre of mass from the inertia ``inertia_about`` a body point P
    (the parallel-axis theorem backwards), ``centre`` the centre of mass relative to P, in
    the same axes: I_c = I_P - m (|d|^2 1 - d d^T).

    >>> m, L = sp.symbols("m L")
    >>> central_inertia(sp.diag(m * L**2 / 3, m * L**2 / 3, 0), m, [0, 0, L / 2])[0, 0]
    L**2*m/12
    """
    d = to_matrix(list(centre))
    shift = to_sympy(mass) * (d.dot(d) * sp.eye(3) - d * d.T)
    return sp.ImmutableMatrix((to_matrix(inertia_about) - shift).applyfunc(sp.expand))


@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of mass and inertia about that centre (axes common to all parts)."""

    mass: Any
    centre: tuple[Any, ...]
    inertia: sp.ImmutableMatrix


def combine(parts: Iterable[MassProperties]) -> MassProperties:
    """One body of several rigidly joined parts: m = sum m_i, c = sum m_i c_i / m,
    I = sum I_i + m_i (|d_i|^2 1 - d_i d_i^T), d_i = c_i - c.

    >>> half = MassProperties(1, (0, 0, 1), sp.zeros(3))
    >>> combine([half, MassProperties(1, (0, 0, -1), sp.zeros(3))]).inertia[0, 0]
    2
    """
    parts = list(parts)
    mass = sp.Add(*[p.mass for p in parts])
    moment = sum((p.mass * sp.Matrix(list(p.centre)) for p in parts), sp.zeros(3, 1))
    centre = (moment / mass).applyfunc(sp.simplify)
    inertia = sp.zeros(3)
    for p in parts:
        inertia += parallel_axis(p.inertia, p.mass, list(sp.Matrix(list(p.centre)) - centre))
    return MassProperties(mass, tuple(centre), sp.ImmutableMatrix(inertia.applyfunc(sp.simplify)))


# -- the generalized inertia matrix (MLS94 ch. 4) ----------------------------------------------


def generalized_inertia(mass: Any, inertia: Any) -> sp.ImmutableMatrix:
    """M^b = [[m 1, 0], [0, I]] for a body frame at the centre of mass, twists (v, omega):
    T = 1/2 V_b^T M^b V_b.

    >>> generalized_inertia(2, sp.eye(3)).diagonal()
    Matrix([[2, 2, 2, 1, 1, 1]])
    """
    block = sp.BlockMatrix([[mass * sp.eye(3), sp.zeros(3)], [sp.zeros(3), to_matrix(inertia)]])
    return sp.ImmutableMatrix(block.as_explicit())


def spatial_inertia(
    mass: Any, inertia: Any, rotation: Any, position: Sequence[Any]
) -> sp.ImmutableMatrix:
    """M^s = Ad_g^-T M^b Ad_g^-1 for the pose g = (R, p) of the body frame at the centre of
    mass, so that T = 1/2 V_s^T M^s V_s with V_s = Ad_g V_b (MLS94 ch. 4).

    >>> spatial_inertia(1, sp.zeros(3), sp.eye(3), [0, 0, 1])[3, 3]
    1
    """
    inverse = adjoint_inverse(rotation, position)
    result = inverse.T * generalized_inertia(mass, inertia) * inverse
    return sp.ImmutableMatrix(result.applyfunc(sp.expand))


# -- checks ------------------------------------------------------------------------------------


def _decidable_problems(inertia: sp.MatrixBase, field: str, subject: str) -> list[Problem]:
    """What SymPy's assumptions decide about a tensor with unknown values."""
    diagonal = [to_sympy(inertia[i, i]) for i in range(3)]
    if any(d.is_negative for d in diagonal):
        fix = "moments of inertia are >= 0; check the signs"
        return [Problem(field, f"{subject} has a negative moment on its diagonal", fix)]
    if inertia.is_diagonal():
        for i in range(3):
            others = [diagonal[j] for j in range(3) if j != i]
            if (others[0] + others[1] - diagonal[i]).is_negative:
                return [_triangle_problem(field, subject, diagonal)]
    return []


def _triangle_problem(field: str, subject: str, moments: Sequence[Any]) -> Problem:
    listed = ", ".join(f"{float(m):.4g}" if to_sympy(m).is_number else str(m) for m in moments)
    return Problem(
        field,
        f"the principal moments of {subject} ({listed}) violate the triangle inequality "
        "I1 + I2 >= I3",
        "no real mass distribution has these moments; check the values",
    )


def _asymmetric(matrix: sp.Matrix, values: Mapping[sp.Symbol, float]) -> bool:
    """I - I^T is not zero: exactly, or (rounding aside) at ``values`` with the unknowns drawn
    at random (a symmetric tensor is symmetric for every value of its parameters)."""
    rows, columns = matrix.shape
    entries = list(matrix)
    differences = (
        sp.expand(entries[i * columns + j] - entries[j * columns + i])
        for i in range(rows)
        for j in range(columns)
        if entries[i * columns + j] != entries[j * columns + i]  # else 0: not built
    )
    asymmetry = [e for e in differences if e != 0]
    if not asymmetry:
        return False
    rng = random.Random(len(asymmetry))
    point = {s: values.get(s, rng.uniform(0.3, 1.3)) for s in matrix.free_symbols}
    scale = evaluate_matrix(matrix, point)
    difference = evaluate_matrix(sp.Matrix(asymmetry), point)
    if scale is None or difference is None:
        return True
    return bool(np.max(np.abs(difference)) > 1e-9 * max(1.0, float(np.max(np.abs(scale)))))


def check_inertia(
    inertia: sp.MatrixBase,
    field: str,
    values: Mapping[sp.Symbol, float],
    subject: str = "the inertia tensor",
) -> list[Problem]:
    """Problems of an inertia tensor: not symmetric, not positive semidefinite, or principal
    moments that violate the triangle inequality.  ``values`` are the known numbers (parameter
    defaults, sample coordinates); with unknowns left only what SymPy can decide is checked.

    >>> check_inertia(sp.diag(1, 1, 3), "I", {})[0].message.split(" violate ")[1]
    'the triangle inequality I1 + I2 >= I3'
    """
    # read only: an immutable matrix is checked as it is, not copied
    matrix = inertia if isinstance(inertia, sp.ImmutableMatrix) else to_matrix(inertia)
    rows, columns = matrix.shape
    if rows != columns:
        fix = "give the tensor as a square matrix (3x3: [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], ...])"
        return [Problem(field, f"{subject} is {rows}x{columns}, not square", fix)]
    if _asymmetric(matrix, values):
        fix = "an inertia tensor is symmetric: I_xy = I_yx, I_xz = I_zx, I_yz = I_zy"
        return [Problem(field, f"{subject} is not symmetric", fix)]
    numbers = evaluate_matrix(matrix, values) if matrix.free_symbols <= set(values) else None
    if numbers is None:
        return _decidable_problems(matrix, field, subject)
    moments = np.linalg.eigvalsh(numbers)
    scale = max(1.0, float(np.max(np.abs(moments))))
    if moments[0] < -1e-12 * scale:
        message = f"{subject} is not positive semidefinite (a principal moment is {moments[0]:.4g})"
        return [Problem(field, message, "principal moments of inertia are >= 0")]
    if moments[0] + moments[1] < moments[2] - 1e-12 * scale:
        return [_triangle_problem(field, subject, [sp.Float(m) for m in moments])]
    return []
