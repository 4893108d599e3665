"""The Legendre transform and Hamilton's equations against textbook formulas.

References:
- charge in a field (seed 002): H = (p - q A)^2 / (2 m) + q phi, here with the example's
  A = B0/2 (-y, x, 0), phi = -E0 x;  the Lorentz force gives d/dt p_x = q E0 + q B0 y_dot/2
  (p_x = m x_dot - q B0 y / 2 and m x_ddot = q (E0 + B0 y_dot));
- planet: H = p_r^2/(2m) + p_theta^2/(2 m r^2) - m mu / r;
- double pendulum (Goldstein-style): the kinetic part of H is 1/2 p^T M^-1 p;
- an RC + RL circuit has no inductance on q1: a singular Legendre transform.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import energy_function, hamilton_equations, hamiltonian

m, mu, q_e, e0, b0 = sp.symbols("m mu q_e E0 B0")
x, y, z, r, theta = sp.symbols("x y z r theta")
x_dot, y_dot, z_dot = sp.symbols("x_dot y_dot z_dot")
p_x, p_y, p_z, p_r, p_theta = sp.symbols("p_x p_y p_z p_r p_theta")


def _same(a: sp.Expr, b: sp.Expr) -> bool:
    return sp.simplify(sp.expand(a - b)) == 0


def test_charge_in_a_field_textbook_hamiltonian() -> None:
    legendre = hamiltonian(lg.examples.charged_particle_em())
    vector = sp.Matrix([-b0 * y / 2, b0 * x / 2, 0])
    scalar = -e0 * x
    kinetic = sp.Matrix([p_x, p_y, p_z]) - q_e * vector
    expected = kinetic.dot(kinetic) / (2 * m) + q_e * scalar
    assert legendre.momenta == (p_x, p_y, p_z)
    assert _same(legendre.hamiltonian, expected)
    assert _same(legendre.velocities[x_dot], (p_x + q_e * b0 * y / 2) / m)


def test_charge_hamilton_equations_reproduce_the_lorentz_force() -> None:
    eom = lg.derive(lg.examples.charged_particle_em())
    equations = hamilton_equations(eom)
    momenta = {p_x: m * x_dot - q_e * b0 * y / 2, p_y: m * y_dot + q_e * b0 * x / 2, p_z: m * z_dot}
    rates = [e.xreplace(momenta) for e in equations.momentum_rates]
    assert _same(rates[0], q_e * e0 + q_e * b0 * y_dot / 2)
    assert _same(rates[1], -q_e * b0 * x_dot / 2)
    assert rates[2] == 0
    velocities = [e.xreplace(momenta) for e in equations.coordinate_rates]
    assert [sp.simplify(v) for v in velocities] == [x_dot, y_dot, z_dot]


def test_planet_hamiltonian() -> None:
    legendre = hamiltonian(lg.examples.planet())
    expected = p_r**2 / (2 * m) + p_theta**2 / (2 * m * r**2) - m * mu / r
    assert _same(legendre.hamiltonian, expected)


def test_double_pendulum_kinetic_part_is_p_minv_p() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    legendre = hamiltonian(eom)
    p = sp.Matrix(legendre.momenta)
    mass = sp.Matrix(eom.mass_matrix)
    expected = (p.T * mass.inv() * p)[0, 0] / 2 + eom.potential_energy
    rng = random.Random(3)
    for _ in range(3):
        point = {s: rng.uniform(0.5, 1.5) for s in legendre.hamiltonian.free_symbols}
        assert abs(float((legendre.hamiltonian - expected).subs(point))) < 1e-12


@pytest.mark.parametrize(
    "name", ["simple_pendulum", "robot_arm", "moving_pivot_pendulum", "two_mesh_circuit"]
)
def test_hamiltonian_is_the_energy_function_in_momenta(name: str) -> None:
    # H(q, p(q, q_dot), t) = h(q, q_dot, t) for every Lagrangian (definition of h).
    eom = lg.derive(lg.examples.get(name)())
    legendre = hamiltonian(eom)
    momenta = {p: s.dL_dvelocity for p, s in zip(legendre.momenta, eom.steps)}
    assert _same(legendre.hamiltonian.xreplace(momenta), energy_function(eom))


def test_damping_and_forces_enter_the_momentum_equations() -> None:
    # Robot arm (seed 001): p_theta = m r^2 theta_dot, d/dt p_theta = -m g r cos(theta)
    # + tau - B1 theta_dot.
    equations = hamilton_equations(lg.examples.robot_arm())
    m_, g, tau, b1 = sp.symbols("m g tau B1")
    expected = -m_ * g * r * sp.cos(theta) + tau - b1 * p_theta / (m_ * r**2)
    assert _same(equations.momentum_rates[0], expected)


def test_non_quadratic_lagrangian_is_inverted_by_solve() -> None:
    # Seed 000's quartic L: p = m^2 x_dot^3 / 3 + 2 m V x_dot has one real inverse.
    eom = lg.derive(lg.examples.quartic_lagrangian())
    legendre = hamiltonian(eom)
    point = {sp.Symbol("m"): 1.3, sp.Symbol("k"): 0.7, x: 0.4, x_dot: 0.9}
    momentum = float(eom.steps[0].dL_dvelocity.subs(point))
    h = complex(legendre.hamiltonian.subs({**point, sp.Symbol("p_x"): momentum}).evalf())
    assert abs(h - float(energy_function(eom).subs(point))) < 1e-10


def test_singular_legendre_transform_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match=r"singular Legendre transform.*q1"):
        hamiltonian(lg.examples.rc_rl_circuit())


def test_velocities_entering_in_fewer_combinations_are_refused() -> None:
    x1, x2 = sp.symbols("x1 x2")
    v1, v2 = sp.symbols("x1_dot x2_dot")
    system = lg.System(coordinates=[x1, x2], kinetic=(v1 + v2) ** 2 / 2)
    with pytest.raises(lg.AnalysisError, match=r"rank 1 < 2.*fewer combinations"):
        hamiltonian(system)
