"""Periodic orbits of smooth systems through a section expression: the pendulum's period
against the elliptic-integral formula, and a Hénon–Heiles orbit checked by SciPy's solve_ivp,
with the Floquet multipliers a conservative orbit must have."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.errors import SimulationInputError


@pytest.mark.parametrize("amplitude", [0.3, 2.0, 3.0])
def test_the_pendulums_period_is_4_K_k_sqrt_l_over_g(amplitude: float) -> None:
    # T = 4 K(k) sqrt(l/g), k = sin(a/2) (Landau & Lifshitz, Mechanics, §11, problem 1); the
    # swing of amplitude a passes the vertical at theta_dot = 2 sqrt(g/l) sin(a/2)
    g, l = 9.81, 1.0
    k = np.sin(amplitude / 2)
    start = {"theta": 0.0, "theta_dot": 2 * np.sqrt(g / l) * k}
    cycle = lg.limit_cycle(lg.examples.simple_pendulum(), start, section="theta")
    assert cycle.period == pytest.approx(4 * ellipk(k**2) * np.sqrt(l / g), rel=1e-10)
    # every swing is periodic: the energy's multiplier 1, the flow's 0 (a start moved along
    # its own orbit returns to the same point)
    moduli = sorted(abs(m) for m in cycle.multipliers)
    assert moduli[0] < 1e-6 and moduli[1] == pytest.approx(1, abs=1e-6)
    assert not cycle.stable and "neutrally stable" in cycle.text()
    falling = lg.limit_cycle(lg.examples.simple_pendulum(), start, section="theta",
                             direction="falling")  # fmt: skip
    assert falling.state["theta_dot"] < 0
    assert falling.period == pytest.approx(cycle.period, rel=1e-10)


def henon_heiles_rates(t: float, state: np.ndarray) -> np.ndarray:
    x, y, x_dot, y_dot = state
    return np.array([x_dot, y_dot, -x - 2 * x * y, -y - x**2 + y**2])


def test_a_henon_heiles_periodic_orbit_closes_and_its_multipliers_are_symplectic() -> None:
    # near the centre of the islands of the section x = 0 at E = 1/8
    near = {"x": 0.0, "y": 0.3, "x_dot": 0.3967, "y_dot": 0.0}
    cycle = lg.limit_cycle(lg.examples.henon_heiles(), near, section="x")
    x0 = np.array([cycle.state[n] for n in ("x", "y", "x_dot", "y_dot")])
    run = solve_ivp(henon_heiles_rates, (0.0, cycle.period), x0, method="DOP853",
                    rtol=1e-12, atol=1e-12)  # fmt: skip
    assert np.allclose(run.y[:, -1], x0, atol=1e-8)  # the orbit closes after one period
    # one multiplier 0 (the flow), one 1 (the energy), and a pair m, 1/m on the energy surface
    m = sorted(cycle.multipliers, key=abs)
    assert abs(m[0]) < 1e-6
    one = min(m[1:], key=lambda v: abs(v - 1))
    pair = [v for v in m[1:] if v is not one]
    assert abs(one - 1) < 1e-6
    assert abs(pair[0] * pair[1] - 1) < 1e-6
    assert all(abs(abs(v) - 1) < 1e-6 for v in pair)  # elliptic: neutrally stable


def test_a_limit_cycle_through_a_section_on_the_command_line(capsys) -> None:
    from lagrangian.cli.main import main

    code = main(["analyze", "examples/simple_pendulum", "--limit-cycle", "theta", "--initial",
                 "theta=0", "--initial", "theta_dot=1", "--format", "json",
                 "--search-degree", "0"])  # fmt: skip
    said = capsys.readouterr()
    assert code == 0, said.err
    cycle = json.loads(said.out)["limit_cycle"]
    k = np.sin(np.arccos(1 - 0.5 / 9.81) / 2)  # the swing with theta_dot = 1 at the bottom
    assert cycle["period"] == pytest.approx(4 * ellipk(k**2) / np.sqrt(9.81), rel=1e-10)


def test_a_section_neither_a_transition_nor_an_expression_is_refused() -> None:
    with pytest.raises(SimulationInputError, match=r"'toe_off' is not a transition .* nor an"):
        lg.limit_cycle(lg.examples.simple_pendulum(), section="toe_off")


def test_a_unilateral_constraint_is_a_section_the_state_just_after_its_impacts() -> None:
    """A self-excited oscillator (negative damping c) against a wall x >= -a with e < 1: the
    energy gained in flight balances the loss at the wall on an isolated cycle.  Checked by
    SciPy: from the wall at the cycle's speed, the flight returns to the wall at the speed
    that restitution turns into the same one, after one period."""
    c, a, e = 0.1, 1.0, 0.8
    oscillator = lg.loads(
        f"""
        coordinates: [x]
        parameters: {{c: {c}, a: {a}, e: {e}}}
        kinetic: x_dot**2/2
        potential: x**2/2
        generalized_forces: {{x: c*x_dot}}
        constraints:
          - {{name: wall, unilateral: x + a, restitution: e}}
        initial: {{x: 0.0, x_dot: 1.2}}
        """
    )
    cycle = lg.limit_cycle(oscillator, section="wall")
    assert cycle.state["x"] == pytest.approx(-a, abs=1e-7)
    speed = cycle.state["x_dot"]

    def wall(t: float, s: np.ndarray) -> float:
        return s[0] + a

    wall.terminal, wall.direction = True, -1  # type: ignore[attr-defined]
    flight = solve_ivp(lambda t, s: [s[1], c * s[1] - s[0]], (0, 50), [-a, speed],
                       events=wall, rtol=1e-12, atol=1e-12)  # fmt: skip
    (t_return,), ((_, v_return),) = flight.t_events[0], flight.y_events[0]
    assert -e * v_return == pytest.approx(speed, rel=1e-6)
    assert cycle.period == pytest.approx(t_return, rel=1e-6)
    # the position is fixed by the section (a zero multiplier); the speed's is dP/dv < 1
    moduli = sorted(abs(m) for m in cycle.multipliers)
    assert moduli[0] < 1e-6 and 0 < moduli[1] < 1 and cycle.stable
