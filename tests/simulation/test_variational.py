"""The variational integrator (midpoint rule, position-momentum form) without constraints:
bounded energy error where RK4 drifts, second-order convergence against exact solutions of
the free, damped and driven oscillators, the energy balance dE/dt = -2F of a damped pendulum,
and refusal of what it does not integrate."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.simulation import simulate

X, X_DOT, T = sp.symbols("x x_dot t")
M, K, B = 1.5, 4.0, 0.6  # mass, stiffness, damping coefficient
W0 = np.sqrt(K / M)


def _oscillator() -> lg.System:
    return lg.System(coordinates=[X], kinetic=X_DOT**2 / 2, potential=X**2 / 2)


def _damped_oscillator() -> lg.System:
    m, k, b = sp.symbols("m k b")
    return lg.System(
        coordinates=[X],
        parameters={m: M, k: K, b: B},
        kinetic=m * X_DOT**2 / 2,
        potential=k * X**2 / 2,
        dissipation=b * X_DOT**2 / 2,
    )


def _driven_oscillator(force: float, frequency: float) -> lg.System:
    m, k, f, w = sp.symbols("m k f w")
    return lg.System(
        coordinates=[X],
        parameters={m: M, k: K, f: force, w: frequency},
        kinetic=m * X_DOT**2 / 2,
        potential=k * X**2 / 2,
        generalized_forces={X: f * sp.cos(w * T)},
    )


def _relative_energy_error(trajectory: lg.simulate.Trajectory) -> np.ndarray:
    energy = trajectory.energy
    return np.abs(energy - energy[0]) / abs(energy[0])


def _quarters(error: np.ndarray) -> tuple[float, float]:
    quarter = len(error) // 4
    return float(error[1 : quarter + 1].max()), float(error[-quarter:].max())


def _halves(error: np.ndarray) -> tuple[float, float]:
    half = len(error) // 2
    return float(error[1:half].max()), float(error[half:].max())


def _order(errors: list[float]) -> list[float]:
    """Observed orders log2(e(dt) / e(dt/2)) of errors at halving steps."""
    return [float(np.log2(a / b)) for a, b in itertools.pairwise(errors)]


def test_oscillator_energy_bounded_while_rk4_drifts() -> None:
    dt, steps = 0.05, 2000
    initial = {"x": 1.0, "x_dot": 0.0}
    variational = simulate(_oscillator(), initial, steps * dt, method="variational", dt=dt)
    assert variational.method == "variational" and variational.success
    assert len(variational.t) == steps + 1
    error = _relative_energy_error(variational)
    first, last = _quarters(error)
    assert error.max() < dt**2
    # the midpoint rule keeps a quadratic energy exactly: what is left is rounding, which
    # may wander by a few ulps but does not drift
    assert last < 1.5 * first + 100 * np.finfo(float).eps
    rk4 = simulate(_oscillator(), initial, steps * dt, method="RK4", dt=dt)
    rk4_error = _relative_energy_error(rk4)
    rk4_first, rk4_last = _quarters(rk4_error)
    assert rk4_last > 2 * rk4_first
    assert np.all(np.diff(rk4_error[1:]) >= 0)  # RK4 loses energy at every step


def test_velocities_from_the_legendre_map() -> None:
    trajectory = simulate(
        _oscillator(), {"x": 0.0, "x_dot": 1.0}, 1.0, method="variational", dt=0.01
    )
    assert trajectory.q_dot[0, 0] == pytest.approx(1.0)
    np.testing.assert_allclose(trajectory["x_dot"], np.cos(trajectory.t), atol=1e-4)


def test_second_order_convergence() -> None:
    errors = []
    for dt in (0.1, 0.05, 0.025):
        trajectory = simulate(
            _oscillator(), {"x": 1.0, "x_dot": 0.0}, 5.0, method="variational", dt=dt
        )
        assert trajectory.t[-1] == pytest.approx(5.0)
        errors.append(abs(trajectory.q[-1, 0] - np.cos(5.0)))
    assert all(1.8 < order < 2.2 for order in _order(errors)), errors


def test_samples_on_the_step_grid() -> None:
    trajectory = simulate(
        _oscillator(), {"x": 1.0, "x_dot": 0.0}, 1.0, method="variational", dt=0.01, samples=11
    )
    np.testing.assert_allclose(trajectory.t, np.linspace(0.0, 1.0, 11))
    np.testing.assert_allclose(trajectory["x"], np.cos(trajectory.t), atol=1e-4)


def test_double_pendulum_energy_bounded_while_rk4_drifts() -> None:
    # Chaotic motion (theta = 1, phi = 0.5) for 1000 s, 20000 steps: the variational error
    # stays at its level of the first seconds, RK4's grows along the run.
    pendulum = lg.examples.double_pendulum()
    eom, dt, span = lg.derive(pendulum), 0.05, 1000.0
    variational = simulate(eom, pendulum.initial, span, method="variational", dt=dt, samples=2001)
    rk4 = simulate(eom, pendulum.initial, span, method="RK4", dt=dt, samples=2001)
    first, last = _halves(_relative_energy_error(variational))
    rk4_first, rk4_last = _halves(_relative_energy_error(rk4))
    assert variational.success and last < 1.5 * first
    assert rk4_last > 1.3 * rk4_first
    assert rk4_last > 5 * max(first, last)


def test_double_pendulum_energy_error_is_of_second_order() -> None:
    pendulum = lg.examples.double_pendulum()
    eom = lg.derive(pendulum)
    worst = []
    for dt in (0.01, 0.005):
        steps = round(5.0 / dt)
        run = simulate(eom, pendulum.initial, 5.0, method="variational", samples=steps + 1)
        worst.append(float(_relative_energy_error(run).max()))
    assert worst[0] < 1e-4
    assert 3.0 < worst[0] / worst[1] < 5.0, worst


def _damped_exact(t: np.ndarray) -> np.ndarray:
    """x(t) of m x'' + b x' + k x = 0 from x = 1, x' = 0 (underdamped)."""
    decay = B / (2 * M)
    w = np.sqrt(W0**2 - decay**2)
    return np.exp(-decay * t) * (np.cos(w * t) + decay / w * np.sin(w * t))


def test_damped_oscillator_converges_to_the_exact_solution_at_second_order() -> None:
    errors = []
    for dt in (0.1, 0.05, 0.025):
        run = simulate(
            _damped_oscillator(), {"x": 1.0, "x_dot": 0.0}, 10.0, method="variational", dt=dt
        )
        errors.append(float(np.max(np.abs(run["x"] - _damped_exact(run.t)))))
    assert errors[-1] < 1e-3
    assert all(1.9 < order < 2.1 for order in _order(errors)), errors


def test_damped_pendulum_loses_energy_at_the_rate_of_twice_the_dissipation() -> None:
    # A nonlinear system with F = c theta_dot^2 / 2: dE/dt = -theta_dot dF/dtheta_dot = -2F.
    theta_dot, c = sp.symbols("theta_dot c")
    pendulum = lg.examples.simple_pendulum().replace(
        parameters={**lg.examples.simple_pendulum().parameters, c: 0.4},
        dissipation=c * theta_dot**2 / 2,
    )
    mismatch = []
    for steps in (250, 500):  # every step an output (the model file asks for 1000 samples)
        run = simulate(pendulum, {"theta": 2.0}, 5.0, method="variational", samples=steps + 1)
        rate = np.gradient(run.energy, run.t)[1:-1]  # central differences, O(dt^2)
        twice_dissipation = 0.4 * run["theta_dot"][1:-1] ** 2
        mismatch.append(float(np.max(np.abs(rate + twice_dissipation))))
        assert run.energy[-1] < 0.5 * run.energy[0]  # it does lose energy
    assert mismatch[0] < 0.02 * np.max(twice_dissipation)
    assert 3.5 < mismatch[0] / mismatch[1] < 4.5, mismatch


def test_driven_oscillator_converges_to_the_exact_solution_at_second_order() -> None:
    force, frequency, x0, v0 = 0.7, 1.3, 0.2, 0.1
    steady = force / (M * (W0**2 - frequency**2))  # amplitude of the driven response

    def exact(t: np.ndarray) -> np.ndarray:
        free = (x0 - steady) * np.cos(W0 * t) + v0 / W0 * np.sin(W0 * t)
        return free + steady * np.cos(frequency * t)

    system = _driven_oscillator(force, frequency)
    errors = []
    for dt in (0.1, 0.05, 0.025):
        run = simulate(system, {"x": x0, "x_dot": v0}, 10.0, method="variational", dt=dt)
        errors.append(float(np.max(np.abs(run["x"] - exact(run.t)))))
    assert errors[-1] < 1e-3
    assert all(1.9 < order < 2.1 for order in _order(errors)), errors


def test_forces_at_points_match_the_multiplier_free_reference() -> None:
    # mass_spring_damper: spring, damper, gravity and a force f at the mass (virtual work)
    system = lg.examples.mass_spring_damper()
    values = {"f": 3.0, "B": 1.2}
    reference = simulate(
        system, t_span=3.0, parameters=values, samples=31, method="DOP853", rtol=1e-12, atol=1e-12
    )
    run = simulate(
        system, t_span=3.0, parameters=values, samples=31, method="variational", dt=0.005
    )
    scale = np.max(np.abs(reference["x"]))
    assert np.max(np.abs(run["x"] - reference["x"])) < 1e-3 * scale


def test_needs_a_step() -> None:
    with pytest.raises(lg.SimulationError, match="the fixed-step method variational needs a step"):
        simulate(_oscillator(), {"x": 1.0, "x_dot": 0.0}, 1.0, method="variational")


def test_refuses_events() -> None:
    def crossing(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(q[0])

    with pytest.raises(lg.SimulationError, match="does not locate events"):
        simulate(_oscillator(), {"x": 1.0}, 1.0, method="variational", dt=0.01, events=[crossing])


def test_refuses_a_coordinate_without_inertia() -> None:
    with pytest.raises(lg.SimulationError, match="needs every coordinate to have inertia"):
        simulate(lg.examples.rc_rl_circuit(), t_span=1.0, method="variational", dt=0.01)


def test_a_lagrangian_not_quadratic_in_the_velocities() -> None:
    # Relativistic oscillator L = -m c^2 sqrt(1 - v^2/c^2) - x^2/2: p = m gamma v is not
    # linear in v, so the velocity comes from Newton's method on the Legendre map.
    mass, light = sp.symbols("m c")
    relativistic = lg.System(
        coordinates=[X],
        parameters={mass: 1.0, light: 2.0},
        lagrangian=-mass * light**2 * sp.sqrt(1 - X_DOT**2 / light**2) - X**2 / 2,
    )
    times = np.linspace(0.0, 10.0, 11)
    start = {"x": 3.0, "x_dot": 0.0}
    reference = simulate(
        relativistic, start, 10.0, t_eval=times, method="DOP853", rtol=1e-12, atol=1e-12
    )
    assert np.max(np.abs(reference["x_dot"])) > 0.8 * 2.0  # fast: gamma well above 1
    errors = []
    for dt in (0.02, 0.01, 0.005):
        run = simulate(relativistic, start, 10.0, method="variational", dt=dt, t_eval=times)
        errors.append(float(np.max(np.abs(run["x_dot"] - reference["x_dot"]))))
    assert all(1.9 < order < 2.1 for order in _order(errors)), errors
    long = simulate(relativistic, start, 500.0, method="variational", dt=0.05, samples=1001)
    assert long.energy_function is not None  # h = m c^2 gamma + x^2/2, not T + V
    first, last = _halves(np.abs(long.energy_function / long.energy_function[0] - 1))
    assert max(first, last) < 1e-4 and last < 1.5 * first
