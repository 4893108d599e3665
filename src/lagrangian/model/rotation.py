"""Orientation of a rigid body in 3-D: rotation matrices from Euler angles, an axis and an
angle, or a quaternion, as functions of q and t, and the angular velocity they imply.

Conventions (Murray, Li & Sastry 1994, ch. 2):

- ``R`` maps body axes to world axes: x_world = R x_body (``ReferenceFrame``: ``N.dcm(B)``).
- Body angular velocity omega_b = vee(R^T R_dot), spatial (world axes) omega_s = vee(R_dot R^T)
  = R omega_b; ``hat(w) v = w x v`` and ``vee`` is its inverse.
- Euler angles: *intrinsic* (body-fixed axes, the default) ``"ZXZ"`` with angles (a, b, c) is
  R = Rz(a) Rx(b) Rz(c); *extrinsic* (world-fixed axes) is the reverse product
  R = Rz(c) Rx(b) Rz(a).  All 12 sequences are allowed.
- Quaternions are scalar first, (w, x, y, z); R is the rotation of the unit quaternion q/|q|.
- Angular velocities are composed from the rotations about constant axes an orientation is
  made of (Euler angles, ``rotations``, and a matrix given whole that is such a product
  multiplied out: :mod:`lagrangian.model.rotation_factors` finds its factors), never
  differentiated from R where they can be; a quaternion's follow from its rates; only
  any other matrix is differentiated, vee(R^T R_dot), and simplified.

>>> import sympy as sp
>>> phi, theta, psi = sp.symbols("phi theta psi")
>>> top = euler_rotation("ZXZ", (phi, theta, psi))
>>> top.gimbal_lock
sin(theta)
>>> omega_b = body_angular_velocity(top, [phi, theta, psi])
>>> omega_b[0], omega_b[2]
(phi_dot*sin(psi)*sin(theta) + theta_dot*cos(psi), phi_dot*cos(theta) + psi_dot)
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.model.rotation_factors import Factoring, factor_rotation, pythagorean_reduced
from lagrangian.symbolic.caches import remembered
from lagrangian.symbolic.canonical import Builder, sympy_product, sympy_sum
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.native import to_symengine, to_symengine_sharing
from lagrangian.symbolic.symbols import t, time_derivative, velocity

#: The 12 Euler-angle sequences: 6 Tait–Bryan (three different axes), 6 proper Euler.
EULER_SEQUENCES = (
    *("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"),
    *("XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"),
)
_AXES = {"X": 0, "Y": 1, "Z": 2}
#: The names of the body axes a simple rotation may turn about (or give a vector).
AXIS_NAMES = ("x", "y", "z")
#: Their unit vectors, the columns (and rows) of the identity.
_BODY_AXES = tuple(tuple(sp.eye(3)[:, i]) for i in range(3))
FORMS = ("matrix", "euler", "axis_angle", "quaternion", "rotations")
#: Rotations with moving angles up to which a composed angular velocity is expanded.
EXPANDED_TURNS = 6
#: The largest |q|^2 (operations) trigsimp is tried on when the reduction modulo
#: sin^2 + cos^2 = 1 does not give 1 (double angles and the like).
TRIGSIMP_OPS = 60
#: Orientations whose angular velocities are remembered (model building, the derivation and
#: the loads ask for the same bodies' again).
REMEMBERED = 256


def as_expression(value: Any, field: str = "value") -> sp.Expr:
    """A SymPy expression from an expression or a number (floats become exact rationals, as
    everywhere in a System); text is refused, never evaluated.

    >>> as_expression(0.5)
    1/2
    """
    if isinstance(value, float):
        return sp.nsimplify(value, rational=True)
    if isinstance(value, sp.Expr) or (isinstance(value, int) and not isinstance(value, bool)):
        return to_sympy(value)
    fix = "give a SymPy expression or a number (Symbols, not text)"
    raise ModelError(
        f"{value!r} is not an expression", [Problem(field, f"{value!r} is not an expression", fix)]
    )


def hat(vector: Sequence[Any]) -> sp.ImmutableMatrix:
    """The skew-symmetric matrix of a 3-vector: hat(w) v = w x v.

    >>> hat([1, 2, 3]) * sp.Matrix([0, 0, 1]) == sp.Matrix([1, 2, 3]).cross(sp.Matrix([0, 0, 1]))
    True
    """
    x, y, z = vector
    return sp.ImmutableMatrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def vee(skew: sp.MatrixBase) -> sp.ImmutableMatrix:
    """The 3-vector of a skew-symmetric matrix, the inverse of :func:`hat`.

    >>> vee(hat([1, 2, 3])).T
    Matrix([[1, 2, 3]])
    """
    return sp.ImmutableMatrix([skew[2, 1], skew[0, 2], skew[1, 0]])


def unit_axis(axis: Sequence[Any]) -> sp.ImmutableMatrix:
    """n / |n| of the axis n (itself when |n|^2 expands to 1), remembered per axis.

    >>> unit_axis((0, 3, 4)).T
    Matrix([[0, 3/5, 4/5]])
    """
    axis = tuple(axis)
    try:  # the same few axes recur: each rotation, composed and differentiated, asks again
        # the entries' types in the key too: 1 and 1.0 are equal keys but not the same axis
        return _remembered_unit(axis, tuple(type(a) for a in axis))
    except TypeError:  # an unhashable expression in it
        return _unit_of(axis)


def _unit_of(axis: tuple[Any, ...], types: tuple[type, ...] = ()) -> sp.ImmutableMatrix:
    """n / |n| (``types``: the entries' types, a part of the memo's key only)."""
    entries = [to_sympy(a) for a in axis]
    n = sp.ImmutableMatrix._new(len(entries), 1, entries, copy=False)
    length_squared = sp.expand(sp.Add(*[a * a for a in entries]))  # n . n
    # exactly 1 (SymPy before 1.13 has Float 1.0 == 1: such an axis is divided as it was)
    return n if length_squared is sp.S.One else n / sp.sqrt(length_squared)


_remembered_unit = remembered(maxsize=REMEMBERED)(_unit_of)


def _about(unit_axis: sp.ImmutableMatrix, angle: Any) -> sp.ImmutableMatrix:
    """Rodrigues: R = cos a 1 + sin a hat(n) + (1 - cos a) n n^T for a unit axis n."""
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.ImmutableMatrix(
        sp.eye(3) * c + hat(unit_axis) * s + unit_axis * unit_axis.T * (1 - c)
    )


def _elementary(axis: str, angle: Any) -> sp.ImmutableMatrix:
    return _about(sp.ImmutableMatrix(sp.eye(3)[:, _AXES[axis]]), angle)


@dataclass(frozen=True)
class Orientation:
    """A rotation R(q, t) of a body (body axes -> world axes) and how it was given.

    Build one with :func:`euler_rotation`, :func:`axis_angle`, :func:`quaternion_rotation`,
    :func:`rotation_sequence` (simple rotations about body axes, relative to a ``parent``
    orientation or to the world), or from a 3x3 matrix with :func:`as_orientation`.
    ``form`` is one of ``"matrix"``, ``"euler"``, ``"axis_angle"``, ``"quaternion"``,
    ``"rotations"``; the fields of the other forms are empty.
    """

    matrix: sp.ImmutableMatrix
    form: str = "matrix"
    sequence: str = ""  # euler: e.g. "ZXZ"
    intrinsic: bool = True  # euler: body-fixed (True) or world-fixed (False) axes
    angles: tuple[Any, ...] = ()  # euler: 3 angles; axis_angle: (angle,)
    axis: tuple[Any, ...] = ()  # axis_angle: the axis as given (normalized in the matrix)
    quaternion: tuple[Any, ...] = ()  # quaternion: (w, x, y, z) as given
    rotations: tuple[tuple[tuple[Any, ...], Any], ...] = ()  # rotations: ((axis, angle), ...)
    parent: Orientation | None = None  # rotations: the orientation they are relative to

    @property
    def gimbal_lock(self) -> sp.Expr | None:
        """For Euler angles, an expression that vanishes at gimbal lock (where the angle rates
        no longer follow from the angular velocity): sin(b) for a proper Euler sequence such
        as ZXZ, cos(b) for a Tait–Bryan one such as ZYX, b the middle angle; None otherwise."""
        if self.form != "euler":
            return None
        middle = self.angles[1]
        return sp.sin(middle) if self.sequence[0] == self.sequence[2] else sp.cos(middle)

    def factors(self) -> tuple[tuple[sp.ImmutableMatrix, Any], ...]:
        """R as a product of rotations about constant axes, ((unit axis, angle), ...) in
        product order: three for Euler angles, one for an axis and angle; () otherwise."""
        if self.form == "euler":
            pairs = [
                (sp.ImmutableMatrix(sp.eye(3)[:, _AXES[a]]), x)
                for a, x in zip(self.sequence, self.angles)
            ]
            return tuple(pairs if self.intrinsic else reversed(pairs))
        if self.form == "axis_angle":
            return ((unit_axis(self.axis), self.angles[0]),)
        if self.form == "rotations":
            inherited = () if self.parent is None else self.parent.factors()
            if self.parent is None or inherited:
                return (*inherited, *self.own_factors())
        return ()

    def own_factors(self) -> tuple[tuple[sp.ImmutableMatrix, Any], ...]:
        """The simple rotations of a ``"rotations"`` orientation relative to its parent,
        ((unit axis, angle), ...) in product order; () for the other forms."""
        return tuple((unit_axis(axis), angle) for axis, angle in self.rotations)

    def map(self, function: Callable[[Any], Any]) -> Orientation:
        """The same orientation with ``function`` applied to every expression in it."""
        if self.form == "euler":
            angles = tuple(function(a) for a in self.angles)
            return euler_rotation(self.sequence, angles, intrinsic=self.intrinsic)
        if self.form == "axis_angle":
            return axis_angle(tuple(function(a) for a in self.axis), function(self.angles[0]))
        if self.form == "quaternion":
            return quaternion_rotation(*(function(c) for c in self.quaternion))
        if self.form == "rotations":
            turns = [(tuple(function(e) for e in n), function(a)) for n, a in self.rotations]
            parent = None if self.parent is None else self.parent.map(function)
            return rotation_sequence(turns, parent)
        return Orientation(sp.ImmutableMatrix(self.matrix.applyfunc(function)))


def as_orientation(value: Any) -> Orientation:
    """An Orientation from an Orientation or a 3x3 rotation matrix (nested lists allowed).

    >>> as_orientation([[1, 0, 0], [0, 1, 0], [0, 0, 1]]).form
    'matrix'
    """
    if isinstance(value, Orientation):
        return value
    rows = value.tolist() if isinstance(value, sp.MatrixBase) else value
    if not (isinstance(rows, (list, tuple)) and all(isinstance(r, (list, tuple)) for r in rows)):
        raise _refuse("orientation", f"{value!r} is not a 3x3 matrix", "give three rows of three")
    return Orientation(
        sp.ImmutableMatrix([[as_expression(e, "orientation") for e in row] for row in rows])
    )


def _refuse(field: str, message: str, fix: str) -> ModelError:
    return ModelError(f"Not a rotation: {message}", [Problem(field, message, fix)])


def euler_rotation(sequence: str, angles: Sequence[Any], *, intrinsic: bool = True) -> Orientation:
    """The rotation of three Euler angles about the axes of ``sequence`` (any of the 12).

    Intrinsic (body-fixed axes): R = R1(a1) R2(a2) R3(a3); extrinsic (world-fixed axes, the
    first rotation about the world's first axis): R = R3(a3) R2(a2) R1(a1).

    >>> a, b, c = sp.symbols("a b c")
    >>> euler_rotation("ZYX", (a, b, c)).matrix[2, 0]
    -sin(b)
    """
    text = str(sequence).upper()
    if text not in EULER_SEQUENCES:
        close = difflib.get_close_matches(text, EULER_SEQUENCES, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise _refuse("euler", f"unknown Euler sequence {sequence!r}", hint + "use e.g. ZXZ, ZYX")
    values = tuple(as_expression(a, "angles") for a in angles)
    if len(values) != 3:
        raise _refuse("angles", f"{len(values)} Euler angles given", "give three angles")
    factors = [_elementary(a, x) for a, x in zip(text, values)]
    first, second, third = factors if intrinsic else factors[::-1]
    matrix = sp.ImmutableMatrix(first * second * third)
    return Orientation(matrix, "euler", text, bool(intrinsic), values)


def axis_angle(axis: Sequence[Any], angle: Any) -> Orientation:
    """The rotation by ``angle`` about ``axis`` (normalized), by Rodrigues' formula:
    R = cos a 1 + sin a hat(n) + (1 - cos a) n n^T, n = axis / |axis|.

    >>> axis_angle([0, 0, 1], sp.Symbol("q")).matrix[0, 1]
    -sin(q)
    """
    values = tuple(as_expression(a, "axis") for a in axis)
    if len(values) != 3:
        raise _refuse("axis", f"an axis of {len(values)} components", "give [x, y, z]")
    if all(v == 0 for v in values):
        raise _refuse("axis", "the axis is the zero vector", "give a direction such as [0, 0, 1]")
    angle = as_expression(angle, "angle")
    return Orientation(_about(unit_axis(values), angle), "axis_angle", angles=(angle,), axis=values)


def rotation_axis(axis: Any, field: str = "axis") -> tuple[sp.Expr, ...]:
    """The body axis ``"x"``, ``"y"`` or ``"z"`` (any case) or a 3-vector, as 3 components.

    >>> rotation_axis("Z")
    (0, 0, 1)
    """
    if isinstance(axis, str):
        if axis.lower() in AXIS_NAMES:
            return _BODY_AXES[AXIS_NAMES.index(axis.lower())]
        close = difflib.get_close_matches(axis.lower(), AXIS_NAMES, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        fix = hint + "use x, y or z (the body's own axes) or a vector [a, b, c]"
        raise _refuse(field, f"unknown axis {axis!r}", fix)
    if isinstance(axis, (sp.MatrixBase, list, tuple)):
        values = tuple(as_expression(a, field) for a in axis)
        if len(values) == 3 and not all(v == 0 for v in values):
            return values
    raise _refuse(field, f"{axis!r} is not an axis", "use x, y, z or a non-zero vector [a, b, c]")


def rotation_sequence(
    rotations: Iterable[Any], parent: Any = None, *, builder: Builder | None = None
) -> Orientation:
    """Simple rotations about body axes, one after another, relative to ``parent`` (an
    Orientation or a 3x3 matrix; the world when None):

        R = R_parent R1(a1) R2(a2) ... Rm(am),

    each ``(axis, angle)`` turning about an axis of the frame the rotations before it made
    (``"x"``, ``"y"``, ``"z"`` or a vector in those axes), as ``orient_body_fixed`` in
    sympy.physics.mechanics.  The angular velocity is composed, not differentiated:
    omega_s = omega_s(parent) + R_parent sum_k R1..R(k-1) n_k a_k_dot.

    ``builder``: the canonical Builder that made the parent's entries, if any (what it knows
    of them is not found again: a chain of frames composes each on its parent's).

    >>> a, b = sp.symbols("a b")
    >>> rotation_sequence([("z", a), ("x", b)]).matrix == euler_rotation("ZXZ", (a, b, 0)).matrix
    True
    """
    turns = []
    for k, item in enumerate(rotations):
        field = f"rotations[{k}]"
        if not (isinstance(item, (list, tuple)) and len(item) == 2):
            raise _refuse(field, f"{item!r} is not an (axis, angle) pair", "write [z, psi]")
        axis, angle = item
        turns.append((rotation_axis(axis, field), as_expression(angle, field)))
    base = None if parent is None else as_orientation(parent)
    rows = [list(axis) for axis in _BODY_AXES] if base is None else base.matrix.tolist()
    builder = builder or Builder()  # the products of one turn are the sums of the next
    for axis, angle in turns:
        rows = _turned(rows, axis, angle, builder)
    # the rows are a 3x3 list already: no reading of the constructor's many input forms
    matrix = sp.ImmutableMatrix._new(3, 3, [e for row in rows for e in row], copy=False)
    return Orientation(matrix, "rotations", rotations=tuple(turns), parent=base)


def _turned(
    rows: list[list[Any]], axis: Sequence[Any], angle: Any, builder: Builder
) -> list[list[Any]]:
    """The rows of the matrix times R1(angle) about ``axis``.  About a coordinate axis i only
    the other two columns change, (j, k) cyclic after i: c col_j + s col_k and
    -s col_j + c col_k (the product itself, entry by entry, without its multiplications by 0
    and 1 nor a matrix's bookkeeping, its sums and products made as SymPy makes them without
    its general evaluation where nothing combines: a tenth of the time on a bicycle's
    fork)."""
    unit = unit_axis(axis)
    ones = [i for i, e in enumerate(unit) if e == 1]
    if len(ones) != 1 or any(e != 0 for i, e in enumerate(unit) if i != ones[0]):
        return (sp.Matrix(rows) * _about(unit, angle)).tolist()
    j, k = (ones[0] + 1) % 3, (ones[0] + 2) % 3
    c, s = sp.cos(angle), sp.sin(angle)
    turned = [list(row) for row in rows]
    for row, new in zip(rows, turned):
        new[j] = sympy_sum([_scaled(row[j], c, builder), _scaled(row[k], s, builder)], builder)
        new[k] = sympy_sum([_scaled(row[k], c, builder), -_scaled(row[j], s, builder)], builder)
    return turned


def _scaled(entry: Any, factor: Any, builder: Builder) -> Any:
    """entry * factor as a matrix's product by a scalar makes it (a zero entry stays 0)."""
    return sympy_product([entry, factor], builder) if entry != 0 else entry


def _norm_squared(w: Any, x: Any, y: Any, z: Any) -> sp.Expr:
    """|q|^2, replaced by 1 when it simplifies to 1 (e.g. (cos(a/2), sin(a/2) n))."""
    squared = sp.expand(w**2 + x**2 + y**2 + z**2)
    if squared == 1 or pythagorean_reduced(squared) == 1:
        return sp.Integer(1)  # (exact, and cheap where trigsimp takes seconds: q1 q2 q3)
    small = sp.count_ops(squared) <= TRIGSIMP_OPS
    return sp.Integer(1) if small and sp.trigsimp(squared) == 1 else squared


def quaternion_rotation(w: Any, x: Any, y: Any, z: Any) -> Orientation:
    """The rotation of the quaternion w + x i + y j + z k (scalar first).

    R is the rotation of the unit quaternion q/|q|, so any non-zero q gives a rotation:

        R = 1/|q|^2 [[w2+x2-y2-z2, 2(xy-wz), 2(xz+wy)],
                     [2(xy+wz), w2-x2+y2-z2, 2(yz-wx)],
                     [2(xz-wy), 2(yz+wx), w2-x2-y2+z2]]

    with the division left out when |q|^2 simplifies to 1.  Quaternion coordinates with the
    constraint |q|^2 = 1 are therefore allowed but not needed.

    >>> a = sp.Symbol("a")
    >>> quaternion_rotation(sp.cos(a / 2), 0, 0, sp.sin(a / 2)).matrix[0, 0]
    -sin(a/2)**2 + cos(a/2)**2
    """
    w, x, y, z = (as_expression(c, "quaternion") for c in (w, x, y, z))
    rows = [
        [w**2 + x**2 - y**2 - z**2, 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), w**2 - x**2 + y**2 - z**2, 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), w**2 - x**2 - y**2 + z**2],
    ]
    matrix = sp.ImmutableMatrix(rows) / _norm_squared(w, x, y, z)
    return Orientation(sp.ImmutableMatrix(matrix), "quaternion", quaternion=(w, x, y, z))


# -- angular velocity -------------------------------------------------------------------------


def _rate(expr: Any, coordinates: Sequence[sp.Symbol]) -> sp.Expr:
    return time_derivative(to_sympy(expr), coordinates)


def _constant(expr: Any, coordinates: Sequence[sp.Symbol]) -> bool:
    return not (to_sympy(expr).free_symbols & {*coordinates, t})


def _quaternion_rates(orientation: Orientation, coordinates: Sequence[sp.Symbol]) -> tuple:
    w, x, y, z = orientation.quaternion
    v = sp.Matrix([x, y, z])
    v_dot = sp.Matrix([_rate(c, coordinates) for c in (x, y, z)])
    w_dot = _rate(w, coordinates)
    return w * v_dot - w_dot * v, v.cross(v_dot), _norm_squared(w, x, y, z)


def _general(
    orientation: Orientation, coordinates: Sequence[sp.Symbol], body: bool
) -> sp.ImmutableMatrix:
    """vee(R^T R_dot) or vee(R_dot R^T); the coefficient of each velocity is simplified on its
    own (sin^2 + cos^2 = 1 etc.), which is much cheaper than simplifying the whole."""
    R = orientation.matrix
    R_dot = R.applyfunc(lambda e: _rate(e, coordinates))
    skew = R.T * R_dot if body else R_dot * R.T
    rates = [velocity(q) for q in coordinates]
    result = []
    for entry in vee(skew):
        terms = sp.collect(sp.expand(entry), rates, evaluate=False)
        result.append(sp.Add(*[sp.fu(part) * rate for rate, part in terms.items()]))
    return sp.ImmutableMatrix(result)


def _moving_axis(
    orientation: Orientation, coordinates: Sequence[sp.Symbol], body: bool
) -> sp.ImmutableMatrix:
    """R = exp(a hat(n)) with a unit axis n(q, t):
    omega_s = a_dot n + sin a n_dot + (1 - cos a) n x n_dot, omega_b the same with - (...)."""
    n, angle = unit_axis(orientation.axis), orientation.angles[0]
    n_dot = n.applyfunc(lambda e: _rate(e, coordinates))
    turn = (1 - sp.cos(angle)) * n.cross(n_dot)
    omega = n * _rate(angle, coordinates) + sp.sin(angle) * n_dot + (-turn if body else turn)
    return sp.ImmutableMatrix(omega)


def _composed(
    parent: Orientation | None,
    factors: Sequence[tuple[sp.ImmutableMatrix, Any]],
    tail: sp.ImmutableMatrix | None,
    q: Sequence[sp.Symbol],
    body: bool,
) -> sp.ImmutableMatrix:
    """The angular velocity of R = R_parent F1 F2 ... Fm, F_k = exp(a_k hat(n_k)) about
    constant axes n_k, composed from the parent's (zero for the world):

        omega_b = (F1..Fm)^T omega_b(parent) + sum_k (F(k+1)..Fm)^T n_k a_k_dot
                  (w <- F_k^T w + n_k a_k_dot, k = 1..m),
        omega_s = omega_s(parent) + R_parent sum_k F1..F(k-1) n_k a_k_dot
                  (s <- n_k a_k_dot + F_k s, k = m..1, as F_k n_k = n_k),

    matrix-vector products only: nothing is differentiated but the angles.  A constant
    ``tail`` C on the right (R = R_parent F1..Fm C, a matrix given whole) turns omega_b into
    C^T omega_b and leaves omega_s as it is.  The result is
    expanded unless more than :data:`EXPANDED_TURNS` of the rotations turn with the
    coordinates (a long chain of joints, whose expanded products of sines and cosines would
    run to thousands of terms): then it stays nested, as the products give it.  (An
    expanded one is usually composed in SymEngine instead: :func:`_composed_backend`.)"""
    moving = sum(1 for _, a in factors if not _constant(a, q))
    tidy = sp.expand if moving <= EXPANDED_TURNS else (lambda e: e)
    if body:
        w = sp.zeros(3, 1) if parent is None else sp.Matrix(_angular_velocity(parent, q, True))
        for n, a in factors:
            w = _about(n, a).T * w + n * _rate(a, q)
        if tail is not None:
            w = tail.T * w
        return sp.ImmutableMatrix(w.applyfunc(tidy))
    s = sp.zeros(3, 1)
    for n, a in reversed(factors):
        s = n * _rate(a, q) + _about(n, a) * s
    if parent is not None:
        s = parent.matrix * s + _angular_velocity(parent, q, False)
    return sp.ImmutableMatrix(s.applyfunc(tidy))


Composition = tuple[
    "Orientation | None", tuple[tuple[sp.ImmutableMatrix, Any], ...], "sp.ImmutableMatrix | None"
]


def _composition(orientation: Orientation, q: tuple[sp.Symbol, ...]) -> Composition | None:
    """(parent, factors, tail) whose :func:`_composed` is the angular velocity of
    ``orientation``: all its rotations about constant axes from the world, or its own from
    its parent, or the factors a matrix given whole is recognised as
    (:func:`~lagrangian.model.rotation_factors.factor_rotation`); None for an orientation
    not so composed."""
    factors = orientation.factors()
    if factors and all(_constant(e, q) for axis, _ in factors for e in axis):
        return None, factors, None
    if orientation.form == "rotations":
        own = orientation.own_factors()
        if all(_constant(e, q) for axis, _ in own for e in axis):
            return orientation.parent, own, None
    if orientation.form in ("matrix", "quaternion"):  # a quaternion: a product of them?
        found = _factoring(orientation.matrix, q)
        if found is not None:
            return None, found.factors, found.tail
    return None


def _factoring(matrix: sp.ImmutableMatrix, q: tuple[sp.Symbol, ...]) -> Factoring | None:
    try:
        return _remembered_factoring(matrix, q)
    except TypeError:  # an unhashable expression in it
        return factor_rotation(matrix, q)


_remembered_factoring = remembered(maxsize=REMEMBERED)(factor_rotation)


def _composed_backend(
    parent: Orientation | None,
    factors: Sequence[tuple[sp.ImmutableMatrix, Any]],
    tail: sp.ImmutableMatrix | None,
    q: tuple[sp.Symbol, ...],
    body: bool,
    limit: int,
) -> tuple[Any, Any, Any] | None:
    """The expanded :func:`_composed` in SymEngine: the same polynomial in the sines and
    cosines as SymPy's expand gives, at a fraction of its cost (a bicycle's fork turns six
    times).  None where that sameness is not plain: an angle with a function or a constant
    such as pi in it (whose sines the two evaluate each their own way), or not expanded
    already (SymPy's expand would reach into the sines), an axis (or a constant tail) not of
    rationals and polynomials in the sines and cosines of parameters (a steer axis tilted by
    lam: (sin(lam), 0, -cos(lam))), or a parent whose own angular velocity is not so
    composed."""
    if not all(_plain_angle(a) for _, a in factors) or not all(
        _plain_constant(e) for n, _ in factors for e in n
    ):
        return None
    if tail is not None and not all(_plain_constant(e) for e in tail):
        return None
    inherited = None if parent is None else _fast(parent, q, body, limit)
    if parent is not None and inherited is None:
        return None
    w: list[Any] = [se.Integer(0)] * 3
    turns = [_backend_turn(n, a, q) for n, a in factors]
    if body:
        w = list(inherited or w)
        for n, rate, about in turns:
            w = [x + n_i * rate for x, n_i in zip(_times(about, w, True), n)]
        if tail is not None:
            w = _times([[to_symengine(e) for e in row] for row in tail.tolist()], w, True)
    else:
        for n, rate, about in reversed(turns):
            w = [n_i * rate + x for x, n_i in zip(_times(about, w), n)]
        if parent is not None and inherited is not None:
            turned = _times([[to_symengine(e) for e in row] for row in parent.matrix.tolist()], w)
            w = [x + e for x, e in zip(turned, inherited)]
    x, y, z = (se.expand(e) for e in w)
    return x, y, z


def _plain_angle(angle: Any) -> bool:
    angle = to_sympy(angle)
    if angle.is_Symbol or angle.is_Rational:
        return True
    if angle.is_Mul and all(f.is_Symbol or f.is_Rational for f in angle.args):
        return True  # a rational multiple of a product of symbols: expanded, no function
    return not angle.has(sp.Function, sp.NumberSymbol) and angle == sp.expand(angle)


def _plain_constant(entry: Any) -> bool:
    """A rational, or an expanded polynomial in the sines and cosines of plain symbols, which
    SymEngine and SymPy expand alike."""
    entry = to_sympy(entry)
    if entry.is_Rational:
        return True
    functions = entry.atoms(sp.Function)
    return (
        not entry.has(sp.NumberSymbol)
        and all(isinstance(f, (sp.sin, sp.cos)) and f.args[0].is_Symbol for f in functions)
        and entry == sp.expand(entry)
    )


def _backend_turn(
    axis: sp.ImmutableMatrix, angle: Any, q: tuple[sp.Symbol, ...]
) -> tuple[tuple[Any, ...], Any, tuple[tuple[Any, ...], ...]]:
    """A turn by ``angle`` about the unit ``axis`` in SymEngine: the axis, the angle's rate
    (:func:`_backend_rate`) and the rotation matrix (:func:`_backend_about`); remembered, as
    the frames of a multibody system share their turns (a bicycle's wheels hang from the
    same yaw, lean and pitch)."""
    try:
        return _remembered_turn(axis, angle, q)
    except TypeError:  # an unhashable expression in it
        return _made_turn(axis, angle, q)


def _made_turn(
    axis: sp.ImmutableMatrix, angle: Any, q: tuple[sp.Symbol, ...]
) -> tuple[tuple[Any, ...], Any, tuple[tuple[Any, ...], ...]]:
    n = [to_symengine(e) for e in axis]
    a = to_symengine(angle)
    return tuple(n), _backend_rate(a, q), tuple(map(tuple, _backend_about(n, a)))


_remembered_turn = remembered(maxsize=REMEMBERED)(_made_turn)


def _backend_rate(a: Any, q: Sequence[sp.Symbol]) -> Any:
    """d a/dt by the chain rule (:func:`_rate`, an angle of q and t) for the SymEngine angle
    ``a``."""
    named = {symbol.name for symbol in a.free_symbols}
    rate = a.diff(to_symengine(t))
    for x in q:
        if x.name in named:
            rate += a.diff(to_symengine(x)) * to_symengine(velocity(x))
    return rate


def _backend_about(n: list[Any], angle: Any) -> list[list[Any]]:
    """:func:`_about` in SymEngine: cos a 1 + sin a hat(n) + (1 - cos a) n n^T; about a
    coordinate axis i, 1 at (i, i), cos a at (j, j) and (k, k), sin a at (k, j) and -sin a
    at (j, k) ((i, j, k) cyclic), 0 elsewhere: the same entries, without the sums that
    cancel to them."""
    c, s = se.cos(angle), se.sin(angle)
    ones = [i for i, e in enumerate(n) if e == 1]
    if len(ones) == 1 and all(e == 0 for e in n if e != 1):
        i = ones[0]
        j, k = (i + 1) % 3, (i + 2) % 3
        matrix = [[se.Integer(0)] * 3 for _ in range(3)]
        matrix[i][i], matrix[j][j], matrix[k][k] = se.Integer(1), c, c
        matrix[k][j], matrix[j][k] = s, -s
        return matrix
    skew = [[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]]
    return [
        [(c if i == j else 0) + s * skew[i][j] + (1 - c) * n[i] * n[j] for j in range(3)]
        for i in range(3)
    ]


def _times(
    matrix: Sequence[Sequence[Any]], vector: list[Any], transposed: bool = False
) -> list[Any]:
    """matrix vector (matrix^T vector when ``transposed``), the zero products left out."""
    rows = [list(column) for column in zip(*matrix)] if transposed else matrix
    return [se.Add(*[m * v for m, v in zip(row, vector) if m != 0 and v != 0]) for row in rows]


def _back_to_sympy(
    vector: tuple[Any, Any, Any], orientation: Orientation, q: tuple[sp.Symbol, ...]
) -> sp.ImmutableMatrix:
    """A SymEngine vector in SymPy, with the symbol objects of the orientation and the
    coordinates (SymEngine keeps no assumptions)."""
    symbols = {t, *q, *(velocity(x) for x in q), *orientation.matrix.free_symbols}
    by_name = {s.name: s for s in symbols if isinstance(s, sp.Symbol)}
    entries = []
    for e in vector:
        value = to_sympy(e)
        swap = {
            s: by_name[s.name]
            for s in value.free_symbols
            if s.name in by_name and by_name[s.name] is not s
        }
        entries.append(value.xreplace(swap) if swap else value)
    return sp.ImmutableMatrix(entries)


def _angular_velocity(
    orientation: Any, coordinates: Iterable[sp.Symbol], body: bool
) -> sp.ImmutableMatrix:
    orientation = as_orientation(orientation)
    q = tuple(coordinates)
    try:  # remembered with the expansion limit it was made under
        return _remembered_angular_velocity(orientation, q, body, EXPANDED_TURNS)
    except TypeError:  # an unhashable expression in it
        return _computed_angular_velocity(orientation, q, body, EXPANDED_TURNS)


@remembered(maxsize=REMEMBERED)
def _remembered_angular_velocity(
    orientation: Orientation, q: tuple[sp.Symbol, ...], body: bool, limit: int
) -> sp.ImmutableMatrix:
    return _computed_angular_velocity(orientation, q, body, limit)


def _computed_angular_velocity(
    orientation: Orientation, q: tuple[sp.Symbol, ...], body: bool, limit: int
) -> sp.ImmutableMatrix:
    fast = _fast(orientation, q, body, limit)
    if fast is not None:
        return _back_to_sympy(fast, orientation, q)
    composition = _composition(orientation, q)
    if composition is not None:
        return _composed(*composition, q, body)
    if orientation.form == "axis_angle":
        return _moving_axis(orientation, q, body)
    if orientation.form == "quaternion":
        # omega_b = 2 vec(conj(q) q_dot) / |q|^2, omega_s = 2 vec(q_dot conj(q)) / |q|^2
        linear, cross, norm = _quaternion_rates(orientation, q)
        vector = linear - cross if body else linear + cross
        return sp.ImmutableMatrix((2 * vector / norm).applyfunc(sp.expand))
    return _general(orientation, q, body)


def angular_velocity_terms(
    orientation: Any, coordinates: Iterable[sp.Symbol], body: bool = True
) -> tuple[Any, Any, Any]:
    """:func:`body_angular_velocity` (or, with ``body`` False, the spatial one) as SymEngine
    expressions, for the derivation and the rolling contacts, which work in SymEngine: an
    orientation composed of rotations about constant axes is composed there and never passes
    through SymPy; any other is converted once.

    >>> a = sp.Symbol("a")
    >>> angular_velocity_terms(rotation_sequence([("z", a)]), [a])
    (0, 0, a_dot)
    """
    orientation = as_orientation(orientation)
    q = tuple(coordinates)
    fast = _fast(orientation, q, body, EXPANDED_TURNS)
    if fast is not None:
        return fast
    x, y, z = (to_symengine(e) for e in _angular_velocity(orientation, q, body))
    return x, y, z


def _fast(
    orientation: Orientation, q: tuple[sp.Symbol, ...], body: bool, limit: int
) -> tuple[Any, Any, Any] | None:
    """The angular velocity composed and expanded in SymEngine (:func:`_composed_backend`),
    remembered per orientation; None for one that is not (not composed of rotations about
    constant axes, more than ``limit`` turning rotations to expand, or not plainly the same
    as SymPy's)."""
    try:
        return _remembered_fast(orientation, q, body, limit)
    except TypeError:  # an unhashable expression in it
        return _fast_composed(orientation, q, body, limit)


def _fast_composed(
    orientation: Orientation, q: tuple[sp.Symbol, ...], body: bool, limit: int
) -> tuple[Any, Any, Any] | None:
    composition = _composition(orientation, q)
    if composition is None:
        return None
    parent, factors, tail = composition
    if sum(1 for _, a in factors if not _constant(a, q)) > limit:
        return None
    try:
        return _composed_backend(parent, factors, tail, q, body, limit)
    except se.SympifyError:  # something SymEngine does not know: SymPy composes it
        return None


_remembered_fast = remembered(maxsize=REMEMBERED)(_fast_composed)


def body_angular_velocity(orientation: Any, coordinates: Iterable[sp.Symbol]) -> sp.ImmutableMatrix:
    """omega_b = vee(R^T R_dot), the angular velocity in body axes, in q, q_dot and t.

    ``orientation`` is an :class:`Orientation` or a 3x3 matrix; ``coordinates`` are the
    symbols whose rates are q_dot (d/dt by the chain rule, :func:`time_derivative`).

    >>> q = sp.Symbol("q")
    >>> body_angular_velocity(axis_angle([0, 0, 2], q), [q]).T
    Matrix([[0, 0, q_dot]])
    """
    return _angular_velocity(orientation, coordinates, body=True)


def spatial_angular_velocity(
    orientation: Any, coordinates: Iterable[sp.Symbol]
) -> sp.ImmutableMatrix:
    """omega_s = vee(R_dot R^T) = R omega_b, the angular velocity in world axes.

    >>> a, b = sp.symbols("a b")
    >>> spatial_angular_velocity(euler_rotation("ZYX", (a, b, 0)), [a, b]).T
    Matrix([[-b_dot*sin(a), b_dot*cos(a), a_dot]])
    """
    return _angular_velocity(orientation, coordinates, body=False)


# -- the check of a rotation given by a user --------------------------------------------------


def evaluate_matrix(matrix: sp.MatrixBase, values: Mapping[sp.Symbol, float]) -> np.ndarray | None:
    """The real numbers of ``matrix`` at ``values``; None if any entry is not finite and real."""
    entries = [to_sympy(e) for e in matrix]
    read = [_read_off(e, values) for e in entries]
    if None not in read:  # an inertia given by its moments: parameters, their negatives, 0
        entries = read
    else:
        # only the symbols of the entries are made 30-digit numbers (a System's samples give
        # every coordinate and parameter a value, a body's inertia has a few of them)
        used = set().union(*(e.free_symbols for e in entries))
        exact = {s: sp.Float(v, 30) for s, v in values.items() if s in used}
        try:
            entries = [_complex(_evaluated(e.xreplace(exact))) for e in entries]
        except (TypeError, ValueError, ZeroDivisionError):
            return None
    array = np.array(entries).reshape(matrix.shape)
    if not np.all(np.isfinite(array)) or np.max(np.abs(array.imag)) > 1e-12:
        return None
    return array.real


def _evaluated(value: sp.Expr) -> sp.Expr:
    """``value`` to 30 digits (a Float of them, or 0, as it is already)."""
    return value if value.is_Float or value is sp.S.Zero else value.evalf(30)


def _read_off(entry: sp.Expr, values: Mapping[sp.Symbol, float]) -> complex | None:
    """The value at ``values`` of an entry that is an integer, a symbol given there or its
    negative, read off exactly: the double its 30-digit evaluation rounds back to (a double
    is exact in 30 digits, and so is its negative); None for any other entry."""
    if entry.is_Integer:
        return complex(int(entry))
    negative = entry.is_Mul and len(entry.args) == 2 and entry.args[0] is sp.S.NegativeOne
    symbol = entry.args[1] if negative else entry
    value = values.get(symbol) if symbol.is_Symbol else None
    if value is None or type(value) not in (float, int):
        return None
    return complex(-float(value) if negative else float(value))


def _complex(value: sp.Expr) -> complex:
    """``complex(value)``; a Float read as the double nearest to it directly (SymPy's
    ``complex`` evaluates it to 15 digits first, 53 bits: the same double, rounded once)."""
    return complex(float(value)) if value.is_Float else complex(value)


def _in_backend(matrix: sp.MatrixBase) -> list[Any] | None:
    memo: dict[Any, Any] = {}  # a product of rotations multiplied out repeats its parts
    try:
        return [to_symengine_sharing(e, memo) for e in matrix]
    except (se.SympifyError, TypeError, ValueError):
        return None


def _doubles(
    entries: list[Any], values: Mapping[sp.Symbol, float], names: set[str]
) -> np.ndarray | None:
    """A 3x3 matrix's entries (SymEngine) at ``values`` in double precision (ample for a
    test of R^T R = 1 to 1e-9, and a hundred times faster than SymPy's evalf on a product
    of rotations); None where they are not all finite real numbers.  ``names``: those of the
    entries' symbols (the values of the others replace nothing)."""
    swap = {to_symengine(s): se.RealDouble(float(v)) for s, v in values.items() if s.name in names}
    try:
        numbers = [complex(e.xreplace(swap)) for e in entries]
    except (TypeError, ValueError, RuntimeError):
        return None
    array = np.array(numbers).reshape(3, 3)
    if not np.all(np.isfinite(array)) or np.max(np.abs(array.imag)) > 1e-12:
        return None
    return array.real


def check_rotation(
    matrix: sp.MatrixBase,
    field: str,
    samples: Iterable[Mapping[sp.Symbol, float]],
    subject: str = "the rotation",
) -> list[Problem]:
    """Problems of a rotation matrix R(q, t): R^T R - 1 not zero, or det R = -1, at any of
    the numeric ``samples`` (values of the coordinates, t and the parameters).

    >>> x = sp.Symbol("x")
    >>> check_rotation(sp.Matrix([[1, 0, 0], [0, 1, x], [0, 0, 1]]), "R", [{x: 0.5}])[0].message
    'the rotation is not orthonormal: R^T R - 1 has an entry of 0.5 at x = 0.5'
    """
    fix = "give an orthonormal matrix, or build it with euler_rotation, axis_angle or quaternions"
    entries = _in_backend(matrix)
    names = {s.name for e in entries for s in e.free_symbols} if entries is not None else set()
    for values in samples:
        R = _doubles(entries, values, names) if entries is not None else None
        R = evaluate_matrix(matrix, values) if R is None else R
        if R is None:
            continue
        defect = float(np.max(np.abs(R.T @ R - np.eye(3))))
        if defect > 1e-9:
            message = f"{subject} is not orthonormal: R^T R - 1 has an entry of {defect:.3g}"
            return [Problem(field, f"{message} at {_where(matrix, values)}", fix)]
        if np.linalg.det(R) < 0:
            message = f"{subject} is a reflection (det R = -1) at {_where(matrix, values)}"
            return [Problem(field, message, fix)]
    return []


def _where(matrix: sp.MatrixBase, values: Mapping[sp.Symbol, float]) -> str:
    """The values of ``matrix``'s symbols at a sample, for a message (its symbols are found
    only then: a product of rotations is a long walk)."""
    used = sorted(matrix.free_symbols & set(values), key=str)
    return ", ".join(f"{s} = {values[s]:.4g}" for s in used) or "every configuration"
