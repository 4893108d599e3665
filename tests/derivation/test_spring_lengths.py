"""A spring's length is written as a textbook writes it: sin^2 + cos^2 = 1 applied under the
root, so the elastic pendulum's equations read k (r - l0), not
k l0 r / sqrt(r^2 sin^2(theta) + r^2 cos^2(theta))."""

from __future__ import annotations

import sympy as sp

import lagrangian as lg

MODEL = """
name: elastic pendulum
coordinates: [r, theta]
parameters: {m: 1.0, k: 10.0, l0: 1.0, g: 9.81, c: 0.1}
particles:
  - {name: bob, mass: m, position: [r*sin(theta), -r*cos(theta)]}
springs:
  - {between: [[0, 0], bob], stiffness: k, rest_length: l0}
dampers:
  - {between: [[0, 0], bob], coefficient: c}
gravity: [0, -g]
"""


def test_the_elastic_pendulum_has_no_trigonometry_under_its_roots() -> None:
    eom = lg.derive(lg.loads(MODEL))
    text = " ".join(str(e) for e in (*eom.equations, eom.potential_energy))
    text += str(eom.dissipation_function)
    assert "sqrt(r**2)" in text
    assert "sin(theta)**2" not in text and "cos(theta)**2" not in text


def test_the_elastic_pendulum_matches_its_hand_derivation() -> None:
    """Taylor, Classical Mechanics, problem 7.3 (the elastic pendulum), with a damper along
    the spring (Rayleigh F = c r_dot^2 / 2): for r > 0,
    m r'' = m r theta'^2 + m g cos(theta) - k (r - l0) - c r',
    m r^2 theta'' + 2 m r r' theta' + m g r sin(theta) = 0."""
    eom = lg.derive(lg.loads(MODEL))
    r, theta = eom.coordinates
    r_dot, theta_dot = eom.velocities
    r_ddot, theta_ddot = eom.accelerations
    m, k, l0, g, c = sp.symbols("m k l0 g c")
    positive = sp.Symbol("r", positive=True)
    hand = [
        m * r_ddot - m * r * theta_dot**2 - m * g * sp.cos(theta) + k * (r - l0) + c * r_dot,
        m * r**2 * theta_ddot + 2 * m * r * r_dot * theta_dot + m * g * r * sp.sin(theta),
    ]
    for derived, expected in zip(eom.equations, hand):
        difference = (derived - expected).subs(r, positive)
        assert sp.simplify(difference) == 0
