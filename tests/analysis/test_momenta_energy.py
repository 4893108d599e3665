"""Conjugate momenta, cyclic coordinates and the energy function against hand results.

References (written here by hand, not taken from the code under test):
- planet (seed 000): L = 1/2 m (r_dot^2 + r^2 theta_dot^2) + m mu / r, so p_theta = m r^2
  theta_dot is conserved and h = T + V = 1/2 m (r_dot^2 + r^2 theta_dot^2) - m mu / r;
- spherical pendulum (seed 000): phi is cyclic, p_phi = m l^2 sin^2(theta) phi_dot;
- mass-spring-damper (seed 001): F = 1/2 B x_dot^2, so dh/dt = -2F = -B x_dot^2 (plus the
  power f x_dot of the applied force);
- bead on a hoop of radius R spinning at omega about the vertical (seed 002 / textbook):
  L = m R^2/2 (theta_dot^2 + omega^2 sin^2 theta) + m g R cos theta has no explicit time, so
  h = m R^2/2 (theta_dot^2 - omega^2 sin^2 theta) - m g R cos theta is conserved, but
  T + V = m R^2/2 (theta_dot^2 + omega^2 sin^2 theta) - m g R cos theta is not h.
"""

from __future__ import annotations

import sympy as sp

import lagrangian as lg
from lagrangian.analysis import (
    conjugate_momenta,
    cyclic_coordinates,
    energy_conservation,
    energy_function,
)

m, g, l, mu, R, omega = sp.symbols("m g l mu R omega")
r, theta, phi, x, z = sp.symbols("r theta phi x z")
r_dot, theta_dot, phi_dot, x_dot, z_dot = sp.symbols("r_dot theta_dot phi_dot x_dot z_dot")
B, f = sp.symbols("B f")


def _same(a: sp.Expr, b: sp.Expr) -> bool:
    return sp.simplify(a - b) == 0


def hoop_given_energies() -> lg.System:
    """Bead on a hoop spinning at omega, T and V written out (T has the part T0)."""
    kinetic = m * R**2 / 2 * (theta_dot**2 + omega**2 * sp.sin(theta) ** 2)
    return lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, R: 1.0, omega: 5.0},
        kinetic=kinetic,
        potential=-m * g * R * sp.cos(theta),
    )


def hoop_particle() -> lg.System:
    """The same bead as a particle at (R sin th cos wt, R sin th sin wt, -R cos th)."""
    position = (
        R * sp.sin(theta) * sp.cos(omega * lg.t),
        R * sp.sin(theta) * sp.sin(omega * lg.t),
        -R * sp.cos(theta),
    )
    return lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, R: 1.0, omega: 5.0},
        particles=[lg.Particle("bead", m, position)],
        gravity=(0, 0, -g),
    )


HOOP_H = m * R**2 / 2 * (theta_dot**2 - omega**2 * sp.sin(theta) ** 2) - m * g * R * sp.cos(theta)


def test_planet_angular_momentum_is_conserved_and_h_is_t_plus_v() -> None:
    eom = lg.derive(lg.examples.planet())
    (cyclic,) = cyclic_coordinates(eom)
    assert cyclic.coordinate == theta
    assert _same(cyclic.momentum, m * r**2 * theta_dot)
    assert "theta does not appear in L" in cyclic.reason
    energy = energy_conservation(eom)
    assert energy.conserved and energy.rate == 0
    assert _same(energy.energy_function, m * (r_dot**2 + r**2 * theta_dot**2) / 2 - m * mu / r)
    assert energy.equals_total_energy
    assert "quadratic form" in energy.total_energy_reason


def test_momenta_are_dl_dq_dot() -> None:
    momenta = conjugate_momenta(lg.examples.planet())
    assert _same(momenta["r"], m * r_dot)
    assert _same(momenta[theta], m * r**2 * theta_dot)
    assert set(momenta.by_name()) == {"r", "theta"}


def test_spherical_pendulum_phi_is_cyclic() -> None:
    (cyclic,) = cyclic_coordinates(lg.examples.spherical_pendulum())
    assert cyclic.coordinate == phi
    assert _same(cyclic.momentum, m * l**2 * sp.sin(theta) ** 2 * phi_dot)


def test_charged_particle_z_is_cyclic_but_x_and_y_are_not() -> None:
    # U = -q E0 x - q B0/2 (x y_dot - y x_dot): x and y appear in L, z does not.
    cyclic = cyclic_coordinates(lg.examples.charged_particle_em())
    assert [c.coordinate for c in cyclic] == [z]
    assert _same(cyclic[0].momentum, m * z_dot)


def test_a_force_on_a_coordinate_absent_from_l_spoils_its_conservation() -> None:
    # particle_plane_cartesian: x and y are absent from L, so cyclic (Goldstein §2.6), but
    # Fx, Fy act on them: their momenta are not conserved, for the reason "force".
    pushed = {"Fx": 1.5, "Fy": -0.5}
    cyclic = cyclic_coordinates(lg.examples.particle_plane_cartesian(), parameters=pushed)
    assert [c.coordinate.name for c in cyclic] == ["x", "y"]
    assert [(c.conserved, c.obstructions) for c in cyclic] == [(False, ("force",))] * 2
    # ... at the example's values Fx = Fy = 0 they are conserved, on that condition ...
    cyclic = cyclic_coordinates(lg.examples.particle_plane_cartesian())
    fx, fy = sp.symbols("Fx Fy")
    assert [(c.conserved, c.condition) for c in cyclic] == [
        (True, sp.Eq(fx, 0)),
        (True, sp.Eq(fy, 0)),
    ]
    # ... and with the forces removed both momenta are conserved unconditionally.
    free = lg.examples.particle_plane_cartesian().replace(forces=())
    assert [(c.coordinate.name, c.conserved, c.condition) for c in cyclic_coordinates(free)] == [
        ("x", True, sp.true),
        ("y", True, sp.true),
    ]


def test_dissipation_gives_dh_dt_minus_two_f() -> None:
    eom = lg.derive(lg.examples.mass_spring_damper())
    energy = energy_conservation(eom)
    assert not energy.conserved
    dissipation = B * x_dot**2 / 2
    assert _same(energy.rate.subs(f, 0), -2 * dissipation)
    assert _same(energy.rate, -2 * dissipation + f * x_dot)
    assert "2F" in energy.reason and "Q_x = f" in energy.reason


def test_hoop_h_conserved_but_not_t_plus_v() -> None:
    energy = energy_conservation(hoop_given_energies())
    assert _same(energy.energy_function, HOOP_H)
    assert energy.conserved, energy.reason
    assert not energy.equals_total_energy
    assert "degree 0" in energy.total_energy_reason
    assert "rheonomic" in energy.total_energy_reason
    total = m * R**2 / 2 * (theta_dot**2 + omega**2 * sp.sin(theta) ** 2)
    assert _same(energy.total_energy, total - m * g * R * sp.cos(theta))


def test_hoop_built_from_a_rotating_particle() -> None:
    energy = energy_conservation(hoop_particle())
    assert energy.conserved and not energy.equals_total_energy
    assert _same(energy.energy_function, HOOP_H)


def test_moving_pivot_h_not_conserved_because_of_explicit_time() -> None:
    energy = energy_conservation(lg.examples.moving_pivot_pendulum())
    assert not energy.conserved
    assert "explicitly on t" in energy.reason
    assert not energy.equals_total_energy


def test_charged_particle_h_is_kinetic_plus_scalar_potential() -> None:
    # Seed 000: H = 1/2 m v^2 + q phi is conserved although the force is not conservative.
    energy = energy_conservation(lg.examples.charged_particle_em())
    y_dot = sp.Symbol("y_dot")
    q_e, e0 = sp.symbols("q_e E0")
    expected = m * (x_dot**2 + y_dot**2 + z_dot**2) / 2 + q_e * (-e0 * x)
    assert energy.conserved
    assert _same(energy.energy_function, expected)
    assert energy.equals_total_energy


def test_applied_time_dependent_force_is_named() -> None:
    w = sp.Symbol("w")
    system = lg.examples.mass_on_spring()
    driven = system.replace(
        generalized_forces={x: sp.cos(w * lg.t)}, parameters={**system.parameters, w: 1.0}
    )
    energy = energy_conservation(driven)
    assert not energy.conserved
    assert "depends on t" in energy.reason


def test_energy_function_of_a_quartic_lagrangian_is_not_t_plus_v() -> None:
    # Seed 000: L = m^2 x_dot^4/12 + m x_dot^2 V - V^2 gives h = m^2 x_dot^4/4 + m x_dot^2 V + V^2.
    k = sp.Symbol("k")
    v = k * x**2 / 2
    h = energy_function(lg.examples.quartic_lagrangian())
    assert _same(h, m**2 * x_dot**4 / 4 + m * x_dot**2 * v + v**2)
    energy = energy_conservation(lg.examples.quartic_lagrangian())
    assert energy.conserved and not energy.equals_total_energy
    assert "degree 4" in energy.total_energy_reason
