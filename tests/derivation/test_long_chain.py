"""A long chain, against its closed form: the planar pendulum of n point masses on massless rods
(absolute angles theta_i from the vertical) has

    M_jk = l_j l_k S_max(j,k) cos(theta_j - theta_k),    S_k = m_k + ... + m_n,
    forcing_j = -sum_k l_j l_k S_max(j,k) sin(theta_j - theta_k) theta_dot_k^2
                - g l_j S_j sin(theta_j),

written here from the physics (the velocity of bob i is sum_(k<=i) l_k theta_dot_k times the
unit vector at right angles to link k).  The sums S_k are what a long chain's equations carry in
every term; the derivation keeps each one whole, and these tests check that what it keeps is
still the closed form, numerically at a random state with distinct masses and lengths.
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.collect import collect_state
from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.render.json import eom_document
from lagrangian.render.text import SumPrinter

LINKS = 30


def _values(system: lg.System, seed: int) -> dict[sp.Symbol, float]:
    """Distinct masses and lengths, and a random state (angles, rates, accelerations)."""
    rng = random.Random(seed)
    values: dict[sp.Symbol, float] = {p: rng.uniform(0.5, 2.0) for p in system.parameters}
    values[sp.Symbol("g")] = 9.81
    for names in (system.coordinates, system.velocities, system.accelerations):
        values.update({s: rng.uniform(-1.5, 1.5) for s in names})
    return values


def _closed_form(n: int, v: dict[sp.Symbol, float]) -> tuple[np.ndarray, np.ndarray]:
    def s(name: str) -> float:
        return v[sp.Symbol(name)]

    theta = [s(f"theta{i}") for i in range(1, n + 1)]
    rate = [s(f"theta{i}_dot") for i in range(1, n + 1)]
    length = [s(f"l{i}") for i in range(1, n + 1)]
    tail = np.cumsum([s(f"m{i}") for i in range(n, 0, -1)])[::-1]  # S_k
    mass = np.empty((n, n))
    forcing = np.empty(n)
    for j in range(n):
        for k in range(n):
            mass[j, k] = length[j] * length[k] * tail[max(j, k)] * np.cos(theta[j] - theta[k])
        forcing[j] = -s("g") * length[j] * tail[j] * np.sin(theta[j]) - sum(
            length[j] * length[k] * tail[max(j, k)] * np.sin(theta[j] - theta[k]) * rate[k] ** 2
            for k in range(n)
        )
    return mass, forcing


def _numbers(matrix: sp.MatrixBase, values: dict[sp.Symbol, float]) -> np.ndarray:
    numbers = {s: sp.Float(x) for s, x in values.items()}
    return np.array(matrix.xreplace(numbers).tolist(), dtype=float)


@pytest.fixture(scope="module")
def chain() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.n_link_pendulum(LINKS))


def test_a_thirty_link_chain_is_its_closed_form(chain: lg.EquationsOfMotion) -> None:
    eom = chain
    values = _values(eom.system, seed=19)
    mass, forcing = _closed_form(LINKS, values)
    np.testing.assert_allclose(_numbers(eom.mass_matrix, values), mass, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(_numbers(eom.forcing, values).ravel(), forcing, rtol=1e-11)
    # the steps differentiate L itself: their equations are M q_ddot - forcing as well
    q_ddot = np.array([values[a] for a in eom.accelerations])
    residuals = _numbers(eom.equations, values).ravel()
    np.testing.assert_allclose(residuals, mass @ q_ddot - forcing, rtol=1e-10, atol=1e-9)


def test_the_steps_of_a_twelve_link_chain_are_its_closed_form() -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(12))
    values = _values(eom.system, seed=12)
    mass, forcing = _closed_form(12, values)
    rates = np.array([values[v] for v in eom.velocities])
    steps = eom.steps
    momentum = _numbers(sp.Matrix([s.dL_dvelocity for s in steps]), values).ravel()
    np.testing.assert_allclose(momentum, mass @ rates, rtol=1e-11)
    shown = sp.Matrix([s.ddt_dL_dvelocity - s.dL_dcoordinate for s in steps])
    q_ddot = np.array([values[a] for a in eom.accelerations])
    np.testing.assert_allclose(
        _numbers(shown, values).ravel(), mass @ q_ddot - forcing, rtol=1e-10, atol=1e-9
    )


def test_the_sums_of_a_long_chain_are_kept_whole_and_written_once(
    chain: lg.EquationsOfMotion,
) -> None:
    eom = chain
    tail = sp.Add(*sp.symbols(f"m5:{LINKS + 1}"))  # S_5, a sum of 26 masses
    document = eom_document(eom)
    entry = document["mass_matrix"][0][4]
    assert sp.sstr(tail, order="none") in entry  # written whole, not as 26 terms
    # and what is written is M: it parses back to the closed form's entry
    values = _values(eom.system, seed=5)
    mass, _ = _closed_form(LINKS, values)
    parsed = sp.sympify(entry, locals={s.name: s for s in values})
    assert float(parsed.xreplace({s: sp.Float(x) for s, x in values.items()})) == pytest.approx(
        mass[0, 4], rel=1e-12
    )


def test_a_sum_kept_whole_collects_as_the_expanded_sum_would() -> None:
    """collect_state with the sums given equals collect_state of the expanded expression."""
    a, b, c, x, y = se.symbols("a b c x y")
    total, placeholder = a + b + c, se.Symbol("S")
    sums = {placeholder: (total, total)}
    expanded = se.expand(x * y * total + 2 * x * y * a + x * total)
    kept = collect_state(x * y * placeholder + 2 * x * y * a + x * placeholder, {x, y}, sums)
    assert se.expand(kept - expanded) == 0
    assert x * total in kept.args  # a coefficient that is one sum keeps it whole


def test_the_sum_printer_writes_what_sstr_writes() -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(4))
    for expr in [*eom.equations, *eom.forcing, eom.lagrangian]:
        assert SumPrinter().doprint(expr) == sp.sstr(expr)
        assert SumPrinter({"order": "none"}).doprint(expr) == sp.sstr(expr, order="none")


def test_compressing_the_sums_of_a_long_chain_loses_nothing() -> None:
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(12))
    lagrangian = terms.kinetic.kinetic_energy - terms.assembly.potential
    compact = terms.compress(lagrangian)
    assert se.expand(terms.expand_sums(compact) - lagrangian) == 0
