"""The scalable examples: what they build is what SymPy builds from the same terms."""

from __future__ import annotations

import sympy as sp

import lagrangian as lg


def test_chain_positions_are_the_sums_sympy_makes() -> None:
    # each bob's position is built in the order of the whole sum's terms, unsorted: it must be
    # the very Add that summing the link vectors with sp.Add gives (srepr, so also the order)
    n = 23  # two-digit names sort apart from their numbers (l10 before l2)
    system = lg.examples.n_link_pendulum(n)
    thetas, lengths = sp.symbols(f"theta1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    for i, bob in enumerate(system.particles):
        across = sp.Add(*[lengths[j] * sp.sin(thetas[j]) for j in range(i + 1)])
        down = sp.Add(*[-lengths[j] * sp.cos(thetas[j]) for j in range(i + 1)])
        assert sp.srepr(bob.position) == sp.srepr((across, down))
        assert bob.position == (across, down)


def test_one_link() -> None:
    (bob,) = lg.examples.n_link_pendulum(1).particles
    l1, theta1 = sp.symbols("l1 theta1")
    assert bob.position == (l1 * sp.sin(theta1), -l1 * sp.cos(theta1))
