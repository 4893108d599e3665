"""A vertical disc rolling without slipping on a plane (non-holonomic), simulated with
multipliers: with no torque its energy is conserved and the rolling conditions hold along the
motion; the contact point runs on a circle when the heading turns steadily (textbook: the
disc's path has radius r phi_dot / theta_dot)."""

from __future__ import annotations

import numpy as np
import sympy as sp

import lagrangian as lg

x, y, theta, phi, m, r = sp.symbols("x y theta phi m r")
x_dot, y_dot, theta_dot, phi_dot = sp.symbols("x_dot y_dot theta_dot phi_dot")
J_heading, J_spin = sp.symbols("J_heading J_spin")


def rolling_disc() -> lg.System:
    return lg.System(
        coordinates=[x, y, theta, phi],
        parameters={m: 1.5, r: 0.3, J_heading: 0.04, J_spin: 0.07},
        kinetic=m * (x_dot**2 + y_dot**2) / 2
        + J_heading * theta_dot**2 / 2
        + J_spin * phi_dot**2 / 2,
        constraints=[
            lg.VelocityConstraint(x_dot - r * phi_dot * sp.cos(theta), "roll x"),
            lg.VelocityConstraint(y_dot - r * phi_dot * sp.sin(theta), "roll y"),
        ],
        # rolling at phi_dot = 2 (contact speed r phi_dot = 0.6) while turning at theta_dot = 0.5
        initial={
            x: 0.0,
            y: 0.0,
            theta: 0.0,
            phi: 0.0,
            x_dot: 0.6,
            y_dot: 0.0,
            theta_dot: 0.5,
            phi_dot: 2.0,
        },
    )


def test_energy_and_rolling_conditions_hold_along_the_motion() -> None:
    trajectory = lg.simulate(
        rolling_disc(),
        t_span=10.0,
        method="DOP853",
        rtol=1e-10,
        atol=1e-10,
        samples=400,
        baumgarte=(5.0, 5.0),
    )
    assert trajectory.status == "success"
    drift = trajectory.drift()
    assert drift["energy_relative"] < 1e-8
    assert drift["constraint_residual_max"] < 1e-8
    # steady turning: the contact point moves on a circle of radius r phi_dot / theta_dot
    radius = 0.3 * 2.0 / 0.5
    center = np.array([0.0, radius])
    points = np.column_stack([trajectory["x"], trajectory["y"]])
    np.testing.assert_allclose(np.linalg.norm(points - center, axis=1), radius, rtol=1e-7)
