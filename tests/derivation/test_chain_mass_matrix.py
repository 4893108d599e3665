"""The mass matrix of an n-link planar pendulum against its closed form

    M_jk = l_j l_k cos(theta_j - theta_k) (m_max(j,k) + ... + m_n)

(point masses on massless rods, absolute angles; e.g. Goldstein §1.6 for n = 2): the
products of the chain's planar columns (l cos theta, l sin theta) are combined at once."""

from __future__ import annotations

import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.examples import get


@pytest.mark.parametrize("n", [1, 2, 5, 9])
def test_the_chain_mass_matrix_is_the_closed_form(n):
    system = get("n_link_pendulum")(n)
    theta = sp.symbols(f"theta1:{n + 1}")
    mass = sp.symbols(f"m1:{n + 1}")
    length = sp.symbols(f"l1:{n + 1}")
    derived = lg.derive(system).mass_matrix
    for j in range(n):
        for k in range(n):
            weight = sum(mass[max(j, k) :])
            closed = length[j] * length[k] * sp.cos(theta[j] - theta[k]) * weight
            assert se.expand(se.sympify(derived[j, k] - closed)) == 0, (j, k)


def test_a_column_that_is_not_planar_polar_is_combined_as_before():
    # a pendulum on a sliding support: the support's column (1, 0) is not (r cos a, r sin a)
    x, theta, m, M, length = sp.symbols("x theta m M l")
    system = lg.System(
        coordinates=[x, theta],
        parameters=[m, M, length],
        particles=[
            lg.Particle("cart", M, (x, 0)),
            lg.Particle("bob", m, (x + length * sp.sin(theta), -length * sp.cos(theta))),
        ],
    )
    expected = sp.Matrix(
        [[M + m, m * length * sp.cos(theta)], [m * length * sp.cos(theta), m * length**2]]
    )
    assert sp.simplify(lg.derive(system).mass_matrix - expected) == sp.zeros(2, 2)
