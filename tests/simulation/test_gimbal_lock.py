"""Euler angles at gimbal lock during a simulation: a start at the lock is refused, a motion
that reaches it stops there with an error naming the body, for every kind of integrator.

Reference: with gravity off and no spin, a top turned about its line of nodes keeps
theta_dot constant (phi_dot = psi_dot = 0 stay, theta_ddot = 0), so ZXZ angles reach the lock
sin(theta) = 1e-6 at t = (theta0 - asin(1e-6)) / |theta_dot|."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import SimulationError
from lagrangian.simulation.gimbal import TOLERANCE

THETA0, RATE = 0.3, -2.9
LOCK_TIME = (THETA0 - np.arcsin(TOLERANCE)) / abs(RATE)
TURNING = {"theta": THETA0, "theta_dot": RATE, "psi_dot": 0.0, "phi_dot": 0.0}
FREE = {"g": 0.0}  # no gravity: theta(t) = theta0 + theta_dot t


def test_a_top_released_at_the_lock_is_refused_before_integrating() -> None:
    with pytest.raises(
        SimulationError,
        match=r"body 'top': Euler angles ZXZ at gimbal lock \(theta = 0\) at the start, t = 0: "
        r"the mass matrix is singular there.*a quaternion",
    ):
        lg.simulate(lg.examples.heavy_symmetric_top(), {"theta": 0.0}, 1.0)


def test_a_top_turned_through_the_lock_stops_there_with_the_body_named() -> None:
    with pytest.raises(
        SimulationError,
        match=r"body 'top': Euler angles ZXZ at gimbal lock \(theta = 1e-06\) at t = 0\.103448; "
        r"use other angles .* Pass raise_on_failure=False",
    ):
        lg.simulate(lg.examples.heavy_symmetric_top(), TURNING, 1.0, parameters=FREE)


@pytest.mark.parametrize(
    ("method", "options", "precise"),
    [
        ("RK45", {}, True),
        ("Radau", {}, True),
        ("RK4", {"dt": 1e-3}, True),
        ("variational", {"dt": 1e-3}, False),  # no events: found on the output rows
        ("DOP853", {"backend": "numba", "samples": 1001}, False),
    ],
)
def test_the_failed_trajectory_ends_at_the_lock(method: str, options: dict, precise: bool) -> None:
    trajectory = lg.simulate(
        lg.examples.heavy_symmetric_top(),
        TURNING,
        1.0,
        parameters=FREE,
        method=method,
        raise_on_failure=False,
        **options,
    )
    assert trajectory.status == "failed"
    assert trajectory.message.startswith("body 'top': Euler angles ZXZ at gimbal lock (theta = ")
    if precise:  # the event is located on the step
        assert trajectory.t[-1] == pytest.approx(LOCK_TIME, abs=1e-9)
        assert trajectory["theta"][-1] == pytest.approx(np.arcsin(TOLERANCE), abs=1e-9)
        assert trajectory.events[-1].name == "gimbal_lock_top"
    else:  # the first output row at or past the lock
        assert LOCK_TIME <= trajectory.t[-1] < LOCK_TIME + 2e-3
    np.testing.assert_allclose(trajectory["theta"], THETA0 + RATE * trajectory.t, atol=1e-9)
    assert len(trajectory.energy) == len(trajectory.t)


def test_tait_bryan_angles_lock_at_a_right_angle() -> None:
    """XYZ angles of the hanging box lock at cos(b) = 0: swung hard about the y axis (gravity
    off) the box turns b through pi/2."""
    start = {"a": 0.0, "b": 1.4, "c": 0.0, "a_dot": 0.0, "b_dot": 2.0, "c_dot": 0.0}
    trajectory = lg.simulate(
        lg.examples.physical_pendulum_3d(),
        start,
        1.0,
        parameters={"g": 0.0},
        raise_on_failure=False,
    )
    assert trajectory.status == "failed"
    assert trajectory.message.startswith("body 'box': Euler angles XYZ at gimbal lock (b = 1.5708")
    expected = (np.arccos(TOLERANCE) - 1.4) / 2.0
    assert trajectory.t[-1] == pytest.approx(expected, abs=1e-9)


def test_motions_away_from_the_lock_are_not_disturbed() -> None:
    trajectory = lg.simulate(lg.examples.heavy_symmetric_top(), t_span=0.5, samples=11)
    assert trajectory.success and trajectory.events == ()
    assert trajectory.message == "The integration reached the end of the time span."


def test_a_disc_that_falls_flat_stops_at_the_lock_of_its_constrained_run() -> None:
    """The rolling disc (ZXY angles, velocity constraints) released leaning with no spin falls
    over; it stops where cos(theta) = 1e-6, its energy kept up to there."""
    start = dict.fromkeys(("x", "y", "psi", "phi", "x_dot", "y_dot", "psi_dot"), 0.0)
    start.update({"theta": -0.3, "theta_dot": 0.0, "phi_dot": 0.0})
    trajectory = lg.simulate(
        lg.examples.rolling_disc(), start, 3.0, raise_on_failure=False, baumgarte=(5.0, 5.0)
    )
    assert trajectory.message.startswith("body 'disc': Euler angles ZXY at gimbal lock")
    assert trajectory["theta"][-1] == pytest.approx(-np.arccos(TOLERANCE), abs=1e-9)
    assert trajectory.drift()["energy_relative"] < 1e-6
