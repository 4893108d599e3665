"""The energy function and T + V expanded in the backend (lagrangian.derivation.energies),
against a hand derivation of the n-link pendulum and against SymPy's own expansion of
h = sum q_dot p - L written with the steps' momenta."""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.energies import energy_function, kinetic_plus_potential, rest_potential
from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.symbolic.native import to_symengine

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from derive import rod_chain


def hand_energy(n: int) -> sp.Expr:
    """T + V of n point masses on massless rods, written out by hand: bob i at
    sum_{k<=i} l_k (sin theta_k, -cos theta_k), velocity sum_{k<=i} l_k theta_k_dot
    (cos theta_k, sin theta_k), V = m_i g y_i."""
    theta = sp.symbols(f"theta1:{n + 1}")
    rates = sp.symbols(" ".join(f"theta{i}_dot" for i in range(1, n + 1)), seq=True)
    m, length, g = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}"), sp.Symbol("g")
    energy = sp.Integer(0)
    for i in range(n):
        vx = sum(length[k] * rates[k] * sp.cos(theta[k]) for k in range(i + 1))
        vy = sum(length[k] * rates[k] * sp.sin(theta[k]) for k in range(i + 1))
        y = -sum(length[k] * sp.cos(theta[k]) for k in range(i + 1))
        energy += m[i] * (vx**2 + vy**2) / 2 + m[i] * g * y
    return energy


def numerically_zero(expr: sp.Expr, points: int = 4) -> bool:
    rng = random.Random(1)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    for _ in range(points):
        value = expr.xreplace({s: sp.Float(rng.uniform(-2, 2)) for s in symbols})
        if abs(float(value)) > 1e-9:
            return False
    return True


@pytest.mark.parametrize("n", [2, 3, 5])
def test_chain_energy_function_is_the_hand_derived_total_energy(n):
    # scleronomic, no velocity potential: h = T + V (Goldstein §2.7)
    system = lg.examples.n_link_pendulum(n)
    assert numerically_zero(energy_function(system) - hand_energy(n))
    assert numerically_zero(kinetic_plus_potential(system) - hand_energy(n))


def sympy_energy_function(eom: lg.EquationsOfMotion) -> sp.Expr:
    momenta = [step.dL_dvelocity for step in eom.steps]
    work = sum((v * p for v, p in zip(eom.velocities, momenta)), sp.Integer(0))
    return sp.expand(work - eom.lagrangian)


#: Chains of particles and of rods, a velocity potential, a moving pivot (T with parts of
#: degree 0 and 1 in the velocities) and a 3-D body.
BUILDS = {
    "particles_9": lambda: lg.examples.n_link_pendulum(9),
    "rods_9": lambda: rod_chain(9),
    "charged_particle": lg.examples.get("charged_particle_em"),
    "moving_pivot": lg.examples.get("moving_pivot_pendulum"),
    "top": lg.examples.get("heavy_symmetric_top"),
}


@pytest.mark.parametrize("build", list(BUILDS.values()), ids=list(BUILDS))
def test_energy_function_is_sympys_expansion_exactly(build):
    system = build()
    eom = lg.derive(system)
    assert sp.srepr(energy_function(system)) == sp.srepr(sympy_energy_function(eom))
    total = sp.expand(eom.kinetic_energy + eom.potential_energy)
    assert sp.srepr(kinetic_plus_potential(system)) == sp.srepr(total)


def test_expansion_sympy_finishes_is_sympys():
    # SymEngine leaves a sine of a product with a sum and an exponential of a sum unexpanded
    x, y, a = sp.symbols("x y a")
    terms = euler_lagrange_terms(lg.examples.simple_pendulum())
    expr = sp.sin(a * (x + y)) * (x + 1) + sp.exp(x + y) * (y - 1) ** 2
    found = terms.sympy_expanded(to_symengine(expr))
    assert found == sp.expand(expr)
    assert found.has(sp.sin(a * x + a * y))


def bead_on_rotating_hoop() -> lg.System:
    """A bead on a hoop of radius R turning at omega about its vertical diameter: T has a
    part free of theta_dot, m R^2 omega^2 sin(theta)^2 / 2 (Goldstein §2.6)."""
    return lg.loads(
        """
name: bead_on_rotating_hoop
coordinates: [theta]
parameters: {m: 1.0, g: 9.81, R: 1.0, omega: 4.0}
kinetic: m*R**2*(theta_dot**2 + omega**2*sin(theta)**2)/2
potential: -m*g*R*cos(theta)
"""
    )


@pytest.mark.parametrize(
    "build",
    [*BUILDS.values(), bead_on_rotating_hoop],
    ids=[*BUILDS, "rotating_hoop"],
)
def test_rest_potential_is_sympys_expansion_of_minus_l_at_rest(build):
    system = build()
    eom = lg.derive(system)
    at_rest = {v: 0 for v in eom.velocities}
    rest = eom.potential_energy + (eom.velocity_potential - eom.kinetic_energy).xreplace(at_rest)
    assert sp.srepr(rest_potential(system)) == sp.srepr(sp.expand(rest))


def test_rest_potential_of_the_rotating_hoop_is_the_textbook_effective_potential():
    # V_eff = -m g R cos(theta) - m R^2 omega^2 sin(theta)^2 / 2: its minimum leaves the bottom
    # once omega^2 > g/R (Goldstein §2.6; Taylor, Classical Mechanics, §7.6)
    m, g, big_r, omega, theta = sp.symbols("m g R omega theta")
    hand = -m * g * big_r * sp.cos(theta) - m * big_r**2 * omega**2 * sp.sin(theta) ** 2 / 2
    assert sp.expand(rest_potential(bead_on_rotating_hoop()) - hand) == 0
