"""The variational integrator with holonomic constraints: the constraints hold to rounding at
every step, positions and multipliers converge at second order to the angle form integrated
by DOP853 (the rod tension m g cos(theta) + m l theta_dot^2 for the multiplier), the energy
error of the Cartesian double pendulum stays bounded, and the results agree with the
multiplier form of :mod:`lagrangian.simulation.constrained_run`."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationError
from lagrangian.model.constraints import Constraint
from lagrangian.simulation import Trajectory, simulate

L, G, M = 1.5, 9.81, 2.0
TIGHT = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12}
TIMES = np.linspace(0.0, 2.0, 21)
STEPS = (0.02, 0.01, 0.005)


def cartesian_pendulum(
    *constraints: Constraint,
    dissipation: sp.Expr | int = 0,
    parameters: dict[sp.Symbol, float] | None = None,
) -> lg.System:
    """A bob on a rod of length L (or on ``constraints``), with extra ``parameters``."""
    x, y, m, g, l = sp.symbols("x y m g l")
    return lg.System(
        coordinates=[x, y],
        parameters={m: M, g: G, l: L, **(parameters or {})},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=constraints or [lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
        dissipation=dissipation,
    )


def on_the_circle(theta: float, omega: float) -> dict[str, float]:
    """The Cartesian state of the pendulum at angle theta, angular velocity omega."""
    return {
        "x": L * np.sin(theta),
        "y": -L * np.cos(theta),
        "x_dot": L * np.cos(theta) * omega,
        "y_dot": L * np.sin(theta) * omega,
    }


def angle_form(theta: float, omega: float, system: lg.System | None = None) -> Trajectory:
    """The same pendulum in its angle, integrated by DOP853 at tight tolerances."""
    return simulate(
        system or lg.examples.simple_pendulum(),
        {"theta": theta, "theta_dot": omega},
        (0.0, 2.0),
        parameters={"m": M, "g": G, "l": L},
        t_eval=TIMES,
        **TIGHT,
    )


def _orders(errors: list[float]) -> list[float]:
    return [float(np.log2(a / b)) for a, b in itertools.pairwise(errors)]


def cartesian_double_pendulum() -> lg.System:
    x1, y1, x2, y2, m1, m2, l1, l2, g = sp.symbols("x1 y1 x2 y2 m1 m2 l1 l2 g")
    return lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob1", m1, (x1, y1)), lg.Particle("bob2", m2, (x2, y2))],
        constraints=[
            lg.Holonomic(x1**2 + y1**2 - l1**2, name="upper rod"),
            lg.Holonomic((x2 - x1) ** 2 + (y2 - y1) ** 2 - l2**2, name="lower rod"),
        ],
    )


def double_start(theta: float = 1.0, phi: float = 0.5) -> dict[str, float]:
    """At rest at the angles of lg.examples.double_pendulum (unit rods)."""
    x1, y1 = np.sin(theta), -np.cos(theta)
    state = {"x1": x1, "y1": y1, "x2": x1 + np.sin(phi), "y2": y1 - np.cos(phi)}
    return state | {name + "_dot": 0.0 for name in list(state)}


def test_the_rod_holds_at_every_step_in_position_and_velocity() -> None:
    run = simulate(
        cartesian_pendulum(), on_the_circle(1.2, 0.8), 5.0, method="variational", dt=0.01
    )
    assert run.success and len(run.t) == 501
    assert run.constraint_residual is not None
    assert np.max(run.constraint_residual) <= 1e-10
    np.testing.assert_allclose(np.hypot(run["x"], run["y"]), L, rtol=0, atol=1e-12)
    radial = run["x"] * run["x_dot"] + run["y"] * run["y_dot"]  # h_dot / 2
    assert np.max(np.abs(radial)) <= 1e-10
    assert run.names == ("t", "x", "y", "x_dot", "y_dot", "lambda_1", "energy")


def test_positions_converge_at_second_order_to_the_angle_form() -> None:
    theta0, omega0 = 0.5, 0.4
    reference = angle_form(theta0, omega0)
    errors = []
    for dt in STEPS:
        run = simulate(
            cartesian_pendulum(),
            on_the_circle(theta0, omega0),
            2.0,
            method="variational",
            dt=dt,
            t_eval=TIMES,
        )
        x_error = np.abs(run["x"] - L * np.sin(reference["theta"]))
        y_error = np.abs(run["y"] + L * np.cos(reference["theta"]))
        errors.append(float(max(x_error.max(), y_error.max())))
    assert errors[-1] < 1e-4
    assert all(1.9 < order < 2.1 for order in _orders(errors)), errors


def test_the_multiplier_is_the_rod_tension_to_second_order() -> None:
    theta0, omega0 = 0.5, 0.4
    reference = angle_form(theta0, omega0)
    theta, omega = reference["theta"], reference["theta_dot"]
    tension = M * G * np.cos(theta) + M * L * omega**2
    errors = []
    for dt in STEPS:
        run = simulate(
            cartesian_pendulum(),
            on_the_circle(theta0, omega0),
            2.0,
            method="variational",
            dt=dt,
            t_eval=TIMES,
        )
        lam = run["lambda_1"]
        # lambda dh/dq = lambda (2x, 2y) is the rod force, |F| = 2 |lambda| l, pulling inwards
        assert np.all(lam < 0)
        errors.append(float(np.max(np.abs(2 * np.abs(lam) * L - tension))))
    assert errors[-1] < 1e-3 * np.max(tension)
    assert all(1.8 < order < 2.2 for order in _orders(errors)), errors


def test_a_moving_pivot_rheonomic_rod_against_the_angle_form() -> None:
    x, y, l, x0, w, t = sp.symbols("x y l x0 omega t")
    a, frequency, theta0 = 0.1, 2.0, 0.2
    pendulum = cartesian_pendulum(
        lg.Holonomic((x - x0 * sp.cos(w * t)) ** 2 + y**2 - l**2, name="rod"),
        parameters={x0: a, w: frequency},
    )
    moving = lg.examples.moving_pivot_pendulum()
    reference = simulate(
        moving,
        {"theta": theta0, "theta_dot": 0.0},
        2.0,
        t_eval=TIMES,
        parameters={"m": M, "g": G, "l": L, "x0": a, "omega": frequency},
        **TIGHT,
    )
    start = {"x": L * np.sin(theta0) + a, "y": -L * np.cos(theta0), "x_dot": 0.0, "y_dot": 0.0}
    errors = []
    for dt in STEPS:
        run = simulate(pendulum, start, 2.0, method="variational", dt=dt, t_eval=TIMES)
        assert run.constraint_residual is not None
        assert np.max(run.constraint_residual) <= 1e-10
        pivot = a * np.cos(frequency * TIMES)
        errors.append(float(np.max(np.abs(run["x"] - pivot - L * np.sin(reference["theta"])))))
    assert errors[-1] < 1e-4
    assert all(1.8 < order < 2.2 for order in _orders(errors)), errors


def test_a_damped_rod_against_the_damped_angle_form() -> None:
    # F = c (x_dot^2 + y_dot^2) / 2 is c l^2 theta_dot^2 / 2 in the angle
    x_dot, y_dot, c, theta_dot = sp.symbols("x_dot y_dot c theta_dot")
    pendulum = cartesian_pendulum(dissipation=c * (x_dot**2 + y_dot**2) / 2, parameters={c: 0.8})
    simple = lg.examples.simple_pendulum()
    damped = simple.replace(
        parameters={**simple.parameters, c: 0.8},
        dissipation=c * sp.Symbol("l") ** 2 * theta_dot**2 / 2,
    )
    reference = angle_form(1.0, 0.0, damped)
    errors = []
    for dt in STEPS:
        run = simulate(
            pendulum, on_the_circle(1.0, 0.0), 2.0, method="variational", dt=dt, t_eval=TIMES
        )
        errors.append(float(np.max(np.abs(run["x"] - L * np.sin(reference["theta"])))))
        assert run.energy[-1] < 0.8 * run.energy[0] - 0.2 * M * G * L  # energy is lost
    assert all(1.8 < order < 2.2 for order in _orders(errors)), errors


def test_the_double_pendulum_rods_hold_and_its_energy_does_not_drift() -> None:
    run = simulate(
        cartesian_double_pendulum(),
        double_start(),
        200.0,
        method="variational",
        dt=0.02,
        samples=2001,
    )
    assert run.success and run.constraint_residual is not None
    assert np.max(run.constraint_residual) <= 1e-10
    energy = np.abs(run.energy - run.energy[0]) / abs(run.energy[0])
    half = len(energy) // 2
    first, last = energy[1:half].max(), energy[half:].max()
    assert max(first, last) < 5e-3
    assert last < 1.5 * first


def test_the_double_pendulum_agrees_with_the_angle_form_and_the_multiplier_form() -> None:
    system = cartesian_double_pendulum()
    angles = simulate(lg.examples.double_pendulum(), t_span=2.0, t_eval=TIMES, **TIGHT)
    multiplier_form = simulate(
        system, double_start(), 2.0, t_eval=TIMES, baumgarte=(10, 10), **TIGHT
    )
    x2 = np.sin(angles["theta"]) + np.sin(angles["phi"])
    assert np.max(np.abs(multiplier_form["x2"] - x2)) < 1e-9
    position_errors, multiplier_errors = [], []
    for dt in STEPS:
        run = simulate(system, double_start(), 2.0, method="variational", dt=dt, t_eval=TIMES)
        assert run.multiplier_names == multiplier_form.multiplier_names == ("lambda_1", "lambda_2")
        assert run.multipliers is not None and multiplier_form.multipliers is not None
        position_errors.append(float(np.max(np.abs(run["x2"] - x2))))
        multiplier_errors.append(
            float(np.max(np.abs(run.multipliers - multiplier_form.multipliers)))
        )
    assert position_errors[-1] < 1e-3 and multiplier_errors[-1] < 1e-2
    assert all(1.9 < order < 2.1 for order in _orders(position_errors)), position_errors
    assert all(1.8 < order < 2.2 for order in _orders(multiplier_errors)), multiplier_errors


def test_an_initial_state_off_the_rod_is_refused_or_projected() -> None:
    off = {"x": 1.0, "y": -1.0, "x_dot": 0.0, "y_dot": 0.0}
    with pytest.raises(SimulationError, match=r"residual.*project_initial=True"):
        simulate(cartesian_pendulum(), off, 0.1, method="variational", dt=0.01)
    run = simulate(
        cartesian_pendulum(), off, 0.1, method="variational", dt=0.01, project_initial=True
    )
    np.testing.assert_allclose(np.hypot(run["x"], run["y"]), L, atol=1e-12)


def test_a_velocity_constraint_is_refused_by_name() -> None:
    x_dot, y_dot = sp.symbols("x_dot y_dot")
    sliding = cartesian_pendulum(lg.VelocityConstraint(x_dot - y_dot, name="rail"))
    with pytest.raises(SimulationError, match=r"'rail'.*not holonomic.*another method"):
        simulate(sliding, on_the_circle(0.3, 0.0), 1.0, method="variational", dt=0.01)


def test_a_unilateral_constraint_is_refused_by_name() -> None:
    x, y, l = sp.symbols("x y l")
    string = cartesian_pendulum(lg.Unilateral(l**2 - x**2 - y**2, name="string"))
    with pytest.raises(SimulationError, match=r"'string'.*unilateral.*another method"):
        simulate(string, on_the_circle(0.3, 0.0), 1.0, method="variational", dt=0.01)


def test_a_failed_step_keeps_the_trajectory_computed_before_it() -> None:
    # A step far too long for the rod: Newton's method finds no position on the circle.
    run = simulate(
        cartesian_pendulum(),
        on_the_circle(0.5, 30.0),
        1.0,
        method="variational",
        dt=0.5,
        raise_on_failure=False,
    )
    assert run.status == "failed" and "try a smaller dt" in run.message
    assert len(run.t) >= 1 and run.t[0] == 0.0


def test_a_bead_on_a_vertical_wire_falls_freely() -> None:
    # h = x holds at x = 0 (a constraint whose residual has no size to compare with); the
    # midpoint rule is exact for the uniform fall y = -g t^2 / 2, and the wire pushes nothing.
    x, y, m, g = sp.symbols("x y m g")
    bead = lg.System(
        coordinates=[x, y],
        parameters={m: M, g: G},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Holonomic(x, name="wire")],
    )
    start = {"x": 0.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
    run = simulate(bead, start, 1.0, method="variational", dt=0.1)
    np.testing.assert_allclose(run["y"], -G * run.t**2 / 2, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(run["y_dot"], -G * run.t, rtol=1e-12, atol=1e-12)
    assert np.all(run["x"] == 0.0) and np.allclose(run["lambda_1"], 0.0, atol=1e-12)
