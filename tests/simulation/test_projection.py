"""Drift control by projection after every step (simulate(..., project_steps=True)), against
the angle form of the pendulum, the drift of the plain index-1 form, and a rolling constraint
on velocities only."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from test_constrained import L, cartesian_pendulum, start

import lagrangian as lg
from lagrangian.errors import SimulationError

TIMES = np.linspace(0.0, 10.0, 401)


def test_projection_holds_the_rod_where_the_plain_form_drifts() -> None:
    plain = lg.simulate(cartesian_pendulum(), start(1.0), 10.0, t_eval=TIMES)
    projected = lg.simulate(
        cartesian_pendulum(), start(1.0), 10.0, t_eval=TIMES, project_steps=True
    )
    drifted = plain.drift()["constraint_residual_max"]
    held = projected.drift()["constraint_residual_max"]
    assert drifted is not None and held is not None
    assert drifted > 1e-7  # RK45 at its default tolerances leaves the circle ...
    assert held < 1e-11  # ... and projected (steps and interpolated rows) it stays on it
    np.testing.assert_allclose(np.hypot(projected["x"], projected["y"]), L, atol=1e-11)


def test_the_projected_pendulum_moves_like_the_angle_form() -> None:
    theta, m, g, l = sp.symbols("theta m g l")
    angle_form = lg.System(
        coordinates=[theta],
        parameters={m: 2.0, g: 9.81, l: L},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (l * sp.sin(theta), -l * sp.cos(theta)))],
    )
    tight = {"method": "DOP853", "rtol": 1e-11, "atol": 1e-12}
    reference = lg.simulate(
        angle_form, {"theta": 1.0, "theta_dot": 0.0}, 10.0, t_eval=TIMES, **tight
    )
    for method in ("RK45", "RK4"):
        options = {"dt": 1e-3} if method == "RK4" else {"rtol": 1e-9, "atol": 1e-10}
        run = lg.simulate(
            cartesian_pendulum(),
            start(1.0),
            10.0,
            t_eval=TIMES,
            method=method,
            project_steps=True,
            **options,
        )
        angle = np.arctan2(run["x"], -run["y"])
        assert np.max(np.abs(angle - reference["theta"])) < 1e-6, method


def test_projection_onto_a_velocity_constraint() -> None:
    """A knife edge: the blade condition x_dot sin(phi) = y_dot cos(phi) at every row."""
    x, y, phi = sp.symbols("x y phi")
    x_dot, y_dot, phi_dot = sp.symbols("x_dot y_dot phi_dot")
    skate = lg.System(
        coordinates=[x, y, phi],
        kinetic=(x_dot**2 + y_dot**2) / 2 + phi_dot**2 / 10,
        constraints=[lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi))],
    )
    start_state = {"x": 0, "y": 0, "phi": 0.3, "x_dot": 2 * np.cos(0.3), "y_dot": 2 * np.sin(0.3)}
    run = lg.simulate(skate, {**start_state, "phi_dot": 1.0}, 5.0, samples=101, project_steps=True)
    blade = run["x_dot"] * np.sin(run["phi"]) - run["y_dot"] * np.cos(run["phi"])
    assert np.max(np.abs(blade)) < 1e-12
    np.testing.assert_allclose(np.hypot(run["x_dot"], run["y_dot"]), 2.0, rtol=1e-6)


def test_projection_is_refused_where_it_does_not_apply() -> None:
    with pytest.raises(SimulationError, match=r"project_steps works with the methods .* not Radau"):
        lg.simulate(cartesian_pendulum(), start(), 1.0, method="Radau", project_steps=True)
    x, y = sp.symbols("x y")
    bead = lg.System(
        coordinates=[x, y],
        parameters={sp.Symbol("g"): 9.81},
        gravity=(0, -sp.Symbol("g")),
        particles=[lg.Particle("bead", 1, (x, y))],
        constraints=[lg.Unilateral(x**2 + y**2 - 1)],
    )
    top = {"x": 0.0, "y": 1.0, "x_dot": 0.1, "y_dot": 0.0}
    with pytest.raises(SimulationError, match="project_steps does not apply to unilateral"):
        lg.simulate(bead, top, 1.0, project_steps=True)
