"""Simulation of constrained systems in the multiplier form, against independent references:
the Cartesian pendulum against the angle form, the rod tension against m g cos(theta) +
m l theta_dot^2, and the free knife edge's energy and blade condition."""

from __future__ import annotations

import io

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationError
from lagrangian.model.constraints import Constraint
from lagrangian.simulation.trajectory import Trajectory

THETA0, L, G, M = 0.5, 1.5, 9.81, 2.0
TIMES = np.linspace(0.0, 2.0, 201)
TIGHT = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}


def cartesian_pendulum(*constraints: Constraint) -> lg.System:
    x, y, m, g, l = sp.symbols("x y m g l")
    return lg.System(
        coordinates=[x, y],
        parameters={m: M, g: G, l: L},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=constraints or [lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
    )


def start(theta: float = THETA0) -> dict[str, float]:
    return {"x": L * np.sin(theta), "y": -L * np.cos(theta), "x_dot": 0.0, "y_dot": 0.0}


@pytest.fixture(scope="module")
def angle_run() -> Trajectory:
    return lg.simulate(
        lg.examples.simple_pendulum(),
        {"theta": THETA0, "theta_dot": 0.0},
        2.0,
        parameters={"m": M, "g": G, "l": L},
        t_eval=TIMES,
        **TIGHT,
    )


@pytest.fixture(scope="module")
def cartesian_run() -> Trajectory:
    return lg.simulate(
        cartesian_pendulum(), start(), 2.0, t_eval=TIMES, baumgarte=(10.0, 10.0), **TIGHT
    )


def test_the_cartesian_pendulum_moves_like_the_angle_form(
    angle_run: Trajectory, cartesian_run: Trajectory
) -> None:
    theta = angle_run["theta"]
    assert cartesian_run.success and angle_run.success
    assert np.max(np.abs(cartesian_run["x"] - L * np.sin(theta))) < 1e-6
    assert np.max(np.abs(cartesian_run["y"] + L * np.cos(theta))) < 1e-6
    assert cartesian_run.drift()["energy_relative"] < 1e-7


def test_the_multiplier_is_the_rod_tension(
    angle_run: Trajectory, cartesian_run: Trajectory
) -> None:
    theta, omega = angle_run["theta"], angle_run["theta_dot"]
    tension = M * G * np.cos(theta) + M * L * omega**2
    # lambda dh/dq = lambda (2x, 2y) is the rod force, |F| = 2 |lambda| l, pulling inwards
    lam = cartesian_run["lambda_1"]
    assert np.all(lam < 0)
    np.testing.assert_allclose(2 * np.abs(lam) * L, tension, rtol=1e-6, atol=1e-6)


def test_the_trajectory_carries_multipliers_and_residuals(cartesian_run: Trajectory) -> None:
    assert cartesian_run.multiplier_names == ("lambda_1",)
    assert cartesian_run.names == ("t", "x", "y", "x_dot", "y_dot", "lambda_1", "energy")
    assert cartesian_run.multipliers is not None and cartesian_run.multipliers.shape == (201, 1)
    assert cartesian_run.constraint_residual is not None
    assert cartesian_run.constraint_residual.shape == (201,)
    buffer = io.StringIO()
    cartesian_run.to_csv(buffer)
    buffer.seek(0)
    back = Trajectory.from_csv(buffer)
    assert back.multiplier_names == ("lambda_1",)
    np.testing.assert_array_equal(back["lambda_1"], cartesian_run["lambda_1"])


def test_baumgarte_keeps_the_residual_small_and_drift_grows_without_it() -> None:
    # RK45 at its default tolerances: the index-1 form drifts off the circle
    stabilized = lg.simulate(cartesian_pendulum(), start(1.0), 10.0, baumgarte=(10, 10))
    plain = lg.simulate(cartesian_pendulum(), start(1.0), 10.0, samples=201)
    kept = stabilized.drift()["constraint_residual_max"]
    drifted = plain.drift()["constraint_residual_max"]
    assert kept is not None and drifted is not None
    assert kept < 1e-6
    assert drifted > 5 * kept
    assert plain.constraint_residual is not None
    residual = plain.constraint_residual
    assert residual[-1] > 5 * residual[20]  # the drift grows along the run


def test_the_tight_stabilized_run_stays_on_the_circle(cartesian_run: Trajectory) -> None:
    kept = cartesian_run.drift()["constraint_residual_max"]
    assert kept is not None and kept < 1e-8
    np.testing.assert_allclose(np.hypot(cartesian_run["x"], cartesian_run["y"]), L, atol=1e-8)


def test_the_free_knife_edge_keeps_its_energy_and_its_blade_condition() -> None:
    x, y, phi, m, inertia = sp.symbols("x y phi m I")
    x_dot, y_dot, phi_dot = sp.symbols("x_dot y_dot phi_dot")
    blade = x_dot * sp.sin(phi) - y_dot * sp.cos(phi)
    skate = lg.System(
        coordinates=[x, y, phi],
        parameters={m: 1.5, inertia: 0.2},
        kinetic=m / 2 * (x_dot**2 + y_dot**2) + inertia / 2 * phi_dot**2,
        constraints=[lg.VelocityConstraint(blade, name="blade")],
    )
    speed, heading = 2.0, 0.3
    initial = {
        "x": 0.0,
        "y": 0.0,
        "phi": heading,
        "x_dot": speed * np.cos(heading),
        "y_dot": speed * np.sin(heading),
        "phi_dot": 1.0,
    }
    run = lg.simulate(skate, initial, 3.0, samples=301, **TIGHT)
    assert run.success
    assert run.drift()["energy_relative"] < 1e-8
    assert run.constraint_residual is not None and np.max(run.constraint_residual) < 1e-8
    velocity = np.hypot(run["x_dot"], run["y_dot"])
    np.testing.assert_allclose(velocity, speed, rtol=1e-8)  # the blade does no work


def test_an_initial_state_off_the_constraints_is_refused_or_projected() -> None:
    off = {"x": 1.0, "y": -1.0, "x_dot": 0.0, "y_dot": 0.0}
    with pytest.raises(SimulationError, match="residual") as error:
        lg.simulate(cartesian_pendulum(), off, 0.1)
    assert "pass project_initial=True" in str(error.value)
    run = lg.simulate(cartesian_pendulum(), off, 0.1, samples=3, project_initial=True)
    radius = np.hypot(run["x"], run["y"])
    np.testing.assert_allclose(radius, L, atol=1e-6)


def test_a_velocity_violation_is_refused() -> None:
    moving = {**start(), "x_dot": np.cos(THETA0), "y_dot": np.sin(THETA0) + 0.1}
    with pytest.raises(SimulationError, match="residual"):
        lg.simulate(cartesian_pendulum(), moving, 0.1)


def test_a_taut_string_stays_active_like_a_rod() -> None:
    x, y, l = sp.symbols("x y l")
    string = cartesian_pendulum(lg.Unilateral(l**2 - x**2 - y**2, name="string"))
    run = lg.simulate(string, start(), 0.5, samples=11, **TIGHT)
    assert run.success and run.events == ()
    assert np.all(run["lambda_1"] > 0)  # the tension pulls the bob in: g = l^2 - r^2 grows


def test_bad_baumgarte_parameters_are_refused() -> None:
    with pytest.raises(SimulationError, match="baumgarte"):
        lg.simulate(cartesian_pendulum(), start(), 0.1, baumgarte=(-1.0, 1.0))
