"""Rolling contact: a thin disc (a wheel) of a 3-D rigid body rolling without slipping on the
horizontal plane z = 0, and the constraints it makes (Greenwood, Advanced Dynamics, 2003, §3.4;
Neimark & Fufaev, Dynamics of Nonholonomic Systems, ch. 1).

With the centre p(q, t), the unit axle a = R n (n the axle in body axes) and the disc's radius
r, the lowest point of the rim is C = p + r d, d the unit vector of the disc's plane that points
most downward:

    d = (a (a . e_z) - e_z) / s,   s = sqrt(a_x^2 + a_y^2) = |a x e_z|,   so  d_z = -s.

A force applied at the contact point (``at: BODY_contact``) acts on the disc's material point
there: the System moves it to the centre with its moment (r d) x F as a torque, so that
Q_j = F . d(v_C)/d(q_dot_j) by virtual work.

The disc touches the plane when C_z = p_z - r s = 0 (holonomic; left out when it holds
identically, when the centre height is written as r s already), and rolls without slipping when
the disc's material point at C is at rest:

    v_C = p_dot + omega_s x (r d) = 0,

whose x and y components are velocity (Pfaffian) constraints; the z component is the time
derivative of the holonomic one (the rim's tangent at its lowest point is horizontal).  The
multipliers of the three constraints are the contact force's components in world axes.

s = sqrt(1 - a_z^2); when ``trigsimp`` finds 1 - a_z^2 a square its root is taken on the
branch s > 0 (the disc not lying flat), so a disc given by heading, lean and spin has
s = cos(lean).

A wheel with a round tyre (a torus: ``radius`` R from the centre to the circle through the
tyre's centres, ``tyre_radius`` r_t) touches the plane at the lowest point of that tyre,

    C = p + R d - r_t e_z,

and a sphere of radius r (:func:`rolling_sphere`) is the torus with R = 0: C = p - r e_z, no
axle needed.  The constraints are the same with this C: C_z = 0 and the x and y components of
v_C = p_dot + omega_s x (C - p) = 0.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.model.constraints import Holonomic, VelocityConstraint
from lagrangian.model.elements import Force, RigidBody, Torque, as_expression
from lagrangian.model.inertia import Shape
from lagrangian.model.probe import is_zero
from lagrangian.model.rotation import rotation_axis, spatial_angular_velocity
from lagrangian.model.symbols import time_derivative, velocity
from lagrangian.model.validation import CONFIGURATION, NameScope

#: Shapes whose axis of symmetry is a wheel's axle.
WHEEL_SHAPES = ("disc", "ring", "cylinder")


@dataclass(frozen=True)
class RollingDisc:
    """A thin disc of radius ``radius`` on the rigid body ``body`` (centred at the body's
    centre of mass, its axle along ``axis`` in body axes: ``"x"``, ``"y"``, ``"z"`` or a
    vector; by default the axis of the body's disc, ring or cylinder shape) rolling without
    slipping on the plane z = 0.  ``name`` names the contact point (default ``BODY_contact``).
    With ``tyre_radius`` r_t the wheel is a torus: a round tyre of radius r_t whose centres
    lie on the circle of radius ``radius`` (the module docstring).
    """

    body: str
    radius: sp.Expr
    axis: Any = None
    name: str = ""
    tyre_radius: sp.Expr = sp.Integer(0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", as_expression(self.radius))
        object.__setattr__(self, "tyre_radius", as_expression(self.tyre_radius))

    @property
    def contact(self) -> str:
        """The name of the contact point."""
        return self.name or f"{self.body}_contact"


@dataclass(frozen=True)
class ContactHeight(Holonomic):
    """The holonomic constraint C_z = 0 of a :class:`RollingDisc` (made by the System)."""

    contact: str = ""


@dataclass(frozen=True)
class NoSlip(VelocityConstraint):
    """A no-slip constraint (one world component of v_C = 0) of a :class:`RollingDisc`."""

    contact: str = ""


GENERATED = (ContactHeight, NoSlip)


def rolling_sphere(body: str, radius: Any, name: str = "") -> RollingDisc:
    """A ball of radius ``radius`` (the rigid body ``body``, centred at its centre of mass)
    rolling without slipping on the plane z = 0: the torus with no hole, so its contact point
    is C = p - r e_z whatever its orientation.

    >>> rolling_sphere("ball", 2).tyre_radius
    2
    """
    return RollingDisc(body, 0, name=name, tyre_radius=radius)


def contact_offset(disc: RollingDisc, body: RigidBody) -> sp.ImmutableMatrix:
    """C - p = R d - r_t e_z, the contact point relative to the centre in world axes (the
    module docstring).

    >>> import lagrangian as lg
    >>> psi, theta, r = sp.symbols("psi theta r")
    >>> wheel = lg.RigidBody("w", 1, sp.eye(3), (0, 0, 0),
    ...                      orientation=lg.model.euler_rotation("ZXY", (psi, theta, 0)))
    >>> contact_offset(RollingDisc("w", r, "y"), wheel).T
    Matrix([[-r*sin(psi)*sin(theta), r*sin(theta)*cos(psi), -r*cos(theta)]])
    """
    offset = sp.Matrix([0, 0, -disc.tyre_radius])
    if not is_zero(disc.radius):
        offset += disc.radius * rim_direction(disc, body)
    return sp.ImmutableMatrix(_roots_kept(offset.applyfunc(sp.expand), offset))


def rim_direction(disc: RollingDisc, body: RigidBody) -> sp.ImmutableMatrix:
    """d = (a (a . e_z) - e_z) / s, the unit vector of the wheel's plane that points most
    downward (world axes; the module docstring)."""
    n = sp.Matrix(_axle(disc, body))
    a = body.orientation.matrix * (n / sp.sqrt(sp.expand(n.dot(n))))  # type: ignore[union-attr]
    a = a.applyfunc(sp.expand)
    s = _horizontal_length(a[2])
    return sp.ImmutableMatrix([a[0] * a[2] / s, a[1] * a[2] / s, -s])


#: Above this many operations 1 - a_z^2 is not given to ``trigsimp`` (which may answer with a
#: long sum of multiple angles, not a square).
TRIGSIMP_OPS = 120


def _horizontal_length(a_z: sp.Expr) -> sp.Expr:
    """s = sqrt(a_x^2 + a_y^2) = sqrt(1 - a_z^2) for the unit axle a: the square root of
    ``trigsimp``'s answer when that is a square (cos(lean)^2 -> cos(lean), on the branch
    s > 0), else sqrt(1 - a_z^2) with a_z as it is (a short product of sines and cosines;
    the sum of multiple angles ``trigsimp`` gives for a steered wheel is far longer)."""
    square = sp.expand(1 - a_z**2)
    if sp.count_ops(square) <= TRIGSIMP_OPS:
        simple = sp.trigsimp(square)
        if (simple.is_Pow and simple.exp.is_even) or not simple.free_symbols:
            return sp.powdenest(sp.sqrt(simple), force=True)
    return sp.sqrt(1 - a_z**2)


def _axle(disc: RollingDisc, body: RigidBody) -> tuple[sp.Expr, ...]:
    if disc.axis is not None:
        return rotation_axis(disc.axis, "axis")
    if isinstance(body.inertia, Shape) and body.inertia.kind in WHEEL_SHAPES:
        return rotation_axis(body.inertia.axis, "axis")
    fix = "give its axle, axis: x, y or z (body axes), or give the body a disc, ring or cylinder"
    raise ModelError("no axle", [Problem("axis", f"the body {body.name!r} has no wheel axle", fix)])


def contact_point(disc: RollingDisc, body: RigidBody) -> tuple[sp.Expr, ...]:
    """C = p + r d, the lowest point of the disc's rim (world axes)."""
    offset = contact_offset(disc, body)
    return tuple(sp.expand(p + e) for p, e in zip(body.position, offset))


def rolling_constraints(disc: RollingDisc, body: RigidBody, coordinates: Any) -> tuple[Any, ...]:
    """The constraints of ``disc`` on ``body``: C_z = 0 (unless it holds identically), then
    the x and y components of v_C = p_dot + omega_s x (r d) = 0."""
    q = tuple(coordinates)
    offset = sp.Matrix(contact_offset(disc, body))
    height = _roots_kept(sp.expand(body.position[2] + offset[2]), offset)
    omega = sp.Matrix(spatial_angular_velocity(body.orientation, q))
    p_dot = sp.Matrix([time_derivative(x, q) for x in body.position])
    rates = [velocity(x) for x in q]
    slip = _roots_kept((p_dot + omega.cross(offset)).applyfunc(lambda e: _tidy(e, rates)), offset)
    name = disc.contact
    found: list[Any] = [] if is_zero(height) else [ContactHeight(height, f"{name} height", name)]
    found += [NoSlip(slip[k], f"{name} slip {axis}", name) for k, axis in ((0, "x"), (1, "y"))]
    return tuple(found)


def _roots_kept(expr: Any, like: Any) -> Any:
    """``expr`` with each square root of ``like`` (s, 1/s) put back as it was written there:
    ``expand`` multiplies out the sum under sqrt(1 - a_z^2) too, which makes it far longer."""
    table = {}
    for power in sp.Matrix(like).atoms(sp.Pow):
        if power.exp in (sp.S.Half, -sp.S.Half) and power.base.is_Add:
            table[sp.Pow(sp.expand(power.base), power.exp)] = power
            table[sp.Pow(sp.expand(power.base), -power.exp)] = 1 / power
    return expr.xreplace(table) if table else expr


def _tidy(expr: sp.Expr, rates: list[sp.Symbol]) -> sp.Expr:
    """``expr`` with the coefficient of each velocity reduced by sin(u)^2 = 1 - cos(u)^2 (a
    normal form of polynomials in sines and cosines), where that makes it shorter."""
    terms = sp.collect(sp.expand(expr), rates, evaluate=False)
    return sp.Add(*[_shorter(part) * rate for rate, part in terms.items()])


def _shorter(expr: sp.Expr) -> sp.Expr:
    def square_free(power: sp.Pow) -> sp.Expr:
        k, rest = divmod(int(power.exp), 2)
        u = power.base.args[0]
        return sp.sin(u) ** rest * (1 - sp.cos(u) ** 2) ** k

    even = [p for p in expr.atoms(sp.Pow) if p.base.func == sp.sin and p.exp.is_Integer]
    if not [p for p in even if p.exp >= 2]:
        return expr
    reduced = sp.expand(expr.xreplace({p: square_free(p) for p in even if p.exp >= 2}))
    return reduced if sp.count_ops(reduced) < sp.count_ops(expr) else expr


def add_rolling_constraints(values: dict[str, Any]) -> list[Problem]:
    """Replace the constraints made by rolling discs in the canonical System ``values`` with
    those of its ``rolling`` discs now (after the bodies' orientations are resolved); the
    problems found (an unknown body, a planar one, no axle, a disc lying flat)."""
    problems: list[Problem] = []
    kept = [c for c in values["constraints"] if not isinstance(c, GENERATED)]
    bodies = {b.name: b for b in values["rigid_bodies"]}
    scope = NameScope(values)
    made: list[Any] = []
    for i, disc in enumerate(values["rolling"]):
        field = f"rolling[{i}]"
        body = bodies.get(disc.body)
        if body is None or body.planar or not _spatial(body):
            problems.append(_body_problem(disc, field, bodies))
            continue
        before = len(problems)
        scope.check(disc.radius, f"{field}.radius", CONFIGURATION, problems)
        scope.check(disc.tyre_radius, f"{field}.tyre_radius", CONFIGURATION, problems)
        if len(problems) > before:
            continue
        try:
            flat = not is_zero(disc.radius) and _lies_flat(rim_direction(disc, body))
        except ModelError as error:
            problems += [Problem(f"{field}.{p.field}", p.message, p.fix) for p in error.problems]
            continue
        if flat:
            fix = "orient the body so that its axle is not vertical"
            message = f"the disc of body {disc.body!r} lies flat on the plane"
            problems.append(Problem(field, message, fix))
            continue
        made += rolling_constraints(disc, body, values["coordinates"])
    values["constraints"] = (*kept, *made)
    return problems


def move_contact_forces(values: dict[str, Any]) -> None:
    """In the canonical System ``values``, replace every force applied at the contact point
    of a rolling disc by the same force at the body's centre and the torque (r d) x F (world
    axes): together they do the virtual work F . delta r_C of the material point at C."""
    bodies = {b.name: b for b in values["rigid_bodies"]}
    contacts = {}
    for disc in values["rolling"]:
        body = bodies.get(disc.body)
        if body is not None and not body.planar and _spatial(body):
            contacts[disc.contact] = (disc, body)
    forces, torques = [], list(values["torques"])
    for force in values["forces"]:
        if not (isinstance(force.at, str) and force.at in contacts):
            forces.append(force)
            continue
        disc, body = contacts[force.at]
        forces.append(Force(body.name, force.force, force.name))
        if not (isinstance(force.force, tuple) and len(force.force) == 3):
            continue  # the validator reports its shape
        arm, push = sp.Matrix(contact_offset(disc, body)), sp.Matrix(force.force)
        moment = tuple(sp.expand(e) for e in arm.cross(push))
        torques.append(Torque(body.name, moment, force.name or f"{force.at} moment"))
    values["forces"], values["torques"] = tuple(forces), tuple(torques)


def _lies_flat(direction: sp.MatrixBase) -> bool:
    """True when the axle is vertical: s = 0, so d (and the contact point) is undefined."""
    return direction.has(sp.zoo, sp.nan) or is_zero(direction[2])


def _spatial(body: RigidBody) -> bool:
    position = body.position
    return isinstance(position, tuple) and len(position) == 3 and body.orientation is not None


def _body_problem(disc: RollingDisc, field: str, bodies: dict[str, RigidBody]) -> Problem:
    if disc.body in bodies:
        message = f"the body {disc.body!r} is not a 3-D rigid body"
        return Problem(f"{field}.body", message, "give it a 3-D position and an orientation")
    close = difflib.get_close_matches(str(disc.body), sorted(bodies), n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    message = f"unknown rigid body {disc.body!r}"
    return Problem(f"{field}.body", message, hint + "name one of the rigid_bodies")
