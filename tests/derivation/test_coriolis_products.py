"""C q_dot of a planar chain read off M by monomial (derivation/coriolis.py), and the
forcing tidied with those monomials taken as they are (EulerLagrangeTerms._tidy_with):
checked against the general Christoffel sum, the textbook chain formula, and the forcing
tidied as a whole."""

import dataclasses
import sys
from pathlib import Path

import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.coriolis import coriolis_products
from lagrangian.derivation.kinetic import _coriolis, coriolis_vector
from lagrangian.derivation.terms import euler_lagrange_terms

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import derive as chains


def _general(terms):
    """The general Christoffel sum of the same M, expanded row by row."""
    return [se.expand(row) for row in _coriolis(terms.kinetic.mass_matrix, terms.assembly)]


@pytest.mark.parametrize("build", [lg.examples.n_link_pendulum, chains.rod_chain])
@pytest.mark.parametrize("n", [2, 5, 9])
def test_products_equal_the_christoffel_sum(build, n):
    terms = euler_lagrange_terms(build(n))
    products = terms.kinetic.coriolis_products
    assert products is not None
    for row, general in zip(products, _general(terms)):
        assert se.expand(se.Add(*[p.term for p in row])) == general
        # each monomial once: the q_dot_j q_dot_k terms cancelled before any expression
        assert len({p.monomial for p in row}) == len(row) == n - 1


def test_chain_rows_are_the_textbook_sums():
    """(C q_dot)_j = sum_k l_j l_k (m_max(j,k) + ... + m_n) sin(theta_j - theta_k) theta_k_dot^2
    for point masses on massless rods (derived by hand from M_jk = l_j l_k S cos)."""
    n = 6
    system = lg.examples.n_link_pendulum(n)
    eom = lg.derive(system)
    th = sp.symbols(f"theta1:{n + 1}")
    dots = sp.symbols(" ".join(f"theta{i}_dot" for i in range(1, n + 1)))
    m, ell = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    for j in range(n):
        expected = sum(
            ell[j] * ell[k] * sum(m[max(j, k) :]) * sp.sin(th[j] - th[k]) * dots[k] ** 2
            for k in range(n)
            if k != j
        )
        assert sp.expand(eom.coriolis[j] - expected) == 0


def _doubled_masses(n):
    """The n-link pendulum with bobs of mass 2 m_i: every sum of masses has the common
    factor 2, which the collection pulls out (a coefficient is not collected as it came)."""
    system = lg.examples.n_link_pendulum(n)
    bobs = [dataclasses.replace(p, mass=2 * p.mass) for p in system.particles]
    return dataclasses.replace(system, particles=tuple(bobs))


@pytest.mark.parametrize("build", [lg.examples.n_link_pendulum, chains.rod_chain, _doubled_masses])
@pytest.mark.parametrize("n", [9, 14])
def test_forcing_is_the_whole_forcing_tidied(build, n):
    """The rows tidied with the products given by monomial are the same expressions as the
    rows tidied whole (sums of masses kept whole from 8 links on, with a common factor or
    without)."""
    terms = euler_lagrange_terms(build(n))
    asm = terms.assembly
    for j in range(n):
        whole = terms.tidy(
            asm.applied[j]
            + terms.dissipation_forces[j]
            + terms.velocity_potential_forces[j]
            - coriolis_vector(terms.kinetic)[j]
            - terms.kinetic.time_terms[j]
            - terms.gravity[j]
        )
        assert terms.forcing[j] == whole


def test_two_coefficients_for_one_monomial_take_the_general_sum():
    """M_11 = b cos(x - y) and M_12 = a cos(x - y) both give x_dot y_dot sin(x - y) in the
    first row: no products, and the equations are the Euler-Lagrange ones by hand."""
    x, y, xd, yd, a, b, c = sp.symbols("x y x_dot y_dot a b c")
    kinetic = b * sp.cos(x - y) * xd**2 / 2 + a * sp.cos(x - y) * xd * yd + c * yd**2 / 2
    system = lg.System(coordinates=[x, y], parameters=[a, b, c], kinetic=kinetic)
    terms = euler_lagrange_terms(system)
    assert coriolis_products(terms.kinetic.mass_matrix, terms.assembly) is None
    eom = lg.derive(system)
    t = sp.Symbol("t")
    X, Y = sp.Function("X")(t), sp.Function("Y")(t)
    lagrangian = kinetic.subs({xd: X.diff(t), yd: Y.diff(t), x: X, y: Y})
    for q, row in ((X, 0), (Y, 1)):
        by_hand = lagrangian.diff(q.diff(t)).diff(t) - lagrangian.diff(q)
        acc = {X.diff(t, 2): sp.Symbol("x_ddot"), Y.diff(t, 2): sp.Symbol("y_ddot")}
        vel = {X.diff(t): xd, Y.diff(t): yd}
        by_hand = by_hand.subs(acc).subs(vel).subs({X: x, Y: y})
        ours = (eom.mass_matrix * sp.Matrix(["x_ddot", "y_ddot"]))[row] - eom.forcing[row]
        assert sp.simplify(sp.expand(by_hand - sp.sympify(ours))) == 0


def test_entries_that_are_not_one_sine_or_cosine_take_the_general_sum():
    """The polar robot arm's M_theta_theta = m r^2 moves with r (no sine or cosine)."""
    terms = euler_lagrange_terms(lg.examples.robot_arm())
    assert terms.kinetic.coriolis_products is None
