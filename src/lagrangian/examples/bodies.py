"""Rigidly or inextensibly connected masses of the seed notes: the dumbbell pushed by forces
(seed 003) and the Atwood machine, with and without the inertia of its pulley (seed 000)."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Force, Particle, RigidBody, System, velocity

__all__ = ["atwood_machine", "atwood_machine_with_pulley", "dumbbell"]


def dumbbell() -> System:
    """Dumbbell: masses m1, m2 a rigid distance h apart, pushed by forces f1, f2.

    Seed 003: q1 = (x1, y1), q2 = q1 + h (cos(theta), sin(theta)), gravity (0, -g):

        m1 x1_ddot + m2 (x1_ddot - h cos(theta) theta_dot^2 - h sin(theta) theta_ddot)
            = f1x + f2x,
        m1 y1_ddot + m2 (y1_ddot - h sin(theta) theta_dot^2 + h cos(theta) theta_ddot)
            = f1y + f2y - (m1 + m2) g,
        m2 (-x1_ddot h sin(theta) + y1_ddot h cos(theta) + h^2 theta_ddot)
            = -f2x h sin(theta) + f2y h cos(theta) - m2 g h cos(theta).
    """
    x1, y1, theta = sp.symbols("x1 y1 theta")
    m1, m2, h, g = sp.symbols("m1 m2 h g")
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")
    second = (x1 + h * sp.cos(theta), y1 + h * sp.sin(theta))
    return System(
        name="dumbbell",
        description="Dumbbell: masses m1, m2 a rigid distance h apart, pushed by forces f1, f2.",
        coordinates=[x1, y1, theta],
        parameters={m1: 1.0, m2: 1.0, h: 1.0, g: 9.81, f1x: 0.0, f1y: 0.0, f2x: 0.0, f2y: 0.0},
        particles=[Particle("particle1", m1, (x1, y1)), Particle("particle2", m2, second)],
        forces=[Force("particle1", (f1x, f1y)), Force("particle2", (f2x, f2y))],
        gravity=(0, -g),
        initial={
            x1: 0.0,
            y1: 0.0,
            theta: 0.0,
            velocity(x1): 1.0,
            velocity(y1): 5.0,
            velocity(theta): 2.0,
        },
    )


def _atwood(pulley: bool) -> System:
    """Masses hanging at x = -R (depth y) and x = R (depth l - y) of a string over a pulley
    of radius R; with ``pulley`` the pulley is a body of inertia I turning by y / R."""
    y = sp.Symbol("y")
    m1, m2, length, radius, g = sp.symbols("m1 m2 l R g")
    parameters = {m1: 2.0, m2: 1.0, length: 2.0, radius: 0.1, g: 9.81}
    bodies = []
    if pulley:
        mass, inertia = sp.symbols("M I")
        parameters.update({mass: 0.5, inertia: 0.0025})  # a 0.5 kg disc: I = M R^2 / 2
        bodies.append(RigidBody("pulley", mass, inertia, (0, 0), y / radius))
    return System(
        coordinates=[y],
        parameters=parameters,
        particles=[
            Particle("mass1", m1, (-radius, -y)),
            Particle("mass2", m2, (radius, -(length - y))),
        ],
        rigid_bodies=bodies,
        gravity=(0, -g),
        initial={y: 1.0, velocity(y): 0.0},
    )


def atwood_machine() -> System:
    """Atwood machine: masses m1, m2 on a string over a massless pulley.

    Seed 000, y the depth of m1: T = 1/2 (m1 + m2) y_dot^2, V = -m1 g y - m2 g (l - y):

        (m1 + m2) y_ddot - g (m1 - m2) = 0,    y_ddot = g (m1 - m2) / (m1 + m2).
    """
    return _atwood(pulley=False).replace(
        name="atwood_machine",
        description="Atwood machine: masses m1, m2 on a string over a massless pulley.",
    )


def atwood_machine_with_pulley() -> System:
    """Atwood machine whose pulley (radius R, inertia I) turns with the string.

    Seed 000: T gains 1/2 I theta_dot^2 = 1/2 I y_dot^2 / R^2, so

        (m1 + m2 + I / R^2) y_ddot - g (m1 - m2) = 0,  y_ddot = g (m1 - m2) / (m1 + m2 + I / R^2).
    """
    return _atwood(pulley=True).replace(
        name="atwood_machine_with_pulley",
        description="Atwood machine whose pulley (radius R, inertia I) turns with the string.",
    )
