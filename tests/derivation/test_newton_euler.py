"""Newton–Euler equations of the bodies of a System, and their agreement with the Euler–Lagrange
equations (seed 003, "4 Newton-Euler equation" and the written assignment).

References: the seed's dumbbell (its Euler–Lagrange equations as written, its generalized inertia
M^s, its wrenches (f, f^T J q) and its claim that the two forms agree), Euler's equations
I omega_dot + omega x I omega = tau and Newton's m (v_dot + omega x v) = f written here from the
angular velocity alone, and the identity V^s = Ad V^b (the spatial residual is Ad^-T times the
body residual)."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.derivation import check_newton_euler
from lagrangian.derivation.body_frames import point_wrench
from lagrangian.derivation.newton_euler import compare_residuals
from lagrangian.derivation.trig import combine_trig_sympy
from lagrangian.errors import DerivationError
from lagrangian.model.inertia import cylinder
from lagrangian.model.rotation import body_angular_velocity, euler_rotation, evaluate_matrix
from lagrangian.symbolic.symbols import time_derivative

x1, y1, theta = lg.coordinates("x1 y1 theta")
m1, m2, h, g = sp.symbols("m1 m2 h g")
f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")


def zero(expr: sp.Expr) -> bool:
    """expr is 0: the numerator over one denominator collects to 0 (Fourier form)."""
    return combine_trig_sympy(sp.fraction(sp.together(expr))[0]) == 0


def zeros(matrix: sp.MatrixBase) -> bool:
    return all(zero(e) for e in matrix)


# -- the seed's dumbbell: the written assignment ----------------------------------------------


def seed_equations() -> sp.Matrix:
    """Seed 003 (line ~595), the Euler–Lagrange equations of the dumbbell as residuals."""
    xdd, ydd, thd, thdd = sp.symbols("x1_ddot y1_ddot theta_dot theta_ddot")
    s, c = sp.sin(theta), sp.cos(theta)
    return sp.Matrix(
        [
            m1 * xdd + m2 * (xdd - h * c * thd**2 - h * s * thdd) - (f1x + f2x),
            m1 * ydd + m2 * (ydd - h * s * thd**2 + h * c * thdd) - (f1y + f2y - (m1 + m2) * g),
            m2 * (-xdd * h * s + ydd * h * c + h**2 * thdd)
            - (-f2x * h * s + f2y * h * c - m2 * g * h * c),
        ]
    )


def rigid_dumbbell() -> lg.System:
    """The dumbbell as the seed's Newton–Euler side sees it: one planar body of mass m1 + m2,
    centre c = (m1 q1 + m2 q2)/m, inertia m1 m2 h^2/m about c, angle theta, pushed by f1 at q1
    and f2 at q2 (points given by position: they move with the body)."""
    m = m1 + m2
    q1 = (x1, y1)
    q2 = (x1 + h * sp.cos(theta), y1 + h * sp.sin(theta))
    centre = tuple((m1 * a + m2 * b) / m for a, b in zip(q1, q2))
    return lg.System(
        coordinates=[x1, y1, theta],
        parameters=[m1, m2, h, g, f1x, f1y, f2x, f2y],
        rigid_bodies=[lg.RigidBody("dumbbell", m, m1 * m2 * h**2 / m, centre, theta)],
        forces=[lg.Force(q1, (f1x, f1y)), lg.Force(q2, (f2x, f2y))],
        gravity=(0, -g),
    )


def test_the_dumbbell_file_has_the_seeds_euler_lagrange_equations() -> None:
    eom = lg.derive(lg.examples.dumbbell())
    assert zeros(eom.equations - seed_equations())


def test_the_seeds_newton_euler_equation_of_the_dumbbell_is_its_euler_lagrange_equation() -> None:
    """The written assignment: d/dt (M^s V^s) = F_1 + F_2 + F_1g + F_2g, projected on x1, y1,
    theta with J^s = dV^s/dq_dot, is the three Euler–Lagrange equations above.

    Where the seed's own algebra slips we trusted the physics: its Mdot^s has m 1 in the top
    left block (d/dt (m 1) = 0, as it cancels elsewhere), its assignment writes
    (v_dot^s, theta_dot) for V_dot^s (the second entry is theta_ddot) and "Mdot^s V^s + M^s V^s"
    without the dot on the second V, and one moment of a force is written with
    J = [[0, 1], [1, 0]] (the quarter turn is [[0, -1], [1, 0]], so f^T J q = q x f)."""
    body = lg.newton_euler(rigid_dumbbell()).body("dumbbell")
    projected = body.frame.spatial_jacobian.T * body.spatial_residual
    assert zeros(projected - seed_equations())
    again = body.frame.jacobian.T * body.residual  # the body frame says the same
    assert zeros(again - seed_equations())


def test_the_dumbbells_generalized_inertia_and_wrenches_are_the_seeds() -> None:
    """M^s = [[m 1, m J c], [(m J c)^T, m1 q1.q1 + m2 q2.q2]] and F^s = sum (f, f^T J q) over
    the two forces and the two weights (seed 003, "Newton-Euler equation - Simple example")."""
    body = lg.newton_euler(rigid_dumbbell()).body("dumbbell")
    m, J = m1 + m2, sp.Matrix([[0, -1], [1, 0]])
    q1 = sp.Matrix([x1, y1])
    q2 = q1 + h * sp.Matrix([sp.cos(theta), sp.sin(theta)])
    c = (m1 * q1 + m2 * q2) / m
    seed_inertia = (m * sp.eye(2)).row_join(m * J * c)
    seed_inertia = seed_inertia.col_join((m * J * c).T.row_join(m1 * q1.T * q1 + m2 * q2.T * q2))
    assert zeros(body.frame.spatial_inertia - seed_inertia)

    def wrench(f: sp.Matrix, q: sp.Matrix) -> sp.Matrix:
        return f.col_join(f.T * J * q)

    forces = [(sp.Matrix([f1x, f1y]), q1), (sp.Matrix([f2x, f2y]), q2)]
    forces += [(sp.Matrix([0, -m1 * g]), q1), (sp.Matrix([0, -m2 * g]), q2)]
    seed_wrench = sum((wrench(f, q) for f, q in forces), sp.zeros(3, 1))
    assert zeros(body.spatial_wrench - seed_wrench)


def test_the_seeds_exercise_mdot_v_is_minus_ad_transpose_m_v() -> None:
    """Seed 003's exercise: Mdot^s V^s = -ad_{V^s}^T M^s V^s, ad = [[J theta_dot, -J v], [0, 0]]."""
    frame = lg.newton_euler(rigid_dumbbell()).body("dumbbell").frame
    q = (x1, y1, theta)
    M, V = frame.spatial_inertia, sp.Matrix(frame.spatial_twist)
    M_dot = M.applyfunc(lambda e: time_derivative(e, q))
    J = sp.Matrix([[0, -1], [1, 0]])
    ad = (J * V[2]).row_join(-J * V[:2, 0]).col_join(sp.zeros(1, 3))
    assert zeros(M_dot * V + ad.T * M * V)


# -- agreement on more systems -----------------------------------------------------------------


def double_compound_pendulum() -> lg.System:
    """Two uniform rods of length l hinged in a chain, a force at the free end of the second
    and a motor torque on the first."""
    a, b = lg.coordinates("a b")
    m, l, F, tau = sp.symbols("m l F tau")
    s1, c1, s2, c2 = sp.sin(a), sp.cos(a), sp.sin(b), sp.cos(b)
    inertia = m * l**2 / 12
    return lg.System(
        coordinates=[a, b],
        parameters=[m, l, g, F, tau],
        rigid_bodies=[
            lg.RigidBody("upper", m, inertia, (l * s1 / 2, -l * c1 / 2), a),
            lg.RigidBody("lower", m, inertia, (l * s1 + l * s2 / 2, -l * c1 - l * c2 / 2), b),
        ],
        forces=[lg.Force((l * s1 + l * s2, -l * c1 - l * c2), (F, 0))],
        torques=[lg.Torque("upper", tau)],
        gravity=(0, -g),
    )


def rod_with_loads() -> lg.System:
    """A cylinder on a ball joint (ZYX angles) with a force at its free end, a torque, and a
    spring and a damper from the free end to fixed anchors (points given by position)."""
    a, b, c = lg.coordinates("a b c")
    m, r, L, k, d = sp.symbols("m r L k d")
    F, tau = sp.symbols("F_x F_y F_z"), sp.symbols("tau_x tau_y tau_z")
    R = euler_rotation("ZYX", (a, b, c))
    end = tuple(-R.matrix[:, 2] * L)
    return lg.System(
        coordinates=[a, b, c],
        parameters=[m, r, L, g, k, d, *F, *tau],
        rigid_bodies=[
            lg.RigidBody("rod", m, cylinder(m, r, L), tuple(-R.matrix[:, 2] * L / 2), orientation=R)
        ],
        forces=[lg.Force(end, F)],
        torques=[lg.Torque("rod", tau)],
        springs=[lg.Spring((end, (L, 0, -L)), k, L / 2)],
        dampers=[lg.Damper((end, (0, L, 0)), d)],
        gravity=(0, 0, -g),
    )


@pytest.mark.parametrize(
    ("build", "frames"),
    [
        pytest.param(lambda: lg.examples.dumbbell(), ("body", "spatial"), id="dumbbell"),
        pytest.param(double_compound_pendulum, ("body", "spatial"), id="double compound"),
        pytest.param(lambda: lg.examples.heavy_symmetric_top(), ("body", "spatial"), id="top"),
        pytest.param(lambda: lg.examples.asymmetric_body(), ("body",), id="asymmetric body"),
        pytest.param(rod_with_loads, ("body",), id="force at a point and a torque"),
        pytest.param(lambda: lg.examples.two_masses_three_springs(), ("body",), id="springs"),
    ],
)
def test_newton_euler_projected_is_euler_lagrange(build, frames) -> None:
    system = build()
    for frame in frames:
        check = check_newton_euler(system, frame=frame)
        assert check.agree, check.summary()
        assert check.frame == frame and len(check.agrees) == len(system.coordinates)


def test_every_row_of_the_top_agrees_symbolically() -> None:
    check = check_newton_euler(lg.examples.heavy_symmetric_top())
    assert check.methods == ("symbolic",) * 3 and check.difference == sp.zeros(3, 1)
    assert "phi: Euler–Lagrange and Newton–Euler (body frame) agree (symbolic)" in check.summary()


def test_a_projection_that_leaves_out_a_force_is_caught_row_by_row() -> None:
    """The check can fail: without the weight of the lower rod only the rows it moves differ,
    and the difference is that weight's generalized force."""
    system = double_compound_pendulum()
    equations = lg.newton_euler(system)
    lower = equations.body("lower")
    m, l = sp.symbols("m l")
    b = system.coordinates[1]
    weight_at_centre = point_wrench("planar", lower.frame.position, (0, -m * g))
    weight = lower.frame.adjoint.T * weight_at_centre
    wrong = equations.projected() + lower.frame.jacobian.T * weight  # weight counted as not applied
    check = compare_residuals(system, lg.derive(system).equations, wrong)
    assert check.agrees == (False, False) and not check.agree
    assert zero(check.difference[1] - m * g * l * sp.sin(b) / 2)
    assert "b: Euler–Lagrange and Newton–Euler (body frame) differ by" in check.summary()


def test_a_difference_left_uncollected_is_compared_at_random_points() -> None:
    """cos^2 a - 1/(1 + tan^2 a) is zero, but collecting sines and cosines does not see through
    tan: the numeric comparison decides, says so, and still catches a small real difference."""
    a = lg.coordinates("a")[0]
    system = lg.System(coordinates=[a])
    same = compare_residuals(system, [sp.cos(a) ** 2], [1 / (1 + sp.tan(a) ** 2)])
    assert same.agree and same.methods == ("numeric",)
    off = compare_residuals(system, [sp.cos(a) ** 2], [1 / (1 + sp.tan(a) ** 2) + 1e-3 * a])
    assert off.agrees == (False,) and off.methods == ("numeric",)


# -- each body's equation in textbook form ----------------------------------------------------


def test_a_3d_body_obeys_newton_and_euler_in_its_own_frame() -> None:
    """Body frame at the centre: residual = (m (v_dot + omega x v) - f, I omega_dot +
    omega x I omega - tau), written here from omega_b = vee(R^T R_dot) and v_b = R^T p_dot."""
    system = lg.examples.heavy_symmetric_top()
    q = system.coordinates
    body = lg.newton_euler(system).body("top")
    top = system.rigid_bodies[0]
    R, I, m = top.orientation.matrix, top.inertia_tensor, top.mass
    omega = sp.Matrix(body_angular_velocity(top.orientation, q))
    p_dot = sp.Matrix([time_derivative(e, q) for e in top.position])
    v = (R.T * p_dot).applyfunc(combine_trig_sympy)
    rate = omega.applyfunc(lambda e: time_derivative(e, q))
    weight = R.T * sp.Matrix([0, 0, -m * sp.Symbol("g")])
    newton = m * (v.applyfunc(lambda e: time_derivative(e, q)) + omega.cross(v)) - weight
    euler = I * rate + omega.cross(I * omega)
    assert zeros(body.residual - newton.col_join(euler))


def test_particles_and_planar_bodies_have_the_plain_forms() -> None:
    system = double_compound_pendulum()
    upper = lg.newton_euler(system).body("upper")
    a = system.coordinates[0]
    m, l, tau = sp.symbols("m l tau")
    a_dot, a_ddot = lg.velocity(a), lg.acceleration(a)
    # rotation about the centre: I a_ddot = tau + moment of the weight (none about the centre)
    assert zero(upper.residual[2] - (m * l**2 / 12 * a_ddot - tau))
    assert upper.frame.twist[2] == a_dot and upper.frame.kind == "planar"
    particle = lg.newton_euler(lg.examples.dumbbell()).body("particle1")
    assert particle.frame.kind == "particle"
    x_ddot = lg.acceleration(x1)
    assert zero(particle.residual[0] - (m1 * x_ddot - f1x))


def test_the_spatial_residual_is_the_body_residual_moved_by_the_adjoint() -> None:
    """F^s = Ad^-T F^b for wrenches, so residual^s = Ad^-T residual^b (checked at random states)."""
    system = lg.examples.physical_pendulum_3d()
    body = lg.newton_euler(system).body("box")
    rng = random.Random(3)
    for _ in range(3):
        point = {s: rng.uniform(0.5, 1.5) for s in system.parameters}
        point.update({s: rng.uniform(-1, 1) for s in system.coordinates})
        point.update({s: rng.uniform(-2, 2) for s in (*system.velocities, *system.accelerations)})
        Ad = evaluate_matrix(body.frame.adjoint, point)
        body_residual = evaluate_matrix(body.residual, point)
        spatial_residual = evaluate_matrix(body.spatial_residual, point)
        np.testing.assert_allclose(Ad.T @ spatial_residual, body_residual, atol=1e-9)


# -- what cannot be split among bodies ---------------------------------------------------------


def test_energies_given_as_expressions_are_refused() -> None:
    with pytest.raises(DerivationError, match=r"kinetic: T is given as an expression"):
        lg.newton_euler(lg.examples.mass_on_spring())
    with pytest.raises(DerivationError, match=r"circuit: circuit elements are not bodies"):
        lg.newton_euler(lg.examples.series_rlc())


def test_a_force_at_a_point_of_no_body_is_refused() -> None:
    system = lg.examples.dumbbell()
    loose = system.replace(forces=[lg.Force((x1 + h * sp.cos(2 * theta), y1), (f1x, 0))])
    with pytest.raises(DerivationError, match=r"forces\[0\]\.at: the point .* is fixed in no body"):
        lg.newton_euler(loose)


def test_a_potential_and_generalized_forces_on_the_coordinates_are_kept_apart() -> None:
    """V and Q given on the coordinates join the projection as Q_rest = Q - dV/dq."""
    phi = lg.coordinates("phi")[0]
    m, l, k, Q = sp.symbols("m l k Q")
    system = lg.System(
        coordinates=[phi],
        parameters=[m, l, k, Q],
        particles=[lg.Particle("bob", m, (l * sp.cos(phi), l * sp.sin(phi)))],
        potential=k * phi**2 / 2,
        generalized_forces={phi: Q},
    )
    assert lg.newton_euler(system).generalized_forces == sp.Matrix([Q - k * phi])
    assert check_newton_euler(system).agree


def test_an_unknown_body_name_lists_the_bodies() -> None:
    with pytest.raises(KeyError, match=r"No body named 'bob'; the bodies are particle1, particle2"):
        lg.newton_euler(lg.examples.dumbbell()).body("bob")
