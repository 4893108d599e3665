"""Scalable systems built in Python (they take a size), for tests and benchmarks."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Particle, System
from lagrangian.symbolic.canonical import Builder, sympy_sum

__all__ = ["n_link_pendulum"]


def n_link_pendulum(n: int = 3) -> System:
    """n point masses m_i on massless rods l_i, absolute angles theta_i from the vertical."""
    thetas = sp.symbols(f"theta1:{n + 1}")
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    across = _partial_sums([lengths[i] * sp.sin(thetas[i]) for i in range(n)])
    down = _partial_sums([-lengths[i] * sp.cos(thetas[i]) for i in range(n)])
    particles = [Particle(f"bob{i + 1}", masses[i], (across[i], down[i])) for i in range(n)]
    parameters: dict[sp.Symbol, float | None] = {s: 1.0 for s in (*masses, *lengths)}
    parameters[g] = 9.81
    return System(
        name=f"pendulum_{n}_links",
        description=f"Planar pendulum of {n} point masses on massless rods",
        coordinates=thetas,
        parameters=parameters,
        particles=particles,
        gravity=(0, -g),
        initial={**{q: 0.5 for q in thetas}, **{sp.Symbol(f"{q.name}_dot"): 0.0 for q in thetas}},
        simulation={"t_end": 10},
    )


def _partial_sums(terms: list[sp.Expr]) -> list[sp.Expr]:
    """The sums of the first 1, 2, ..., n of ``terms``, each the very Add that ``sp.Add``
    makes, built by one :class:`~lagrangian.symbolic.canonical.Builder` (no sorting and
    checking of each term again: a 200-link chain's positions in 0.02 s, not 0.1).

    >>> x, y, z = sp.symbols("x y z")
    >>> _partial_sums([z, y, x])
    [z, y + z, x + y + z]
    >>> _partial_sums([x, 2 * x, y])  # terms that combine
    [x, 3*x, 3*x + y]
    """
    builder = Builder()
    return [sympy_sum(terms[: i + 1], builder) for i in range(len(terms))]
