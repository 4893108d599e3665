"""Scalable systems built in Python (they take a size), for tests and benchmarks."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Particle, System

__all__ = ["n_link_pendulum"]


def n_link_pendulum(n: int = 3) -> System:
    """n point masses m_i on massless rods l_i, absolute angles theta_i from the vertical."""
    thetas = sp.symbols(f"theta1:{n + 1}")
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    # each bob's position made as one sum of its terms (a third cheaper than adding them
    # one by one, which flattens the growing sum at every link)
    across: list[sp.Expr] = []
    down: list[sp.Expr] = []
    particles = []
    for i in range(n):
        across.append(lengths[i] * sp.sin(thetas[i]))
        down.append(-lengths[i] * sp.cos(thetas[i]))
        particles.append(Particle(f"bob{i + 1}", masses[i], (sp.Add(*across), sp.Add(*down))))
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
