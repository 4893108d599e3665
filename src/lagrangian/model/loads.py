"""Loads that are not a force at a body's centre: a force at a body-fixed point, a torque
between two bodies (action and reaction), and a torque on a massless frame; each written
with the elements a System already has, so that its virtual work is the right one.

A force F at the material point p + a of a rigid body (a = R k in world axes, k fixed in the
body) does the virtual work F . (delta p + delta theta x a) = F . delta p + (a x F) . delta
theta: the same force at the centre and the torque a x F.  A torque tau that body A exerts on
body B exerts -tau on A (Newton's third law), so the pair does the work tau . (delta
theta_B - delta theta_A): only the relative rotation.  A torque on a frame turned by the
coordinates does Q_j = tau . d(omega_s)/d(q_dot_j), omega_s the frame's spatial angular
velocity.  On planar bodies the same holds with scalar torques: a force at the body point
R(angle) k does the work of the force at the centre and the torque (R k) x F (its z
component), and a pair acts on the difference of the two angles.

>>> import sympy as sp
>>> import lagrangian as lg
>>> tau = sp.Symbol("tau")
>>> [(load.body, load.torque) for load in torque_pair("fork", "frame", (0, 0, tau))]
[('fork', (0, 0, tau)), ('frame', (0, 0, -tau))]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.model.elements import Force, RigidBody, Torque
from lagrangian.model.rotation import spatial_angular_velocity
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import velocity


def _vector3(value: Sequence[Any], field: str) -> sp.Matrix:
    return _sized(value, field, 3, "give 3 components (world axes), e.g. (0, 0, tau)")


def _sized(value: Any, field: str, size: int, fix: str) -> sp.Matrix:
    items = list(value) if isinstance(value, (list, tuple, sp.MatrixBase)) else [value]
    if len(items) != size:
        message = f"{field} needs {size} components"
        raise ModelError(message, [Problem(field, f"not a {size}-vector", fix)])
    return sp.Matrix([to_sympy(e) for e in items])


def force_at_point(
    body: RigidBody, offset: Sequence[Any], force: Sequence[Any], name: str = ""
) -> tuple[Force, Torque]:
    """A force (world axes) at the body-fixed point at ``offset`` from the centre of mass
    (body axes) of ``body`` (as the System holds it: its orientation composed), as the force
    at the centre and the torque (R k) x F.  On a planar body (an ``angle``, R the rotation
    by it) the offset and the force have 2 components and the torque is a scalar.

    >>> import lagrangian as lg
    >>> q, F = sp.symbols("q F")
    >>> rod = lg.RigidBody("rod", 1, sp.eye(3), (0, 0, 0), rotations=[("z", q)])
    >>> rod = lg.System(coordinates=[q], rigid_bodies=[rod]).rigid_bodies[0]
    >>> force_at_point(rod, (1, 0, 0), (0, F, 0))[1].torque
    (0, 0, F*cos(q))
    >>> flat = lg.RigidBody("rod", 1, 1, (0, 0), angle=q)
    >>> force_at_point(flat, (1, 0), (0, F))[1].torque
    F*cos(q)
    """
    label = name or f"force on {body.name}"
    if body.orientation is None and body.angle is not None and not body.relative:
        arm = _planar_rotation(body.angle) * _sized(offset, "offset", 2, _FIX_PLANAR)
        push = _sized(force, "force", 2, "give 2 components (world axes), e.g. (F, 0)")
        moment = sp.expand(arm[0] * push[1] - arm[1] * push[0])
        return Force(body.name, tuple(push), label), Torque(body.name, moment, f"{label} moment")
    if body.orientation is None:
        fix = "give the body an orientation (or parent and rotations), or a planar angle"
        problem = Problem("body", f"the body {body.name!r} is not a 3-D rigid body", fix)
        raise ModelError("No orientation", [problem])
    arm = body.orientation.matrix * _sized(offset, "offset", 3, _FIX_SPATIAL)
    push = _vector3(force, "force")
    moments = tuple(sp.expand(e) for e in arm.cross(push))
    return Force(body.name, tuple(push), label), Torque(body.name, moments, f"{label} moment")


_FIX_PLANAR = "give the point in body axes as [dx, dy] (a planar body)"
_FIX_SPATIAL = "give the point in body axes as [dx, dy, dz] (a 3-D body)"


def _planar_rotation(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def torque_pair(on: str, by: str, torque: Any, name: str = "") -> tuple[Torque, Torque]:
    """The torque ``torque`` that the body ``by`` exerts on the body ``on``, and its reaction
    -torque on ``by`` (a motor between a frame and a fork, a spring in a joint): 3 components
    in world axes between 3-D bodies, a scalar between planar ones.

    >>> [load.torque for load in torque_pair("rotor", "stator", sp.Symbol("tau"))]
    [tau, -tau]
    """
    if on == by:
        fix = "name the body the torque acts on and another body that exerts it"
        problem = Problem("by", f"a torque pair needs two bodies, got {on!r} twice", fix)
        raise ModelError("A torque pair on one body", [problem])
    label = name or f"torque {by} on {on}"
    if isinstance(torque, (list, tuple, sp.MatrixBase)):
        tau = _vector3(torque, "torque")
        return (
            Torque(on, tuple(tau), label),
            Torque(by, tuple(-e for e in tau), f"{label} reaction"),
        )
    scalar = to_sympy(torque)
    return Torque(on, scalar, label), Torque(by, -scalar, f"{label} reaction")


def frame_torque(
    orientation: Any, coordinates: Sequence[sp.Symbol], torque: Sequence[Any]
) -> Mapping[sp.Symbol, sp.Expr]:
    """The generalized forces Q_j = tau . d(omega_s)/d(q_dot_j) of a torque (world axes) on a
    frame or body of the given orientation (a System's composed one): coordinate -> Q_j, the
    zero ones left out; add them to the System's ``generalized_forces``.

    >>> from lagrangian.model.rotation import rotation_sequence
    >>> psi, theta, tau = sp.symbols("psi theta tau")
    >>> lean = rotation_sequence([("z", psi), ("x", theta)])
    >>> dict(frame_torque(lean, [psi, theta], (tau, 0, 0)))
    {theta: tau*cos(psi)}
    """
    q = list(coordinates)
    omega = sp.Matrix(spatial_angular_velocity(orientation, q))
    tau = _vector3(torque, "torque")
    found = {}
    for coordinate in q:
        rate = velocity(coordinate)
        value = sp.expand(tau.dot(omega.diff(rate)))
        if value != 0:
            found[coordinate] = value
    return found
