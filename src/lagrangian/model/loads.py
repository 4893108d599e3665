"""Loads that are not a force at a body's centre: a force at a body-fixed point, a torque
between two bodies (action and reaction), and a torque on a massless frame; each written
with the elements a System already has, so that its virtual work is the right one.

A force F at the material point p + a of a rigid body (a = R k in world axes, k fixed in the
body) does the virtual work F . (delta p + delta theta x a) = F . delta p + (a x F) . delta
theta: the same force at the centre and the torque a x F.  A torque tau that body A exerts on
body B exerts -tau on A (Newton's third law), so the pair does the work tau . (delta
theta_B - delta theta_A): only the relative rotation.  A torque on a frame turned by the
coordinates does Q_j = tau . d(omega_s)/d(q_dot_j), omega_s the frame's spatial angular
velocity.

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
from lagrangian.model.conversion import to_sympy
from lagrangian.model.elements import Force, RigidBody, Torque
from lagrangian.model.rotation import spatial_angular_velocity
from lagrangian.model.symbols import velocity


def _vector3(value: Sequence[Any], field: str) -> sp.Matrix:
    items = list(value)
    if len(items) != 3:
        fix = "give 3 components (world axes), e.g. (0, 0, tau)"
        raise ModelError(f"{field} needs 3 components", [Problem(field, "not a 3-vector", fix)])
    return sp.Matrix([to_sympy(e) for e in items])


def force_at_point(
    body: RigidBody, offset: Sequence[Any], force: Sequence[Any], name: str = ""
) -> tuple[Force, Torque]:
    """A force (world axes) at the body-fixed point at ``offset`` from the centre of mass
    (body axes) of the 3-D ``body`` (as the System holds it: its orientation composed), as
    the force at the centre and the torque (R k) x F.

    >>> import lagrangian as lg
    >>> q, F = sp.symbols("q F")
    >>> rod = lg.RigidBody("rod", 1, sp.eye(3), (0, 0, 0), rotations=[("z", q)])
    >>> rod = lg.System(coordinates=[q], rigid_bodies=[rod]).rigid_bodies[0]
    >>> force_at_point(rod, (1, 0, 0), (0, F, 0))[1].torque
    (0, 0, F*cos(q))
    """
    if body.orientation is None:
        fix = "give the body an orientation (or parent and rotations)"
        problem = Problem("body", f"the body {body.name!r} is not a 3-D rigid body", fix)
        raise ModelError("No orientation", [problem])
    arm = body.orientation.matrix * _vector3(offset, "offset")
    push = _vector3(force, "force")
    moment = tuple(sp.expand(e) for e in arm.cross(push))
    label = name or f"force on {body.name}"
    return Force(body.name, tuple(push), label), Torque(body.name, moment, f"{label} moment")


def torque_pair(on: str, by: str, torque: Sequence[Any], name: str = "") -> tuple[Torque, Torque]:
    """The torque ``torque`` (world axes) that the body ``by`` exerts on the body ``on``, and
    its reaction -torque on ``by`` (a motor between a frame and a fork, a spring in a joint)."""
    tau = _vector3(torque, "torque")
    label = name or f"torque {by} on {on}"
    return (
        Torque(on, tuple(tau), label),
        Torque(by, tuple(-e for e in tau), f"{label} reaction"),
    )


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
