"""The rimless wheel's steady roll against its closed form (Coleman, Chatterjee & Ruina,
"Motions of a rimless spoked wheel: a simple three-dimensional system with impacts",
Dynamics and Stability of Systems 12(3), 1997, §2, the planar wheel; McGeer 1990)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

import lagrangian as lg

G, L = 9.81, 1.0


def steady_rate(alpha: float, gamma: float) -> float:
    """The post-strike rate of the period-one roll.  A step pivots from theta = gamma - alpha
    to gamma + alpha (theta from the vertical), the hub falling 2 l sin(alpha) sin(gamma):
    omega_-^2 = omega_+^2 + (4 g / l) sin(alpha) sin(gamma); the strike keeps the angular
    momentum about the new foot, omega_+ = cos(2 alpha) omega_-.  At the fixed point
    omega*^2 = (4 g / l) sin(alpha) sin(gamma) cos^2(2 alpha) / (1 - cos^2(2 alpha))."""
    c2 = np.cos(2 * alpha) ** 2
    return float(np.sqrt(4 * G / L * np.sin(alpha) * np.sin(gamma) * c2 / (1 - c2)))


def step_time(alpha: float, gamma: float, rate: float) -> float:
    """The time of one step, by quadrature of energy conservation between strikes:
    theta_dot^2 = rate^2 + (2 g / l)(cos(gamma - alpha) - cos(theta))."""

    def dt(theta: float) -> float:
        return 1 / np.sqrt(rate**2 + 2 * G / L * (np.cos(gamma - alpha) - np.cos(theta)))

    return float(quad(dt, gamma - alpha, gamma + alpha, epsabs=1e-13, epsrel=1e-13)[0])


@pytest.mark.parametrize(("alpha", "gamma"), [(np.pi / 8, 0.1), (np.pi / 6, 0.2)])
def test_the_steady_roll_is_the_closed_form_and_its_multiplier_cos2_2alpha(alpha, gamma):
    wheel = lg.examples.rimless_wheel()
    rate = steady_rate(alpha, gamma)
    start = {"theta": gamma - alpha, "theta_dot": 1.05 * rate}  # Newton starts off the cycle
    cycle = lg.limit_cycle(wheel, start, section="heel_strike",
                           parameters={"alpha": alpha, "gamma": gamma})  # fmt: skip
    assert cycle.state["theta"] == pytest.approx(gamma - alpha, abs=1e-12)
    assert cycle.state["theta_dot"] == pytest.approx(rate, rel=1e-9)
    assert cycle.period == pytest.approx(step_time(alpha, gamma, rate), rel=1e-9)
    # d omega_+' / d omega_+ = cos^2(2 alpha) omega_+ / omega_+' = cos^2(2 alpha) at the fixed
    # point; the strike fixes theta, so the other multiplier is 0
    moduli = sorted(abs(m) for m in cycle.multipliers)
    assert moduli[0] < 1e-6
    assert moduli[1] == pytest.approx(np.cos(2 * alpha) ** 2, abs=1e-6)
    assert cycle.stable


def test_the_example_starts_on_its_steady_roll() -> None:
    wheel = lg.examples.rimless_wheel()
    run = lg.simulate(wheel)
    assert run.success, run.message
    rate = steady_rate(np.pi / 8, 0.1)
    assert len(run.impacts) > 5
    for strike in run.impacts:
        assert strike.after["theta_dot"] == pytest.approx(rate, rel=1e-4)
        assert strike.before["theta_dot"] * np.cos(np.pi / 4) == pytest.approx(
            strike.after["theta_dot"], rel=1e-12
        )
    assert "transitions" in run.drift_summary()
