"""Inertia given about a body point, forces at body-fixed points, torques between bodies and on
frames: each against the virtual work it must do (closed forms, and the derivative of the
material point's position written out by hand)."""

from __future__ import annotations

import random

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.model import Frame, RigidBody, System
from lagrangian.model.inertia import central_inertia, parallel_axis
from lagrangian.model.loads import force_at_point, frame_torque, torque_pair
from lagrangian.model.rotation import euler_rotation, rotation_sequence

a, b, c, x, y, z, m, L, F, tau = sp.symbols("a b c x y z m L F tau")


def test_central_inertia_undoes_the_parallel_axis_theorem() -> None:
    rng = random.Random(2)
    centre = [sp.Rational(rng.randint(-9, 9), 7) for _ in range(3)]
    tensor = sp.Matrix([[3, 1, 0], [1, 4, -1], [0, -1, 5]])
    about_point = parallel_axis(tensor, m, centre)
    assert central_inertia(about_point, m, centre) == sp.ImmutableMatrix(tensor)
    # a rod of length L about its end: m L^2/3 -> m L^2/12 about the middle
    assert central_inertia(sp.diag(0, m * L**2 / 3, m * L**2 / 3), m, [L / 2, 0, 0]) == sp.diag(
        0, m * L**2 / 12, m * L**2 / 12
    )


def test_a_compound_pendulum_given_its_inertia_about_the_pivot() -> None:
    """A rod swinging about a fixed pivot: T = 1/2 I_P a_dot^2 with I_P = m L^2/3, whatever
    the inertia was given about (Goldstein §5.1)."""
    about_pivot = sp.diag(m * L**2 / 3, m * L**2 / 3, 0)  # the rod along its z axis
    inertia = central_inertia(about_pivot, m, [0, 0, -L / 2])
    centre = (L / 2 * sp.sin(a), 0, -L / 2 * sp.cos(a))
    rod = RigidBody("rod", m, inertia, centre, rotations=[("y", a)])
    g = sp.Symbol("g")
    eom = lg.derive(System(coordinates=[a], parameters=[m, L, g], rigid_bodies=[rod]))
    assert sp.simplify(eom.mass_matrix[0, 0] - m * L**2 / 3) == 0


def _body(system: System, name: str) -> RigidBody:
    return next(body for body in system.rigid_bodies if body.name == name)


def test_a_force_at_a_body_point_does_the_work_of_that_material_point() -> None:
    """Q_j = F . d(p + R k)/dq_j for the material point at k (body axes), at random states."""
    orientation = euler_rotation("ZYX", (a, b, c))
    block = RigidBody("block", m, sp.diag(1, 2, 3), (x, y, z), orientation=orientation)
    system = System(coordinates=[x, y, z, a, b, c], parameters=[m, F], rigid_bodies=[block])
    k, push = (sp.Rational(1, 3), -2, sp.Rational(1, 2)), (F, 2 * F, -F)
    force, moment = force_at_point(_body(system, "block"), k, push, name="push")
    loaded = system.replace(forces=[force], torques=[moment])
    ours = lg.derive(loaded).generalized_forces
    point = sp.Matrix([x, y, z]) + orientation.matrix * sp.Matrix(k)
    rng = random.Random(4)
    for _ in range(3):
        values = {s: rng.uniform(-1.0, 1.0) for s in (x, y, z, a, b, c, F)}
        for j, q in enumerate(system.coordinates):
            work = sp.Matrix(push).dot(point.diff(q))
            assert float((ours[j] - work).xreplace(values)) == pytest.approx(0, abs=1e-12)


def test_a_torque_between_two_bodies_acts_only_on_their_relative_rotation() -> None:
    """A frame yawing by a and a fork steered by b relative to it, a steering torque tau
    between them: the pair does tau delta b, nothing on a (action and reaction)."""
    frame = RigidBody("frame", m, sp.diag(1, 2, 3), (0, 0, 0), rotations=[("z", a)])
    fork = RigidBody("fork", m, sp.diag(1, 1, 1), (0, 0, 0), parent="frame", rotations=[("z", b)])
    pair = torque_pair("fork", "frame", (0, 0, tau), name="steer")
    system = System(coordinates=[a, b], parameters=[m, tau], rigid_bodies=[frame, fork])
    forces = lg.derive(system.replace(torques=list(pair))).generalized_forces
    assert list(forces) == [0, tau]
    assert [t.name for t in pair] == ["steer", "steer reaction"]


def test_a_torque_on_a_frame_gives_the_generalized_forces_of_its_rotation() -> None:
    """A gimbal (frame) yawing by a, tilted by b about its x axis: a torque tau about the
    world x axis does tau (omega_s . e_x) = tau cos(a) b_dot."""
    gimbal = Frame("gimbal", [("z", a), ("x", b)])
    rotor = RigidBody("rotor", m, sp.diag(1, 1, 2), (0, 0, 0), parent="gimbal")
    system = System(coordinates=[a, b], parameters=[m, tau], frames=[gimbal], rigid_bodies=[rotor])
    composed = next(f for f in system.frames if f.name == "gimbal").orientation
    assert dict(frame_torque(composed, [a, b], (tau, 0, 0))) == {b: tau * sp.cos(a)}
    direct = rotation_sequence([("z", a), ("x", b)])
    assert dict(frame_torque(direct, [a, b], (0, 0, tau))) == {a: tau}


def test_a_force_at_a_planar_body_point_does_the_work_of_that_material_point() -> None:
    """A planar block at (x, y) turned by a: Q_j = F . d(p + R(a) k)/dq_j."""
    block = RigidBody("block", m, 1, (x, y), angle=a)
    k, push = (sp.Rational(1, 3), -2), (F, 2 * F)
    force, moment = force_at_point(block, k, push)
    system = System(coordinates=[x, y, a], parameters=[m, F], rigid_bodies=[block])
    ours = lg.derive(system.replace(forces=[force], torques=[moment])).generalized_forces
    turn = sp.Matrix([[sp.cos(a), -sp.sin(a)], [sp.sin(a), sp.cos(a)]])
    point = sp.Matrix([x, y]) + turn * sp.Matrix(k)
    for j, q in enumerate(system.coordinates):
        assert sp.simplify(ours[j] - sp.Matrix(push).dot(point.diff(q))) == 0


def test_a_planar_torque_pair_is_a_scalar_and_its_reaction() -> None:
    pair = torque_pair("rotor", "stator", tau, name="motor")
    assert [(t.body, t.torque, t.name) for t in pair] == [
        ("rotor", tau, "motor"),
        ("stator", -tau, "motor reaction"),
    ]


def test_bad_loads_are_refused_with_the_fix() -> None:
    planar = RigidBody("disc", m, 1, (x, y), angle=a)
    with pytest.raises(ModelError, match=r"offset: not a 2-vector.*\[dx, dy\]"):
        force_at_point(planar, (1, 0, 0), (F, 0, 0))
    with pytest.raises(ModelError, match=r"force: not a 2-vector"):
        force_at_point(planar, (1, 0), (F, 0, 0))
    unoriented = RigidBody("box", m, sp.eye(3), (x, y, z))
    with pytest.raises(ModelError, match=r"'box' is not a 3-D rigid body.*orientation"):
        force_at_point(unoriented, (1, 0, 0), (F, 0, 0))
    with pytest.raises(ModelError, match=r"torque needs 3 components"):
        torque_pair("fork", "frame", (0, tau))
    with pytest.raises(ModelError, match=r"by: a torque pair needs two bodies, got 'fork' twice"):
        torque_pair("fork", "fork", (0, 0, tau))
