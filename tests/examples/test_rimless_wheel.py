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


def rock_time(rate: float, angle: float) -> float:
    """The time a wheel standing on a spoke at ``angle`` from the vertical, turning towards
    the vertical at ``rate`` too slow to pass it, takes to fall back onto the spoke it left:
    twice the quadrature of energy conservation from the turning point theta_0,
    theta_dot^2 = (2 g / l)(cos(theta_0) - cos(theta)), written with theta = theta_0 + u^2
    (no singularity at the turning point) and cos a - cos b = 2 sin((a + b)/2) sin((b - a)/2)
    (no cancellation near it).  Below 1e-4 rad/s the rock is one of constant deceleration,
    g sin(angle) / l, to 1e-9 of its length (the angle changes by rate^2 / (2 g sin(angle)))."""
    if rate < 1e-4:
        return 2 * rate / (G / L * np.sin(angle))
    theta_0 = np.arccos(np.cos(angle) + rate**2 * L / (2 * G))

    def dt(u: float) -> float:
        if u == 0:
            return 2 / np.sqrt(2 * G / L * np.sin(theta_0))
        theta = theta_0 + u * u
        drop = 2 * np.sin((theta + theta_0) / 2) * np.sin(u * u / 2)
        return 2 * u / np.sqrt(2 * G / L * drop)

    return 2 * float(quad(dt, 0.0, np.sqrt(angle - theta_0), epsabs=1e-15, epsrel=1e-13)[0])


def test_a_slow_wheel_rocks_between_two_spokes_to_rest() -> None:
    """Too slow to pass over its foot, the wheel falls back onto the rear spoke (alpha - gamma
    from the vertical), then forward onto the front one (alpha + gamma), each strike with
    omega+ = cos(2 alpha) omega- (McGeer 1990), each rock as long as the quadrature says;
    the rocks shrink geometrically, end within a single step of the integrator (every one is
    still found, none skipped: the wheel never rolls over a foot) and accumulate to rest."""
    alpha, gamma = np.pi / 8, 0.1
    wheel = lg.examples.rimless_wheel()
    start = {"theta": gamma - alpha, "theta_dot": 0.5}
    run = lg.simulate(wheel, start, 5.0, samples=501)
    assert run.success and "Zeno accumulation" in run.message
    assert np.all(run["theta"] >= gamma - alpha - 1e-9) and np.all(
        run["theta"] <= gamma + alpha + 1e-9
    )
    t, rate, angle, expected = 0.0, 0.5, alpha - gamma, []
    while rate > 1e-12:
        t += rock_time(rate, angle)
        rate *= np.cos(2 * alpha)
        expected.append((t, "back_strike" if angle == alpha - gamma else "heel_strike", rate))
        angle = alpha + gamma if angle == alpha - gamma else alpha - gamma
    at_rest = expected[-1][0]  # the rest of the series is below 1e-11 s
    expected = [strike for strike in expected if strike[2] > 1e-5]
    assert len(run.impacts) > len(expected) > 20
    for strike, (t, name, after) in zip(run.impacts, expected):
        assert strike.constraints == (name,)
        assert strike.t == pytest.approx(t, abs=1e-9)
        assert abs(strike.after["theta_dot"]) == pytest.approx(after, rel=1e-7, abs=1e-10)
        assert strike.after["theta_dot"] == pytest.approx(
            np.cos(2 * alpha) * strike.before["theta_dot"], rel=1e-12
        )
    # the last rocks checked, 2 omega / (g sin(angle) / l) ~ 1e-5 s, are far shorter than the
    # integrator's steps (~2 ms here): each began and ended within one step
    assert run.impacts[len(expected) - 1].t - run.impacts[len(expected) - 2].t < 2e-5
    # rest where the rocks accumulate (the run stops when rocks of ~1e-7 rad/s, 1e-8 s long,
    # come at once: the rest of the series is shorter than 1e-6 s)
    assert run.impacts[-1].t == pytest.approx(at_rest, abs=1e-6)
    assert run.impacts[-1].t <= at_rest
