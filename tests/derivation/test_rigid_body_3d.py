"""3-D rigid bodies in the System, T = 1/2 m v_c.v_c + 1/2 omega_b^T I omega_b, cross-checked
against sympy.physics.mechanics (RigidBody, frames oriented by its own methods, LagrangesMethod
or KanesMethod): the mass matrix and the accelerations M^-1 forcing at random states and
parameters, and the kinetic energy itself.  Each system is built twice, independently."""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.model.inertia import cylinder
from lagrangian.model.rotation import (
    as_orientation,
    axis_angle,
    euler_rotation,
    quaternion_rotation,
)
from lagrangian.symbolic.symbols import t, velocity

TIME = me.dynamicsymbols._t


@dataclass(frozen=True)
class Reference:
    """sympy.physics.mechanics' M, forcing and T in lagrangian's plain symbols."""

    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    kinetic_energy: sp.Expr


def _plain(expr: sp.Basic, coordinates: Sequence[sp.Function], speeds=()) -> sp.Basic:
    swap: dict[sp.Basic, sp.Basic] = {TIME: t}
    for j, q in enumerate(coordinates):
        name = q.func.__name__
        swap[q.diff(TIME, 2)] = sp.Symbol(name + "_ddot")
        swap[q.diff(TIME)] = sp.Symbol(name + "_dot")
        if speeds:
            swap[speeds[j].diff(TIME)] = sp.Symbol(name + "_ddot")
            swap[speeds[j]] = sp.Symbol(name + "_dot")
    swap.update({q: sp.Symbol(q.func.__name__) for q in coordinates})
    return expr.xreplace(swap)


def lagranges(frame, coordinates, bodies, potential, forcelist=()) -> Reference:
    lagrangian = me.Lagrangian(frame, *bodies) - potential
    method = me.LagrangesMethod(lagrangian, coordinates, forcelist=list(forcelist), frame=frame)
    method.form_lagranges_equations()
    kinetic = sum(b.kinetic_energy(frame) for b in bodies)
    return Reference(
        _plain(method.mass_matrix, coordinates),
        _plain(method.forcing, coordinates),
        _plain(kinetic, coordinates),
    )


def kanes(frame, coordinates, bodies, loads) -> Reference:
    speeds = [me.dynamicsymbols(f"u_{q.func.__name__}") for q in coordinates]
    kinematics = [q.diff(TIME) - u for q, u in zip(coordinates, speeds)]
    method = me.KanesMethod(frame, coordinates, speeds, kd_eqs=kinematics)
    method.kanes_equations(list(bodies), list(loads))
    swap = dict(zip(speeds, (q.diff(TIME) for q in coordinates)))
    kinetic = sum(b.kinetic_energy(frame) for b in bodies)
    return Reference(
        _plain(method.mass_matrix, coordinates, speeds),
        _plain(method.forcing, coordinates, speeds),
        _plain(kinetic.xreplace(swap), coordinates),
    )


def _state(system: lg.System, rng: random.Random) -> dict[sp.Symbol, float]:
    values = {p: rng.uniform(0.5, 1.5) for p in system.parameters}
    values.update({q: rng.uniform(-1.2, 1.2) for q in system.coordinates})
    values.update({v: rng.uniform(-2.0, 2.0) for v in system.velocities})
    values[t] = rng.uniform(0.0, 2.0)
    return values


def _numbers(expr: sp.Basic, values) -> np.ndarray:
    return np.array(sp.Matrix(expr).xreplace(values).evalf(), dtype=float)


def assert_same_motion(system: lg.System, reference: Reference, states: int = 3) -> None:
    eom = lg.derive(system)
    rng = random.Random(11)
    for _ in range(states):
        values = _state(system, rng)
        mass, ref_mass = _numbers(eom.mass_matrix, values), _numbers(reference.mass_matrix, values)
        np.testing.assert_allclose(mass, ref_mass, rtol=1e-10, atol=1e-10)
        ours = np.linalg.solve(mass, _numbers(eom.forcing, values))
        theirs = np.linalg.solve(ref_mass, _numbers(reference.forcing, values))
        np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-9)
        kinetic = float(eom.kinetic_energy.xreplace(values))
        assert kinetic == pytest.approx(float(reference.kinetic_energy.xreplace(values)), rel=1e-10)


def _pivot(frame_name: str = "N"):
    frame = me.ReferenceFrame(frame_name)
    origin = me.Point("O")
    origin.set_vel(frame, 0)
    return frame, origin


# -- the systems -------------------------------------------------------------------------------


def heavy_symmetric_top():
    """Spinning top on a fixed tip, ZXZ Euler angles (precession, nutation, spin); the centre
    at l along the symmetry axis, A = B about the centre."""
    phi, theta, psi = lg.coordinates("phi theta psi")
    m, g, l, A, C = sp.symbols("m g l A C")
    R = euler_rotation("ZXZ", (phi, theta, psi))
    system = lg.System(
        coordinates=[phi, theta, psi],
        parameters={m: 1.0, g: 9.81, l: 0.5, A: 0.3, C: 0.5},
        rigid_bodies=[
            lg.RigidBody("top", m, sp.diag(A, A, C), tuple(R.matrix[:, 2] * l), orientation=R)
        ],
        gravity=(0, 0, -g),
    )
    q = me.dynamicsymbols("phi theta psi")
    frame, tip = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, q, "ZXZ")
    centre = tip.locatenew("G", l * body.z)
    centre.v2pt_theory(tip, frame, body)
    top = me.RigidBody("top", centre, body, m, (me.inertia(body, A, A, C), centre))
    potential = m * g * centre.pos_from(tip).dot(frame.z)
    return system, lagranges(frame, q, [top], potential)


def test_heavy_symmetric_top_matches_sympy_mechanics() -> None:
    system, reference = heavy_symmetric_top()
    assert_same_motion(system, reference)


def test_heavy_symmetric_top_mass_matrix_is_the_textbook_one() -> None:
    """M = [[A' sin^2 th + C cos^2 th, 0, C cos th], [0, A', 0], [C cos th, 0, C]], A' = A + m l^2
    (Goldstein 5.7), and the forcing has m g l sin(theta) for theta."""
    system, _ = heavy_symmetric_top()
    theta = system.coordinates[1]
    m, g, l, A, C = sp.symbols("m g l A C")
    A1 = A + m * l**2
    textbook = sp.Matrix(
        [
            [A1 * sp.sin(theta) ** 2 + C * sp.cos(theta) ** 2, 0, C * sp.cos(theta)],
            [0, A1, 0],
            [C * sp.cos(theta), 0, C],
        ]
    )
    eom = lg.derive(system)
    assert (eom.mass_matrix - textbook).applyfunc(sp.simplify) == sp.zeros(3, 3)
    at_rest = {v: 0 for v in system.velocities}
    assert sp.simplify(eom.forcing[1].xreplace(at_rest) - m * g * l * sp.sin(theta)) == 0


def free_asymmetric_body():
    """A torque-free body with a full inertia tensor (products of inertia), turning about its
    fixed centre of mass: extrinsic XYZ angles, against KanesMethod."""
    a, b, c = lg.coordinates("a b c")
    I = sp.symbols("Ixx Iyy Izz Ixy Iyz Izx")
    Ixx, Iyy, Izz, Ixy, Iyz, Izx = I
    tensor = sp.Matrix([[Ixx, Ixy, Izx], [Ixy, Iyy, Iyz], [Izx, Iyz, Izz]])
    system = lg.System(
        coordinates=[a, b, c],
        parameters={Ixx: 2.0, Iyy: 3.0, Izz: 4.0, Ixy: 0.1, Iyz: -0.2, Izx: 0.3},
        rigid_bodies=[
            lg.RigidBody(
                "brick",
                1,
                tensor,
                (0, 0, 0),
                orientation=euler_rotation("XYZ", (a, b, c), intrinsic=False),
            )
        ],
    )
    q = me.dynamicsymbols("a b c")
    frame, centre = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_space_fixed(frame, q, "XYZ")
    brick = me.RigidBody("brick", centre, body, 1, (me.inertia(body, *I), centre))
    return system, kanes(frame, q, [brick], [])


def test_free_asymmetric_body_matches_sympy_mechanics() -> None:
    system, reference = free_asymmetric_body()
    assert_same_motion(system, reference)


def _spherical_pendulum(orientation_of: Callable[[tuple], object]):
    """A cylinder hanging from a ball joint at one end (ZYX angles), with a constant torque in
    world axes and gravity; ``orientation_of`` gives lagrangian's orientation of the angles."""
    a, b, c = lg.coordinates("a b c")
    m, g, r, h = sp.symbols("m g r h")
    tau = sp.symbols("tau_x tau_y tau_z")
    R = euler_rotation("ZYX", (a, b, c)).matrix
    system = lg.System(
        coordinates=[a, b, c],
        parameters={m: 1.0, g: 9.81, r: 0.1, h: 1.0, **dict.fromkeys(tau, 0.2)},
        rigid_bodies=[
            lg.RigidBody(
                "rod",
                m,
                cylinder(m, r, h),
                tuple(-R[:, 2] * h / 2),
                orientation=orientation_of((a, b, c)),
            )
        ],
        torques=[lg.Torque("rod", tau)],
        gravity=(0, 0, -g),
    )
    q = me.dynamicsymbols("a b c")
    frame, joint = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, q, "ZYX")
    centre = joint.locatenew("G", -h / 2 * body.z)
    centre.v2pt_theory(joint, frame, body)
    inertia = me.inertia(body, m * (3 * r**2 + h**2) / 12, m * (3 * r**2 + h**2) / 12, m * r**2 / 2)
    rod = me.RigidBody("rod", centre, body, m, (inertia, centre))
    torque = tau[0] * frame.x + tau[1] * frame.y + tau[2] * frame.z
    loads = [(centre, -m * g * frame.z), (body, torque)]
    return system, kanes(frame, q, [rod], loads)


@pytest.mark.parametrize(
    "orientation_of",
    [
        pytest.param(lambda angles: euler_rotation("ZYX", angles), id="Euler angles"),
        pytest.param(
            lambda angles: as_orientation(euler_rotation("ZYX", angles).matrix), id="plain matrix"
        ),
    ],
)
def test_spherical_pendulum_with_a_torque_matches_sympy_mechanics(orientation_of) -> None:
    system, reference = _spherical_pendulum(orientation_of)
    assert_same_motion(system, reference)


def test_a_hinge_about_an_inclined_axis_matches_sympy_mechanics() -> None:
    """A box turning about the fixed axis (1, 1, 1) through a corner, under gravity and a torque
    about world z: axis and angle."""
    theta = lg.coordinates("theta")[0]
    m, g, w, tau = sp.symbols("m g w tau")
    R = axis_angle([1, 1, 1], theta)
    corner_to_centre = sp.Matrix([w, 0, 0]) / 2
    system = lg.System(
        coordinates=[theta],
        parameters={m: 2.0, g: 9.81, w: 0.4, tau: 0.3},
        rigid_bodies=[
            lg.RigidBody(
                "lid",
                m,
                lg.model.inertia.box(m, w, w / 4, w / 8),
                tuple(R.matrix * corner_to_centre),
                orientation=R,
            )
        ],
        torques=[lg.Torque("lid", (0, 0, tau))],
        gravity=(0, 0, -g),
    )
    q = me.dynamicsymbols("theta")
    frame, corner = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_axis(frame, frame.x + frame.y + frame.z, q)
    centre = corner.locatenew("G", w / 2 * body.x)
    centre.v2pt_theory(corner, frame, body)
    inertia = me.inertia(
        body,
        m * ((w / 4) ** 2 + (w / 8) ** 2) / 12,
        m * (w**2 + (w / 8) ** 2) / 12,
        m * (w**2 + (w / 4) ** 2) / 12,
    )
    lid = me.RigidBody("lid", centre, body, m, (inertia, centre))
    potential = m * g * centre.pos_from(corner).dot(frame.z)
    reference = lagranges(frame, [q], [lid], potential, [(body, tau * frame.z)])
    assert_same_motion(system, reference)


def test_a_gyroscope_with_a_prescribed_spin_matches_sympy_mechanics() -> None:
    """Rheonomic orientation: the rotor's spin psi = W t is driven, precession and nutation free
    (explicit time in omega_b: the terms of degree 0 and 1 in the velocities)."""
    phi, theta = lg.coordinates("phi theta")
    m, g, l, A, C, W = sp.symbols("m g l A C W")
    R = euler_rotation("ZXZ", (phi, theta, W * t))
    system = lg.System(
        coordinates=[phi, theta],
        parameters={m: 1.0, g: 9.81, l: 0.3, A: 0.2, C: 0.3, W: 5.0},
        rigid_bodies=[
            lg.RigidBody("rotor", m, sp.diag(A, A, C), tuple(R.matrix[:, 2] * l), orientation=R)
        ],
        gravity=(0, 0, -g),
    )
    q = me.dynamicsymbols("phi theta")
    frame, tip = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, (q[0], q[1], W * TIME), "ZXZ")
    centre = tip.locatenew("G", l * body.z)
    centre.v2pt_theory(tip, frame, body)
    rotor = me.RigidBody("rotor", centre, body, m, (me.inertia(body, A, A, C), centre))
    potential = m * g * centre.pos_from(tip).dot(frame.z)
    reference = lagranges(frame, q, [rotor], potential)
    assert_same_motion(system, reference)
    assert any(e != 0 for e in lg.derive(system).time_terms)


def test_a_body_turned_by_a_unit_quaternion_matches_sympy_mechanics() -> None:
    """q = (cos(a/2), sin(a/2) n(b, c)): angle a about the axis at polar angles (b, c)."""
    a, b, c = lg.coordinates("a b c")
    m, g, l = sp.symbols("m g l")

    def unit(angle, polar, azimuth):
        axis = (sp.sin(polar) * sp.cos(azimuth), sp.sin(polar) * sp.sin(azimuth), sp.cos(polar))
        return (sp.cos(angle / 2), *(sp.sin(angle / 2) * e for e in axis))

    R = quaternion_rotation(*unit(a, b, c))
    system = lg.System(
        coordinates=[a, b, c],
        parameters={m: 1.0, g: 9.81, l: 0.7},
        rigid_bodies=[
            lg.RigidBody(
                "body", m, sp.diag(1, 2, 3) * m / 10, tuple(R.matrix[:, 0] * l), orientation=R
            )
        ],
        gravity=(0, 0, -g),
    )
    q = me.dynamicsymbols("a b c")
    frame, pivot = _pivot()
    body = me.ReferenceFrame("B")
    body.orient_quaternion(frame, unit(*q))
    centre = pivot.locatenew("G", l * body.x)
    centre.v2pt_theory(pivot, frame, body)
    rigid = me.RigidBody(
        "body", centre, body, m, (me.inertia(body, m / 10, 2 * m / 10, 3 * m / 10), centre)
    )
    potential = m * g * centre.pos_from(pivot).dot(frame.z)
    assert_same_motion(system, lagranges(frame, q, [rigid], potential))


def test_a_free_body_with_translation_has_the_block_mass_matrix() -> None:
    """Centre (x, y, z) and ZYZ angles: M = diag(m 1, J^T I J), the blocks uncoupled."""
    x, y, z, a, b, c = lg.coordinates("x y z a b c")
    m = sp.Symbol("m")
    R = euler_rotation("ZYZ", (a, b, c))
    free = lg.System(
        coordinates=[x, y, z, a, b, c],
        parameters={m: 2.0},
        rigid_bodies=[lg.RigidBody("free", m, sp.diag(1, 2, 3), (x, y, z), orientation=R)],
    )
    mass = lg.derive(free).mass_matrix
    assert mass[:3, :3] == sp.eye(3) * m and mass[:3, 3:] == sp.zeros(3, 3)
    omega = lg.model.rotation.body_angular_velocity(R, [a, b, c])
    J = omega.jacobian([velocity(s) for s in (a, b, c)])
    expected = J.T * sp.diag(1, 2, 3) * J
    assert (mass[3:, 3:] - expected).applyfunc(sp.simplify) == sp.zeros(3, 3)


def test_a_planar_body_is_unchanged_by_the_3d_path() -> None:
    """A planar pendulum as a planar body and as a 3-D body turning about z: same equations."""
    theta = lg.coordinates("theta")[0]
    m, g, l, I = sp.symbols("m g l I")
    parameters = {m: 1.0, g: 9.81, l: 1.0, I: 0.1}
    planar = lg.System(
        coordinates=[theta],
        parameters=parameters,
        rigid_bodies=[lg.RigidBody("rod", m, I, (l * sp.sin(theta), -l * sp.cos(theta)), theta)],
        gravity=(0, -g),
    )
    spatial = lg.System(
        coordinates=[theta],
        parameters=parameters,
        rigid_bodies=[
            lg.RigidBody(
                "rod",
                m,
                sp.diag(I, I, I),
                (l * sp.sin(theta), -l * sp.cos(theta), 0),
                orientation=axis_angle([0, 0, 1], theta),
            )
        ],
        gravity=(0, -g, 0),
    )
    first, second = lg.derive(planar), lg.derive(spatial)
    assert first.mass_matrix == second.mass_matrix
    assert sp.simplify(first.forcing[0] - second.forcing[0]) == 0


def test_a_kinetic_energy_that_is_not_quadratic_takes_the_general_path() -> None:
    """T with a quartic term plus a 3-D body: the body's 1/2 w^T I w is still in T."""
    a = lg.coordinates("a")[0]
    system = lg.System(
        coordinates=[a],
        kinetic=velocity(a) ** 4 / 12,
        rigid_bodies=[
            lg.RigidBody(
                "wheel", 1, sp.diag(1, 1, 2), (0, 0, 0), orientation=axis_angle([0, 0, 1], a)
            )
        ],
    )
    eom = lg.derive(system)
    assert sp.expand(eom.kinetic_energy - velocity(a) ** 4 / 12 - velocity(a) ** 2) == 0
    assert sp.expand(eom.mass_matrix[0, 0] - velocity(a) ** 2 - 2) == 0
