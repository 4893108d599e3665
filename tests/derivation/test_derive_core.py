"""The derivation itself: residual and matrix forms agree, singular mass matrices,
explicit time, non-quadratic T, velocity potentials, elements, Nielsen form.

References are written by hand from the physics (textbook results), never produced by the code.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import DerivationError

t = lg.t
x, y, r, theta, q1, q2 = sp.symbols("x y r theta q1 q2")
x_dot, y_dot, r_dot, theta_dot, q1_dot, q2_dot = sp.symbols(
    "x_dot y_dot r_dot theta_dot q1_dot q2_dot"
)
x_ddot, y_ddot, r_ddot, theta_ddot, q1_ddot, q2_ddot = sp.symbols(
    "x_ddot y_ddot r_ddot theta_ddot q1_ddot q2_ddot"
)
m, k, c, g, l, big_r, big_c, big_l, u, w, x0, l0 = sp.symbols("m k c g l R C L u w x0 l0")


def _zero(expr: sp.Expr) -> bool:
    return sp.simplify(expr) == 0


def _matrix_form_holds(eom: lg.EquationsOfMotion) -> bool:
    q_ddot = sp.Matrix(eom.accelerations)
    return all(_zero(e) for e in eom.equations - (eom.mass_matrix * q_ddot - eom.forcing))


def test_mass_spring_damper_with_force() -> None:
    system = lg.System(
        coordinates=[x],
        parameters=[m, k, c, u, w],
        kinetic=m * x_dot**2 / 2,
        potential=k * x**2 / 2,
        dissipation=c * x_dot**2 / 2,
        generalized_forces={x: u * sp.cos(w * t)},
        name="msd",
    )
    eom = lg.derive(system)
    assert eom.equations[0] == m * x_ddot + c * x_dot + k * x - u * sp.cos(w * t)
    assert eom.mass_matrix == sp.Matrix([[m]])
    assert eom.gravity == sp.Matrix([k * x])
    assert eom.dissipation_forces == sp.Matrix([-c * x_dot])
    assert eom.forcing == sp.Matrix([u * sp.cos(w * t) - c * x_dot - k * x])
    assert eom.explicit_accelerations[0] == sp.expand((u * sp.cos(w * t) - c * x_dot - k * x) / m)
    step = eom.steps[0]
    assert (step.dL_dvelocity, step.ddt_dL_dvelocity, step.dL_dcoordinate) == (
        m * x_dot,
        m * x_ddot,
        -k * x,
    )
    assert step.dF_dvelocity == c * x_dot and step.generalized_force == u * sp.cos(w * t)


def test_eom_is_an_immutable_value() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign"):
        eom.mass_matrix = sp.ImmutableMatrix([[1]])  # type: ignore[misc]
    assert "simple_pendulum" in repr(eom)


def test_polar_particle_with_applied_force_by_virtual_work() -> None:
    fr, ft = sp.symbols("F_r F_theta")
    direction_r = (sp.cos(theta), sp.sin(theta))
    direction_t = (-sp.sin(theta), sp.cos(theta))
    force = tuple(fr * a + ft * b for a, b in zip(direction_r, direction_t))
    system = lg.System(
        coordinates=[r, theta],
        parameters=[m, fr, ft],
        particles=[lg.Particle("p", m, (r * sp.cos(theta), r * sp.sin(theta)))],
        forces=[lg.Force("p", force)],
    )
    eom = lg.derive(system)
    # Q_r = F_r, Q_theta = r F_theta (seed 000, polar coordinates)
    assert eom.generalized_forces.applyfunc(sp.simplify) == sp.Matrix([fr, r * ft])
    assert eom.mass_matrix == sp.Matrix([[m, 0], [0, m * r**2]])
    assert _zero(eom.equations[0] - (m * r_ddot - m * r * theta_dot**2 - fr))
    assert _zero(
        eom.equations[1] - (m * r**2 * theta_ddot + 2 * m * r * r_dot * theta_dot - r * ft)
    )
    assert eom.coriolis.applyfunc(sp.expand) == sp.Matrix(
        [-m * r * theta_dot**2, 2 * m * r * r_dot * theta_dot]
    )


def test_singular_mass_matrix_gives_a_first_order_coordinate() -> None:
    # RC + RL circuit of seed 001: q1 carries no inductance.
    ua, rl = sp.symbols("u_a R_L")
    system = lg.System(
        coordinates=[q1, q2],
        parameters=[big_l, big_c, big_r, rl, ua],
        circuit=[
            lg.Inductor(big_l, q2_dot),
            lg.Capacitor(big_c, q1 - q2),
            lg.Resistor(big_r, q1_dot),
            lg.Resistor(rl, q2_dot),
            lg.VoltageSource(ua, q1),
        ],
    )
    eom = lg.derive(system)
    assert eom.orders_by_name() == {"q1": 1, "q2": 2}
    assert not eom.mass_matrix_is_regular
    assert _zero(eom.explicit[q1_dot] - (ua - (q1 - q2) / big_c) / big_r)
    assert _zero(eom.explicit[q2_ddot] - (-rl * q2_dot + (q1 - q2) / big_c) / big_l)
    with pytest.raises(DerivationError, match="mass matrix is singular"):
        _ = eom.explicit_accelerations
    assert _matrix_form_holds(eom)


def test_algebraic_coordinate() -> None:
    system = lg.System(
        coordinates=[x, y],
        parameters=[m, k],
        kinetic=m * x_dot**2 / 2,
        potential=k * (x - y) ** 2 / 2 + k * y**2,
    )
    eom = lg.derive(system)
    assert eom.orders_by_name() == {"x": 2, "y": 0}
    assert eom.algebraic_equations == (sp.expand(-(k * (y - x) + 2 * k * y)),)


def test_rheonomic_pendulum_keeps_the_time_terms_apart() -> None:
    pivot = x0 * sp.cos(w * t)
    system = lg.System(
        coordinates=[theta],
        parameters=[m, g, l, x0, w],
        particles=[lg.Particle("bob", m, (pivot + l * sp.sin(theta), -l * sp.cos(theta)))],
        gravity=(0, -g),
    )
    eom = lg.derive(system)
    # m l^2 theta'' + m g l sin(theta) - m l x0 w^2 cos(w t) cos(theta) = 0
    expected = (
        m * l**2 * theta_ddot
        + m * g * l * sp.sin(theta)
        - m * l * x0 * w**2 * sp.cos(w * t) * sp.cos(theta)
    )
    assert _zero(eom.equations[0] - expected)
    assert _zero(eom.time_terms[0] + m * l * x0 * w**2 * sp.cos(w * t) * sp.cos(theta))
    assert eom.coriolis == sp.Matrix([0])
    assert _matrix_form_holds(eom)


def test_kinetic_energy_not_quadratic_in_the_velocities() -> None:
    # Seed 000: L = m^2 x_dot^4/12 + m x_dot^2 V - V^2 with V = k x^2/2.
    v = k * x**2 / 2
    system = lg.System(
        coordinates=[x],
        parameters=[m, k],
        lagrangian=m**2 * x_dot**4 / 12 + m * x_dot**2 * v - v**2,
    )
    eom = lg.derive(system)
    # (m x'' + V')(m x'^2 + 2V) = 0, by hand: d/dt(m^2 x'^3/3 + 2 m x' V) - (m x'^2 V' - 2 V V')
    expected = (m * x_ddot + k * x) * (m * x_dot**2 + 2 * v)
    assert _zero(eom.equations[0] - expected)
    assert eom.mass_matrix[0, 0].has(x_dot)
    assert _matrix_form_holds(eom)


def test_velocity_potential_quadratic_in_the_velocity_enters_the_mass_matrix() -> None:
    # Weber's potential (seed 000, problem 16): U = (1 + r_dot^2/c^2)/r
    system = lg.System(
        coordinates=[r],
        parameters=[m, c],
        kinetic=m * r_dot**2 / 2,
        velocity_potential=(1 + r_dot**2 / c**2) / r,
    )
    eom = lg.derive(system)
    assert _zero(eom.mass_matrix[0, 0] - (m - 2 / (r * c**2)))
    expected = (m - 2 / (r * c**2)) * r_ddot + r_dot**2 / (r**2 * c**2) - 1 / r**2
    assert _zero(eom.equations[0] - expected)
    assert _matrix_form_holds(eom)


def test_spring_with_rest_length_and_damper_along_the_line() -> None:
    system = lg.System(
        coordinates=[x, y],
        parameters=[m, k, l0, c],
        particles=[lg.Particle("p", m, (x, y))],
        springs=[lg.Spring(("origin", "p"), k, l0)],
        dampers=[lg.Damper(("origin", "p"), c)],
    )
    eom = lg.derive(system)
    rho = sp.sqrt(x**2 + y**2)
    radial_speed = (x * x_dot + y * y_dot) / rho
    expected_fx = -k * (rho - l0) * x / rho - c * radial_speed * x / rho
    assert _zero(eom.forcing[0] - expected_fx)
    assert _zero(sp.diff(eom.dissipation_function, x_dot) - c * radial_speed * x / rho)


def test_one_dimensional_spring_is_signed_and_keeps_order() -> None:
    system = lg.System(
        coordinates=[q1, q2],
        parameters=[m, k, l0],
        particles=[lg.Particle("a", m, (q1,)), lg.Particle("b", m, (q2,))],
        springs=[lg.Spring(("a", "b"), k, l0)],
    )
    eom = lg.derive(system)
    assert eom.potential_energy == sp.expand(k * (q2 - q1 - l0) ** 2 / 2) or _zero(
        eom.potential_energy - k * (q2 - q1 - l0) ** 2 / 2
    )


def test_planar_body_and_torque() -> None:
    inertia, tau = sp.symbols("I tau")
    system = lg.System(
        coordinates=[theta],
        parameters=[m, g, l, inertia, tau],
        rigid_bodies=[
            lg.RigidBody("rod", m, inertia, (l * sp.sin(theta), -l * sp.cos(theta)), theta)
        ],
        torques=[lg.Torque("rod", tau)],
        gravity=(0, -g),
    )
    eom = lg.derive(system)
    expected = (inertia + m * l**2) * theta_ddot + m * g * l * sp.sin(theta) - tau
    assert _zero(eom.equations[0] - expected)


def test_dynamicsymbols_input_gives_the_same_equations() -> None:
    from sympy.physics.mechanics import dynamicsymbols

    th = dynamicsymbols("theta")
    tt = dynamicsymbols._t
    system = lg.System(
        coordinates=[th],
        parameters=[m, g, l],
        kinetic=m * l**2 * th.diff(tt) ** 2 / 2,
        potential=-m * g * l * sp.cos(th),
    )
    eom = lg.derive(system)
    assert eom.equations[0] == lg.derive(lg.examples.simple_pendulum()).equations[0]


@pytest.mark.parametrize("n", [1, 2, 3])
def test_nielsen_form_agrees(n: int) -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(n))
    assert all(_zero(e) for e in lg.nielsen_equations(eom) - eom.equations)


def test_nielsen_form_agrees_with_dissipation_time_and_velocity_potential() -> None:
    qe, b0 = sp.symbols("q_e B_0")
    z, z_dot = sp.symbols("z z_dot")
    a_dot_v = b0 / 2 * (-y * x_dot + x * y_dot)
    system = lg.System(
        coordinates=[x, y, z],
        parameters=[m, qe, b0, c, w],
        particles=[lg.Particle("p", m, (x, y, z))],
        velocity_potential=-qe * a_dot_v,
        dissipation=c * z_dot**2 / 2,
        generalized_forces={z: sp.sin(w * t)},
    )
    eom = lg.derive(system)
    assert all(_zero(e) for e in lg.nielsen_equations(eom) - eom.equations)
    # Lorentz force: m x'' = q_e B0 y', m y'' = -q_e B0 x'
    assert _zero(eom.forcing[0] - qe * b0 * y_dot)
    assert _zero(eom.forcing[1] + qe * b0 * x_dot)


def test_coriolis_matrix_is_christoffel_and_skew_property_holds() -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(3))
    q_dot = sp.Matrix(eom.velocities)
    assert all(_zero(e) for e in eom.coriolis_matrix * q_dot - eom.coriolis)
    m_dot = sum(
        (eom.mass_matrix.diff(q) * v for q, v in zip(eom.coordinates, eom.velocities)),
        sp.zeros(3, 3),
    )
    skew = m_dot - 2 * eom.coriolis_matrix
    assert all(_zero(e) for e in skew + skew.T)
