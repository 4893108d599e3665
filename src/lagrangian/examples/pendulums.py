"""Pendulums of the seed notes (000): simple, compound, spherical, double, n-link, and the
pendulum whose pivot moves as x0 cos(omega t)."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Particle, System

__all__ = ["n_link_pendulum", "simple_pendulum"]


def simple_pendulum() -> System:
    """Bob of mass m on a massless rod of length l; theta from the downward vertical.

    Seed 000: m l^2 theta_ddot + m g l sin(theta) = 0.
    """
    theta = sp.Symbol("theta")
    m, g, l = sp.symbols("m g l")
    return System(
        name="simple_pendulum",
        description="Simple pendulum: m l^2 theta'' + m g l sin(theta) = 0",
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        particles=[Particle("bob", m, (l * sp.sin(theta), -l * sp.cos(theta)))],
        gravity=(0, -g),
        initial={theta: 0.5, sp.Symbol("theta_dot"): 0.0},
    )


def n_link_pendulum(n: int) -> System:
    """n point masses m_i on massless rods l_i, absolute angles theta_i from the vertical."""
    thetas = sp.symbols(f"theta1:{n + 1}")
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    x, y = sp.Integer(0), sp.Integer(0)
    particles = []
    for i in range(n):
        x += lengths[i] * sp.sin(thetas[i])
        y -= lengths[i] * sp.cos(thetas[i])
        particles.append(Particle(f"bob{i + 1}", masses[i], (x, y)))
    parameters: dict[sp.Symbol, float | None] = {s: 1.0 for s in (*masses, *lengths)}
    parameters[g] = 9.81
    return System(
        name=f"pendulum_{n}_links",
        description=f"Planar pendulum of {n} point masses on massless rods",
        coordinates=thetas,
        parameters=parameters,
        particles=particles,
        gravity=(0, -g),
    )
