"""The variational integrator (midpoint rule, position-momentum form): bounded energy error
where RK4 drifts, second-order convergence, and refusal of what it does not integrate."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.simulate import simulate


def _oscillator() -> lg.System:
    x, x_dot = sp.symbols("x x_dot")
    return lg.System(coordinates=[x], kinetic=x_dot**2 / 2, potential=x**2 / 2)


def _relative_energy_error(trajectory: lg.simulate.Trajectory) -> np.ndarray:
    energy = trajectory.energy
    return np.abs(energy - energy[0]) / abs(energy[0])


def _quarters(error: np.ndarray) -> tuple[float, float]:
    quarter = len(error) // 4
    return float(error[1 : quarter + 1].max()), float(error[-quarter:].max())


def test_oscillator_energy_bounded_while_rk4_drifts() -> None:
    dt, steps = 0.05, 2000
    initial = {"x": 1.0, "x_dot": 0.0}
    variational = simulate(_oscillator(), initial, steps * dt, method="variational", dt=dt)
    assert variational.method == "variational" and variational.success
    assert len(variational.t) == steps + 1
    error = _relative_energy_error(variational)
    first, last = _quarters(error)
    assert error.max() < dt**2
    assert last < 1.5 * first
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
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(3.5 < ratio < 4.5 for ratio in ratios), ratios


def test_samples_on_the_step_grid() -> None:
    trajectory = simulate(
        _oscillator(), {"x": 1.0, "x_dot": 0.0}, 1.0, method="variational", dt=0.01, samples=11
    )
    np.testing.assert_allclose(trajectory.t, np.linspace(0.0, 1.0, 11))
    np.testing.assert_allclose(trajectory["x"], np.cos(trajectory.t), atol=1e-4)


def test_double_pendulum_energy_bounded() -> None:
    trajectory = simulate(
        lg.examples.double_pendulum(), t_span=10.0, method="variational", dt=0.005
    )
    error = _relative_energy_error(trajectory)
    first, last = _quarters(error)
    assert error.max() < 1e-3
    assert last <= 2 * first


def test_refuses_a_damped_system() -> None:
    with pytest.raises(lg.SimulationError, match=r"conservative systems only.*dissipation"):
        simulate(lg.examples.mass_spring_damper(), t_span=1.0, method="variational", dt=0.01)


def test_needs_a_step() -> None:
    with pytest.raises(lg.SimulationError, match="the fixed-step method variational needs a step"):
        simulate(_oscillator(), {"x": 1.0, "x_dot": 0.0}, 1.0, method="variational")


def test_refuses_a_constrained_system() -> None:
    x, y, l = sp.symbols("x y l")
    pendulum = lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        particles=[lg.Particle("bob", 1, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
    )
    with pytest.raises(lg.SimulationError, match="constrained systems is not implemented yet"):
        simulate(pendulum, {"x": 1.0, "y": 0.0}, 1.0, method="variational", dt=0.01)
