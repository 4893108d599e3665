"""The action and Hamilton's principle (seed 003) against closed forms: the free particle's
straight line, the parabola under uniform gravity, the oscillator's sin(w t)/sin(w T), the
small-oscillation pendulum's action by quad, a shooting cross-check with simulate, and the
stationarity of A(q + eps eta) at eps = 0 on the true path only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

import lagrangian as lg
from lagrangian.render.action_plot import plot_action_variation
from lagrangian.simulation import Trajectory, action, action_variation, simulate, stationary_path

G, M = 9.81, 1.0  # the defaults of lagrangian.examples.simple_pendulum (l = 1)
OMEGA = np.sqrt(G)


def _free_particle() -> lg.System:
    x, x_dot, m = sp.symbols("x x_dot m")
    return lg.System(coordinates=[x], parameters={m: 3.0}, kinetic=m * x_dot**2 / 2)


def _gravity() -> lg.System:
    z, z_dot, m, g = sp.symbols("z z_dot m g")
    return lg.System(
        coordinates=[z], parameters={m: 2.0, g: 9.81}, kinetic=m * z_dot**2 / 2, potential=m * g * z
    )


def _oscillator() -> lg.System:
    x, x_dot, k = sp.symbols("x x_dot k")
    return lg.System(
        coordinates=[x], parameters={k: 1.0}, kinetic=x_dot**2 / 2, potential=k * x**2 / 2
    )


@pytest.fixture(scope="module")
def pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.simple_pendulum())


def _swing(eom: lg.EquationsOfMotion, amplitude: float, t_end: float) -> Trajectory:
    return simulate(
        eom,
        {"theta": amplitude, "theta_dot": 0.0},
        t_end,
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        samples=2001,
    )


# --- stationary paths against closed forms --------------------------------------------------


def test_free_particle_moves_on_the_straight_line_with_action_m_v2_t_over_2() -> None:
    system = _free_particle()
    path = stationary_path(system, [0.0], [2.0], 1.0)
    assert path.status == "success" and path.method == "discrete action (midpoint rule)"
    assert len(path.t) == 51
    np.testing.assert_allclose(path["x"], 2 * path.t, atol=1e-12)
    np.testing.assert_allclose(path["x_dot"], 2.0, rtol=1e-10)
    assert action(system, path) == pytest.approx(3.0 * 2.0**2 * 1.0 / 2, rel=1e-12)  # 2 m


def test_uniform_gravity_gives_the_parabola_exactly() -> None:
    # L is quadratic in z_dot and linear in z: the midpoint rule's discrete equations
    # z_{k+1} - 2 z_k + z_{k-1} = -g h^2 hold exactly for z = g t (T - t) / 2.
    T = 2.0
    path = stationary_path(_gravity(), {"z": 0.0}, {"z": 0.0}, T, nodes=40)
    exact = G * path.t * (T - path.t) / 2
    assert np.max(np.abs(path["z"] - exact)) < 1e-9 * np.max(exact)
    np.testing.assert_allclose(path["z_dot"], G * (T / 2 - path.t), atol=1e-8)


def _oscillator_error(nodes: int, T: float = 2.0) -> float:
    path = stationary_path(_oscillator(), [0.0], [1.0], T, nodes=nodes)
    exact = np.sin(path.t) / np.sin(T)  # omega = 1, T < pi / omega: one solution
    return float(np.max(np.abs(path["x"] - exact)))


def test_oscillator_path_is_second_order_accurate() -> None:
    coarse, fine = _oscillator_error(100), _oscillator_error(200)
    assert coarse < 1e-3
    assert coarse / fine == pytest.approx(4.0, rel=0.05)


def test_stationary_path_agrees_with_shooting(pendulum: lg.EquationsOfMotion) -> None:
    # The true motion from theta = 0 with theta_dot = 2 reaches theta(1) = shot; the boundary
    # problem between the same ends must recover it (second order: 1e-4 at h = 1/400).
    shot = simulate(pendulum, {"theta": 0.0, "theta_dot": 2.0}, 1.0, rtol=1e-11, atol=1e-12)
    path = stationary_path(pendulum, [0.0], shot.q[-1], 1.0, nodes=400)
    reference = simulate(
        pendulum, {"theta": 0.0, "theta_dot": 2.0}, 1.0, t_eval=path.t, rtol=1e-11, atol=1e-12
    )
    np.testing.assert_allclose(path["theta"], reference["theta"], atol=1e-4)


# --- the action along simulated motion ------------------------------------------------------


def _small_oscillation_action(amplitude: float, t_end: float) -> float:
    # L = 1/2 m l^2 theta_dot^2 + m g l cos(theta) on theta = a cos(w t), w = sqrt(g / l)
    def lagrangian(t: float) -> float:
        theta = amplitude * np.cos(OMEGA * t)
        theta_dot = -amplitude * OMEGA * np.sin(OMEGA * t)
        return 0.5 * M * theta_dot**2 + M * G * np.cos(theta)

    return float(quad(lagrangian, 0.0, t_end, epsabs=0, epsrel=1e-13)[0])


def test_pendulum_action_matches_the_small_oscillation_closed_form(
    pendulum: lg.EquationsOfMotion,
) -> None:
    half_period = np.pi / OMEGA
    trajectory = _swing(pendulum, 1e-3, half_period)
    expected = _small_oscillation_action(1e-3, half_period)
    assert action(pendulum, trajectory) == pytest.approx(expected, rel=1e-3)
    # The constant m g l t dominates A; the motion's own part, over a span where the kinetic
    # and potential parts do not cancel, must match too (small-angle error ~ a^2).
    span = half_period / 3
    trajectory = _swing(pendulum, 1e-2, span)
    motion = action(pendulum, trajectory) - M * G * span
    assert motion == pytest.approx(_small_oscillation_action(1e-2, span) - M * G * span, rel=1e-3)


def _linear_and_quadratic_terms(amplitudes: np.ndarray, actions: np.ndarray) -> tuple[float, float]:
    scale = np.max(np.abs(amplitudes))
    c, b, _ = np.polyfit(amplitudes / scale, actions, 2)
    return b / scale, c / scale**2


def test_the_true_path_makes_the_action_stationary(pendulum: lg.EquationsOfMotion) -> None:
    # A quarter period keeps the span short of the conjugate point (half a period), where the
    # second variation for eta = sin(pi t / T) would vanish.
    quarter = np.pi / OMEGA / 2
    true = _swing(pendulum, 0.1, quarter)
    eps = np.linspace(-1e-3, 1e-3, 5)
    amplitudes, actions = action_variation(pendulum, true, eps)
    np.testing.assert_array_equal(amplitudes, eps)
    b, c = _linear_and_quadratic_terms(amplitudes, actions)
    assert c > 0
    assert abs(b) < 1e-3 * abs(c) * 1e-3
    # The straight line between the same ends is no motion: A has a clear linear term.
    line = (true.q[-1] - true.q[0]) / quarter
    straight = Trajectory(
        t=true.t,
        q=true.q[0] + np.outer(true.t, line),
        q_dot=np.tile(line, (len(true.t), 1)),
        coordinates=true.coordinates,
        energy=np.zeros(len(true.t)),
        parameters=true.parameters,
    )
    b_line, c_line = _linear_and_quadratic_terms(*action_variation(pendulum, straight, eps))
    assert abs(b_line) > 10 * abs(c_line) * 1e-3


def test_a_custom_shape_gives_the_same_stationarity(pendulum: lg.EquationsOfMotion) -> None:
    quarter = np.pi / OMEGA / 2
    true = _swing(pendulum, 0.1, quarter)

    def bump(t: float) -> np.ndarray:
        return np.array([t * (quarter - t) * t])

    b, c = _linear_and_quadratic_terms(*action_variation(pendulum, true, [-1e-2, 0.0, 1e-2], bump))
    assert abs(b) < 1e-5 * abs(c) * 1e-2


# --- bad input -----------------------------------------------------------------------------


def test_a_shape_that_moves_the_ends_is_refused(pendulum: lg.EquationsOfMotion) -> None:
    true = _swing(pendulum, 0.1, 0.2)
    with pytest.raises(lg.SimulationError, match=r"shape\(t0\) = shape\(t1\) = 0"):
        action_variation(pendulum, true, [0.1], lambda t: np.array([1.0]))


def test_bad_boundary_input_is_reported_at_once(pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(lg.SimulationError, match=r"\(3 problems\)") as caught:
        stationary_path(pendulum, [0.0, 1.0], {"phi": 1.0}, 1.0, nodes=1)
    assert sorted(p.field for p in caught.value.problems) == ["nodes", "q_end", "q_start"]


def test_a_trajectory_of_another_system_is_refused(pendulum: lg.EquationsOfMotion) -> None:
    path = stationary_path(_oscillator(), [0.0], [1.0], 1.0, nodes=4)
    with pytest.raises(lg.SimulationError, match="not the system's"):
        action(pendulum, path)


# --- plot ----------------------------------------------------------------------------------


def test_plot_action_variation_saves_a_png(tmp_path: Path) -> None:
    eps = np.linspace(-1e-3, 1e-3, 5)
    ax = plot_action_variation(eps, 3.0 + eps**2)
    assert ax.get_xlabel() == "eps"
    target = tmp_path / "action.png"
    ax.figure.savefig(target)
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
