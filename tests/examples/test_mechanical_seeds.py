"""Every mechanical worked example of the seed notes, against the notes' own equations.

Each reference below is copied by hand from the notes (seed 000 unless said otherwise) into
residual form "expression = 0", written with plain symbols.  Where the notes divide an
equation through by a factor, the factor is stated; where the notes have a typo, the test
trusts the physics and says so.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest
import sympy as sp

import lagrangian as lg

t = lg.t
m, g, k, F, f, h = sp.symbols("m g k F f h")
m1, m2, l1, l2, ell, big_r, big_i = sp.symbols("m1 m2 l1 l2 l R I")
x, y, z, r, theta, phi = sp.symbols("x y z r theta phi")
x_dot, y_dot, z_dot, r_dot, theta_dot, phi_dot = sp.symbols(
    "x_dot y_dot z_dot r_dot theta_dot phi_dot"
)
x_ddot, y_ddot, z_ddot, r_ddot, theta_ddot, phi_ddot = sp.symbols(
    "x_ddot y_ddot z_ddot r_ddot theta_ddot phi_ddot"
)
x1, y1, x2 = sp.symbols("x1 y1 x2")
x1_dot, y1_dot, x2_dot = sp.symbols("x1_dot y1_dot x2_dot")
x1_ddot, y1_ddot, x2_ddot = sp.symbols("x1_ddot y1_ddot x2_ddot")

#: The examples this file covers (one function per worked example of the notes).
MECHANICAL = [
    lg.examples.get(name)
    for name in (
        "simple_pendulum",
        "compound_pendulum",
        "spherical_pendulum",
        "double_pendulum",
        "moving_pivot_pendulum",
        "particle_plane_cartesian",
        "particle_plane_polar",
        "mass_on_spring",
        "mass_spring_damper",
        "projectile_polar",
        "planet",
        "two_masses_three_springs",
        "quartic_lagrangian",
        "stokes_drag",
        "charged_particle_em",
        "dumbbell",
        "atwood_machine",
        "atwood_machine_with_pulley",
    )
]


def _same(ours: sp.Expr, expected: sp.Expr) -> bool:
    return sp.simplify(ours - expected) == 0


def _equations(system: lg.System) -> list[sp.Expr]:
    return list(lg.derive(system).equations)


def _ddt(expr: sp.Expr, pairs: list[tuple[sp.Symbol, sp.Symbol, sp.Symbol]]) -> sp.Expr:
    """d/dt by the chain rule over (q, q_dot, q_ddot) triples, written independently here."""
    return sum((expr.diff(q) * qd + expr.diff(qd) * qdd for q, qd, qdd in pairs), sp.Integer(0))


# -- conventions every example follows ----------------------------------------------------


@pytest.mark.parametrize("build", MECHANICAL, ids=lambda fn: fn.__name__)
def test_example_conventions(build: Callable[[], lg.System]) -> None:
    system = build()
    doc_line = build.__doc__.strip().splitlines()[0]
    assert system.name == build.__name__
    assert system.description == doc_line
    assert all(value is not None for value in system.parameters.values())
    state = {*system.coordinates, *system.velocities}
    assert set(system.initial) == state


# -- pendulums ------------------------------------------------------------------------------


def test_simple_pendulum() -> None:
    (eq,) = _equations(lg.examples.simple_pendulum())
    assert _same(eq, m * ell**2 * theta_ddot + m * g * ell * sp.sin(theta))


def test_compound_pendulum_inertia_about_the_pivot() -> None:
    # Notes: I theta_ddot + m g l sin(theta) = 0 with I about the pivot, I = I_c + m l^2.
    i_c = sp.Symbol("I_c")
    eom = lg.derive(lg.examples.compound_pendulum())
    pivot_inertia = i_c + m * ell**2
    assert _same(eom.equations[0], pivot_inertia * theta_ddot + m * g * ell * sp.sin(theta))
    assert _same(eom.kinetic_energy, pivot_inertia * theta_dot**2 / 2)
    assert _same(eom.potential_energy, -m * g * ell * sp.cos(theta))


def test_spherical_pendulum() -> None:
    eom = lg.derive(lg.examples.spherical_pendulum())
    eq_theta, eq_phi = eom.equations
    # Notes: m r^2 (theta_ddot - sin cos phi_dot^2 + g/r sin) = 0 (their r is our ell).
    notes_theta = (
        m
        * ell**2
        * (theta_ddot - sp.sin(theta) * sp.cos(theta) * phi_dot**2 + g / ell * sp.sin(theta))
    )
    assert _same(eq_theta, notes_theta)
    # Notes: d/dt (m r^2 sin^2 phi_dot) = 0, i.e. phi_ddot = -2 cot(theta) theta_dot phi_dot,
    # which is our residual divided by m l^2 sin^2(theta).
    notes_phi = phi_ddot + 2 * sp.cot(theta) * theta_dot * phi_dot
    assert _same(eq_phi, m * ell**2 * sp.sin(theta) ** 2 * notes_phi)
    assert _same(eom.steps[1].dL_dvelocity, m * ell**2 * sp.sin(theta) ** 2 * phi_dot)
    assert eom.steps[1].dL_dcoordinate == 0  # phi is cyclic
    notes_l = m * ell**2 * (
        theta_dot**2 + sp.sin(theta) ** 2 * phi_dot**2
    ) / 2 + m * g * ell * sp.cos(theta)
    assert _same(eom.lagrangian, notes_l)


def _double_pendulum_notes() -> dict[str, sp.Expr]:
    c, s = sp.cos(theta - phi), sp.sin(theta - phi)
    return {
        "T": (m1 + m2) * l1**2 * theta_dot**2 / 2
        + m2 * l2**2 * phi_dot**2 / 2
        + m2 * l1 * l2 * theta_dot * phi_dot * c,
        "dL/dtheta_dot": (m1 + m2) * l1**2 * theta_dot + m2 * l1 * l2 * phi_dot * c,
        "d/dt dL/dtheta_dot": (m1 + m2) * l1**2 * theta_ddot
        + m2 * l1 * l2 * phi_ddot * c
        - m2 * l1 * l2 * phi_dot * (theta_dot - phi_dot) * s,
        "dL/dtheta": -m2 * l1 * l2 * theta_dot * phi_dot * s - (m1 + m2) * g * l1 * sp.sin(theta),
        "dL/dphi_dot": m2 * l2**2 * phi_dot + m2 * l1 * l2 * theta_dot * c,
        "d/dt dL/dphi_dot": m2 * l2**2 * phi_ddot
        + m2 * l1 * l2 * theta_ddot * c
        - m2 * l1 * l2 * theta_dot * (theta_dot - phi_dot) * s,
        # The notes label this dL/dtheta and end it with sin(theta): both typos for phi.
        "dL/dphi": m2 * l1 * l2 * theta_dot * phi_dot * s - m2 * g * l2 * sp.sin(phi),
        # Divided through by l1.  The notes print "- m2 l2 phi_dot^2 sin(theta - phi)" and
        # "(m1 + m2) g sin(theta - phi)": the physics (and their own dL/dtheta above) gives
        # "+" and sin(theta).
        "theta equation / l1": (m1 + m2) * l1 * theta_ddot
        + m2 * l2 * phi_ddot * c
        + m2 * l2 * phi_dot**2 * s
        + (m1 + m2) * g * sp.sin(theta),
        # Divided through by l2; as printed in the notes.
        "phi equation / l2": m2 * l2 * phi_ddot
        + m2 * l1 * theta_ddot * c
        - m2 * l1 * theta_dot**2 * s
        + m2 * g * sp.sin(phi),
    }


def test_double_pendulum_equations() -> None:
    notes = _double_pendulum_notes()
    eom = lg.derive(lg.examples.double_pendulum())
    assert _same(eom.kinetic_energy, notes["T"])
    assert _same(eom.equations[0], l1 * notes["theta equation / l1"])
    assert _same(eom.equations[1], l2 * notes["phi equation / l2"])
    printed = (m1 + m2) * l1 * theta_ddot + m2 * l2 * phi_ddot * sp.cos(theta - phi)
    printed += -m2 * l2 * phi_dot**2 * sp.sin(theta - phi) + (m1 + m2) * g * sp.sin(theta - phi)
    assert not _same(eom.equations[0], l1 * printed)  # the typo, kept out of the library


def test_double_pendulum_steps_as_the_notes_write_them() -> None:
    notes = _double_pendulum_notes()
    step_theta, step_phi = lg.derive(lg.examples.double_pendulum()).steps
    assert _same(step_theta.dL_dvelocity, notes["dL/dtheta_dot"])
    assert _same(step_theta.ddt_dL_dvelocity, notes["d/dt dL/dtheta_dot"])
    assert _same(step_theta.dL_dcoordinate, notes["dL/dtheta"])
    assert _same(step_phi.dL_dvelocity, notes["dL/dphi_dot"])
    assert _same(step_phi.ddt_dL_dvelocity, notes["d/dt dL/dphi_dot"])
    assert _same(step_phi.dL_dcoordinate, notes["dL/dphi"])


def test_double_pendulum_mass_matrix_from_the_notes_kinetic_energy() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    velocities = [theta_dot, phi_dot]
    expected = sp.hessian(_double_pendulum_notes()["T"], velocities)
    assert all(_same(a, b) for a, b in zip(eom.mass_matrix, expected, strict=True))


def test_moving_pivot_pendulum_is_rheonomic() -> None:
    x0, omega = sp.symbols("x0 omega")
    eom = lg.derive(lg.examples.moving_pivot_pendulum())
    drive = -m * ell * x0 * omega**2 * sp.cos(omega * t) * sp.cos(theta)
    expected = m * ell**2 * theta_ddot + drive + m * g * ell * sp.sin(theta)
    assert _same(eom.equations[0], expected)
    assert _same(eom.time_terms[0], drive)  # the explicit time dependence of the pivot


# -- particles ------------------------------------------------------------------------------


def test_particle_plane_cartesian() -> None:
    f_x, f_y = sp.symbols("Fx Fy")
    eom = lg.derive(lg.examples.particle_plane_cartesian())
    assert list(eom.generalized_forces) == [f_x, f_y]  # Q_x = Fx, Q_y = Fy
    assert list(eom.equations) == [m * x_ddot - f_x, m * y_ddot - f_y]


def test_particle_plane_polar_generalized_forces_by_virtual_work() -> None:
    f_r, f_theta = sp.symbols("F_r F_theta")
    eom = lg.derive(lg.examples.particle_plane_polar())
    assert _same(eom.generalized_forces[0], f_r)
    assert _same(eom.generalized_forces[1], r * f_theta)
    eq_r, eq_theta = eom.equations
    assert _same(eq_r, m * (r_ddot - r * theta_dot**2) - f_r)
    assert _same(eq_theta, m * r * (r * theta_ddot + 2 * r_dot * theta_dot) - r * f_theta)
    step = eom.steps[1]  # notes: d/dt (m r^2 theta_dot) = m (r^2 theta_ddot + 2 r r_dot theta_dot)
    assert _same(step.dL_dvelocity, m * r**2 * theta_dot)
    assert _same(step.ddt_dL_dvelocity, m * (r**2 * theta_ddot + 2 * r * r_dot * theta_dot))


def test_mass_on_spring_steps() -> None:
    eom = lg.derive(lg.examples.mass_on_spring())
    step = eom.steps[0]
    assert (step.dL_dvelocity, step.ddt_dL_dvelocity, step.dL_dcoordinate) == (
        m * x_dot,
        m * x_ddot,
        -k * x,
    )
    assert _same(eom.equations[0], m * x_ddot + k * x - F)  # m x_ddot = -k x once F = 0


def test_mass_spring_damper_seed_001() -> None:
    big_k, big_b = sp.symbols("K B")
    eom = lg.derive(lg.examples.mass_spring_damper())
    assert _same(eom.potential_energy, big_k * x**2 / 2 + m * g * (h + x))
    assert _same(eom.dissipation_function, big_b * x_dot**2 / 2)
    step = eom.steps[0]
    assert step.dF_dvelocity == big_b * x_dot and step.generalized_force == f
    # Seed 001: f = m x_ddot + K x + m g + B x_dot.
    assert _same(eom.equations[0], m * x_ddot + big_k * x + m * g + big_b * x_dot - f)


def test_projectile_polar() -> None:
    eq_r, eq_theta = _equations(lg.examples.projectile_polar())
    assert _same(eq_r, m * (r_ddot - r * theta_dot**2) + m * g * sp.sin(theta))
    # The notes print m (r theta_ddot - 2 r_dot theta_dot) + m g cos(theta) = 0: the Coriolis
    # sign is a typo (d/dt (m r^2 theta_dot) = m r^2 theta_ddot + 2 m r r_dot theta_dot) and
    # the whole equation was divided by r.  The physics:
    expected = m * r**2 * theta_ddot + 2 * m * r * r_dot * theta_dot + m * g * r * sp.cos(theta)
    assert _same(eq_theta, expected)
    printed = m * (r * theta_ddot - 2 * r_dot * theta_dot) + m * g * sp.cos(theta)
    assert not _same(eq_theta, r * printed)


def test_planet() -> None:
    mu = sp.Symbol("mu")
    eom = lg.derive(lg.examples.planet())
    assert _same(eom.potential_energy, -m * mu / r)
    # The notes stop at "two Lagrange equations"; the textbook result:
    assert _same(eom.equations[0], m * r_ddot - m * r * theta_dot**2 + m * mu / r**2)
    assert _same(eom.equations[1], m * r**2 * theta_ddot + 2 * m * r * r_dot * theta_dot)
    assert eom.steps[1].dL_dcoordinate == 0  # theta is cyclic: m r^2 theta_dot is conserved
    assert _same(eom.steps[1].dL_dvelocity, m * r**2 * theta_dot)


def test_two_masses_three_springs() -> None:
    k1, k2, k3 = sp.symbols("k1 k2 k3")
    eom = lg.derive(lg.examples.two_masses_three_springs())
    notes_v = k1 * x1**2 / 2 + k3 * x2**2 / 2 + k2 * (x1 - x2) ** 2 / 2
    assert _same(eom.potential_energy, notes_v)
    assert eom.mass_matrix == sp.diag(m1, m2)
    assert _same(eom.steps[0].dL_dcoordinate, -k1 * x1 - k2 * (x1 - x2))
    assert _same(eom.equations[0], m1 * x1_ddot + x1 * (k1 + k2) - k2 * x2)
    assert _same(eom.equations[1], m2 * x2_ddot + x2 * (k3 + k2) - k2 * x1)


def test_quartic_lagrangian() -> None:
    # By hand: dL/dx_dot = m^2 x_dot^3/3 + 2 m V x_dot; its d/dt minus dL/dx factorizes as
    # (m x_ddot + V')(m x_dot^2 + 2 V), the notes' equation without their factor x_dot.
    eom = lg.derive(lg.examples.quartic_lagrangian())
    potential = k * x**2 / 2
    force = potential.diff(x)
    assert _same(eom.equations[0], (m * x_ddot + force) * (m * x_dot**2 + 2 * potential))
    assert _same(eom.mass_matrix[0, 0], m**2 * x_dot**2 + 2 * m * potential)  # depends on x_dot
    energy = m * x_dot**2 / 2 + potential
    pairs = [(x, x_dot, x_ddot)]
    assert _same(x_dot * eom.equations[0], _ddt(energy**2, pairs))  # d(E^2)/dt = 2 E E_dot


def test_stokes_drag() -> None:
    eta, a = sp.symbols("eta a")
    drag = 6 * sp.pi * eta * a
    eom = lg.derive(lg.examples.stokes_drag())
    assert list(eom.dissipation_forces) == [-drag * x_dot, -drag * y_dot]
    assert _same(eom.equations[0], m * x_ddot + drag * x_dot)
    assert _same(eom.equations[1], m * y_ddot + drag * y_dot + m * g)


def test_charged_particle_lorentz_force() -> None:
    q_e, e0, b0 = sp.symbols("q_e E0 B0")
    position, speed = sp.Matrix([x, y, z]), sp.Matrix([x_dot, y_dot, z_dot])
    scalar = -e0 * x
    vector = sp.Matrix([-b0 * y / 2, b0 * x / 2, 0])
    field_e = -sp.Matrix([scalar.diff(c) for c in position]) - vector.diff(t)
    field_b = sp.Matrix(
        [
            vector[2].diff(y) - vector[1].diff(z),
            vector[0].diff(z) - vector[2].diff(x),
            vector[1].diff(x) - vector[0].diff(y),
        ]
    )
    assert list(field_e) == [e0, 0, 0] and list(field_b) == [0, 0, b0]
    eom = lg.derive(lg.examples.charged_particle_em())
    lorentz = q_e * (field_e + speed.cross(field_b))
    for j, acc in enumerate([x_ddot, y_ddot, z_ddot]):
        assert _same(eom.equations[j], m * acc - lorentz[j])
        # notes: dL/dr_dot = m r_dot + q A
        assert _same(eom.steps[j].dL_dvelocity, m * speed[j] + q_e * vector[j])


# -- connected bodies -----------------------------------------------------------------------


def test_atwood_machine() -> None:
    eom = lg.derive(lg.examples.atwood_machine())
    assert _same(eom.kinetic_energy, y_dot**2 * (m1 + m2) / 2)
    assert _same(eom.potential_energy, -m1 * g * y - m2 * g * (ell - y))
    assert _same(eom.equations[0], y_ddot * (m1 + m2) - g * (m1 - m2))
    assert _same(eom.explicit_accelerations[0], g * (m1 - m2) / (m1 + m2))


def test_atwood_machine_with_pulley_inertia() -> None:
    eom = lg.derive(lg.examples.atwood_machine_with_pulley())
    pulley = big_i * y_dot**2 / (2 * big_r**2)
    assert _same(eom.kinetic_energy, y_dot**2 * (m1 + m2) / 2 + pulley)
    expected = g * (m1 - m2) / (m1 + m2 + big_i / big_r**2)
    assert _same(eom.explicit_accelerations[0], expected)


def test_dumbbell_seed_003() -> None:
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")
    s, c = sp.sin(theta), sp.cos(theta)
    eom = lg.derive(lg.examples.dumbbell())
    x2_acc = x1_ddot - h * c * theta_dot**2 - h * s * theta_ddot
    y2_acc = y1_ddot - h * s * theta_dot**2 + h * c * theta_ddot
    notes = [
        m1 * x1_ddot + m2 * x2_acc - (f1x + f2x),
        m1 * y1_ddot + m2 * y2_acc - (f1y + f2y - (m1 + m2) * g),
        m2 * (-x1_ddot * h * s + y1_ddot * h * c + h**2 * theta_ddot)
        - (-f2x * h * s + f2y * h * c - m2 * g * h * c),
    ]
    for ours, expected in zip(eom.equations, notes, strict=True):
        assert _same(ours, expected)
    # Q = (f1 + f2, f2 . h (-sin, cos)) by virtual work.
    q_theta = h * (-f2x * s + f2y * c)
    assert all(
        _same(a, b)
        for a, b in zip(eom.generalized_forces, [f1x + f2x, f1y + f2y, q_theta], strict=True)
    )


def test_dumbbell_steps_as_the_notes_write_them() -> None:
    # The notes write these momenta with double dots (x1_ddot for x1_dot): a typo, since the
    # next line differentiates them in time.
    s, c = sp.sin(theta), sp.cos(theta)
    step_x, _, step_theta = lg.derive(lg.examples.dumbbell()).steps
    assert _same(step_x.dL_dvelocity, m1 * x1_dot + m2 * (x1_dot - h * s * theta_dot))
    expected = m1 * x1_ddot + m2 * (x1_ddot - h * (c * theta_dot**2 + s * theta_ddot))
    assert _same(step_x.ddt_dL_dvelocity, expected)
    assert step_x.dL_dcoordinate == 0
    assert _same(step_theta.dL_dvelocity, m2 * h * ((c * y1_dot - s * x1_dot) + h * theta_dot))


def test_dumbbell_mass_matrix() -> None:
    s, c = sp.sin(theta), sp.cos(theta)
    expected = sp.Matrix(
        [
            [m1 + m2, 0, -m2 * h * s],
            [0, m1 + m2, m2 * h * c],
            [-m2 * h * s, m2 * h * c, m2 * h**2],
        ]
    )
    mass = sp.Matrix(lg.derive(lg.examples.dumbbell()).mass_matrix)
    assert sp.simplify(mass - expected) == sp.zeros(3, 3)
