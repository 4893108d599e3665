"""Pendulums of the seed notes (000): simple, compound, spherical, double, n-link, and the
pendulum whose pivot moves as x0 cos(omega t)."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Particle, RigidBody, System, t, velocity

__all__ = [
    "compound_pendulum",
    "double_pendulum",
    "moving_pivot_pendulum",
    "n_link_pendulum",
    "simple_pendulum",
    "spherical_pendulum",
]


def simple_pendulum() -> System:
    """Bob of mass m on a massless rod of length l; theta from the downward vertical.

    Seed 000: m l^2 theta_ddot + m g l sin(theta) = 0.
    """
    theta = sp.Symbol("theta")
    m, g, length = sp.symbols("m g l")
    return System(
        name="simple_pendulum",
        description="Simple pendulum: m l^2 theta'' + m g l sin(theta) = 0",
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, length: 1.0},
        particles=[Particle("bob", m, (length * sp.sin(theta), -length * sp.cos(theta)))],
        gravity=(0, -g),
        initial={theta: 0.5, sp.Symbol("theta_dot"): 0.0},
    )


def n_link_pendulum(n: int = 3) -> System:
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


def compound_pendulum() -> System:
    """Compound pendulum: a rigid body swinging about a pivot l above its centre.

    Seed 000: I theta_ddot + m g l sin(theta) = 0, with I the moment of inertia about the
    pivot.  The body is given by its inertia I_c about the centre of mass, so by the parallel
    axis theorem the notes' I is I_c + m l^2:

        (I_c + m l^2) theta_ddot + m g l sin(theta) = 0.
    """
    theta = sp.Symbol("theta")
    m, g, length, i_c = sp.symbols("m g l I_c")
    return System(
        name="compound_pendulum",
        description="Compound pendulum: a rigid body swinging about a pivot l above its centre.",
        coordinates=[theta],
        # a uniform 1 m rod pivoted at one end: I_c = m (1 m)^2 / 12, l = 0.5 m
        parameters={m: 1.0, g: 9.81, length: 0.5, i_c: 1.0 / 12},
        rigid_bodies=[
            RigidBody("body", m, i_c, (length * sp.sin(theta), -length * sp.cos(theta)), theta)
        ],
        gravity=(0, -g),
        initial={theta: 0.5, velocity(theta): 0.0},
    )


def spherical_pendulum() -> System:
    """Spherical pendulum: a bob on a rod of length l, free to swing in 3-D.

    Seed 000 (the notes call the length r), theta from the downward vertical, phi azimuth:

        m l^2 (theta_ddot - sin(theta) cos(theta) phi_dot^2 + (g/l) sin(theta)) = 0,
        d/dt (m l^2 sin(theta)^2 phi_dot) = 0.
    """
    theta, phi = sp.symbols("theta phi")
    m, g, length = sp.symbols("m g l")
    position = (
        length * sp.sin(theta) * sp.cos(phi),
        length * sp.sin(theta) * sp.sin(phi),
        -length * sp.cos(theta),
    )
    return System(
        name="spherical_pendulum",
        description="Spherical pendulum: a bob on a rod of length l, free to swing in 3-D.",
        coordinates=[theta, phi],
        parameters={m: 1.0, g: 9.81, length: 1.0},
        particles=[Particle("bob", m, position)],
        gravity=(0, 0, -g),
        initial={theta: 0.8, phi: 0.0, velocity(theta): 0.0, velocity(phi): 1.5},
    )


def double_pendulum() -> System:
    """Double pendulum: two bobs on massless rods, angles theta and phi.

    Seed 000:

        (m1 + m2) l1 theta_ddot + m2 l2 phi_ddot cos(theta - phi)
            + m2 l2 phi_dot^2 sin(theta - phi) + (m1 + m2) g sin(theta) = 0,
        m2 l2 phi_ddot + m2 l1 theta_ddot cos(theta - phi)
            - m2 l1 theta_dot^2 sin(theta - phi) + m2 g sin(phi) = 0.
    """
    theta, phi = sp.symbols("theta phi")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    bob1 = (l1 * sp.sin(theta), -l1 * sp.cos(theta))
    bob2 = (bob1[0] + l2 * sp.sin(phi), bob1[1] - l2 * sp.cos(phi))
    return System(
        name="double_pendulum",
        description="Double pendulum: two bobs on massless rods, angles theta and phi.",
        coordinates=[theta, phi],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        particles=[Particle("bob1", m1, bob1), Particle("bob2", m2, bob2)],
        gravity=(0, -g),
        initial={theta: 1.0, phi: 0.5, velocity(theta): 0.0, velocity(phi): 0.0},
    )


def moving_pivot_pendulum() -> System:
    """Pendulum whose pivot moves as x0 cos(omega t) along x (rheonomic).

    Seed 000, constraint (x - x0 cos(omega t))^2 + y^2 - l^2 = 0; with theta from the
    downward vertical:

        m l^2 theta_ddot - m l x0 omega^2 cos(omega t) cos(theta) + m g l sin(theta) = 0.
    """
    theta = sp.Symbol("theta")
    m, g, length, x0, omega = sp.symbols("m g l x0 omega")
    pivot = x0 * sp.cos(omega * t)
    return System(
        name="moving_pivot_pendulum",
        description="Pendulum whose pivot moves as x0 cos(omega t) along x (rheonomic).",
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, length: 1.0, x0: 0.1, omega: 2.0},
        particles=[Particle("bob", m, (pivot + length * sp.sin(theta), -length * sp.cos(theta)))],
        gravity=(0, -g),
        initial={theta: 0.2, velocity(theta): 0.0},
    )
