"""Hybrid transitions against an independent event-driven integration: the simplest walker
(Garcia, Chatterjee, Ruina & Coleman 1998) stepped by SciPy's solve_ivp with its heel-strike
event and reset written out here, and the model-file contract of ``transitions``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ModelError

GAMMA = 0.009
TIGHT = {"method": "DOP853", "rtol": 1e-11, "atol": 1e-12}


def walker_rates(t: float, x: np.ndarray) -> np.ndarray:
    """Garcia et al.'s eq. 3 in the limit of light feet."""
    theta, phi, theta_dot, phi_dot = x
    theta_ddot = np.sin(theta - GAMMA)
    phi_ddot = theta_ddot + np.sin(phi) * (theta_dot**2 - np.cos(theta - GAMMA))
    return np.array([theta_dot, phi_dot, theta_ddot, phi_ddot])


def heel_strike(x: np.ndarray) -> np.ndarray:
    """Their eq. 4: the legs swap, angular momentum about the new contact is kept."""
    theta, _, theta_dot, _ = x
    c = np.cos(2 * theta)
    return np.array([-theta, -2 * theta, c * theta_dot, c * (1 - c) * theta_dot])


def reference_steps(x0: np.ndarray, steps: int) -> list[tuple[float, np.ndarray]]:
    """Heel-strike times and the states after them, by solve_ivp with the guard phi - 2 theta
    rising, crossings with theta >= 0 (the swing foot scuffing mid-step) passed by."""

    def guard(t: float, x: np.ndarray) -> float:
        return x[1] - 2 * x[0]

    guard.direction = 1.0  # type: ignore[attr-defined]
    t, x, found = 0.0, x0, []
    while len(found) < steps:
        run = solve_ivp(walker_rates, (t, t + 10), x, events=guard, rtol=1e-12, atol=1e-13,
                        method="DOP853", dense_output=True)  # fmt: skip
        strike = next(i for i, s in enumerate(run.t_events[0]) if run.y_events[0][i][0] < 0)
        t = float(run.t_events[0][strike])
        x = heel_strike(run.y_events[0][strike])
        found.append((t, x))
    return found


def test_the_simplest_walker_steps_as_an_event_driven_integration_says() -> None:
    walker = lg.examples.simplest_walker()
    run = lg.simulate(walker, t_span=12.0, samples=121, **TIGHT)
    assert run.success, run.message
    given = {s.name: value for s, value in walker.initial.items()}
    x0 = np.array([given[n] for n in ("theta", "phi", "theta_dot", "phi_dot")])
    expected = reference_steps(x0, 3)
    strikes = [e for e in run.events if e.name == "heel_strike"]
    assert len(strikes) == len(run.impacts) == 3
    for event, (t, x) in zip(strikes, expected):
        assert event.t == pytest.approx(t, abs=1e-8)
        state = [event.state[n] for n in ("theta", "phi", "theta_dot", "phi_dot")]
        assert np.allclose(state, x, atol=1e-8)
    # the gait is the period-one cycle it starts on: each step ends where it began
    for impact in run.impacts:
        assert impact.after["theta_dot"] == pytest.approx(x0[2], abs=1e-4)


def test_a_transition_in_a_model_file_round_trips_and_bad_ones_are_refused() -> None:
    from lagrangian.io.dump import dumps

    walker = lg.examples.simplest_walker()
    again = lg.loads(dumps(walker))
    assert again.transitions == walker.transitions
    with pytest.raises(ModelError, match=r"transitions\[0\].when .*cannot read the expression"):
        lg.loads(
            "coordinates: [q]\nkinetic: q_dot**2/2\n"
            "transitions: [{name: a, guard: q, when: 'q +', reset: {q: -q}}]"
        )
    with pytest.raises(ModelError, match=r"transitions\[0\].reset.psi .*: psi is not a coordinate"):
        lg.loads(
            "coordinates: [q]\nkinetic: q_dot**2/2\n"
            "transitions: [{name: a, guard: q, reset: {psi: 1}}]"
        )
    with pytest.raises(ModelError, match=r"transitions\[0\].direction .*: unknown direction 'up'"):
        lg.loads(
            "coordinates: [q]\nkinetic: q_dot**2/2\n"
            "transitions: [{name: a, guard: q, direction: up, reset: {q: -q}}]"
        )


def test_the_walkers_two_period_one_gaits_are_garcia_et_al_s() -> None:
    # Garcia, Chatterjee, Ruina & Coleman (1998), gamma = 0.009: a stable gait at
    # (theta, theta_dot) = (0.2003109003, -0.1998324731) and an unstable one, of shorter
    # period, at (0.1939373695, -0.2038669273), just after heel strike
    walker = lg.examples.simplest_walker()
    stable = lg.limit_cycle(walker, section="heel_strike")
    assert stable.state["theta"] == pytest.approx(0.2003109003, abs=1e-9)
    assert stable.state["theta_dot"] == pytest.approx(-0.1998324731, abs=1e-9)
    assert stable.stable
    theta, rate = 0.1939, -0.2039
    near = {"theta": theta, "phi": 2 * theta, "theta_dot": rate,
            "phi_dot": (1 - np.cos(2 * theta)) * rate}  # fmt: skip
    unstable = lg.limit_cycle(walker, near, section="heel_strike")
    assert unstable.state["theta"] == pytest.approx(0.1939373695, abs=1e-9)
    assert unstable.state["theta_dot"] == pytest.approx(-0.2038669273, abs=1e-9)
    assert not unstable.stable and abs(unstable.multipliers[0]) > 1
    assert unstable.period < stable.period


def test_the_floquet_multipliers_are_those_of_an_independent_return_map() -> None:
    cycle = lg.limit_cycle(lg.examples.simplest_walker(), section="heel_strike")
    x = np.array([cycle.state[n] for n in ("theta", "phi", "theta_dot", "phi_dot")])
    columns = []
    for i in range(4):  # the return map of solve_ivp, by central differences
        h = 1e-6 * (1 + abs(x[i]))
        step = np.eye(4)[i] * h
        after = [reference_steps(x + sign * step, 1)[0][1] for sign in (1, -1)]
        columns.append((after[0] - after[1]) / (2 * h))
    reference = np.linalg.eigvals(np.column_stack(columns))
    assert np.allclose(sorted(np.abs(reference)), sorted(np.abs(cycle.multipliers)), atol=1e-5)
    # the reset fixes phi and phi_dot by theta and theta_dot: two multipliers vanish
    assert sum(abs(m) < 1e-6 for m in cycle.multipliers) == 2


@pytest.mark.slow  # half a minute: the walker's cycle found from the command line
def test_a_limit_cycle_on_the_command_line(capsys) -> None:
    from lagrangian.cli.main import main

    code = main(["analyze", "examples/simplest_walker", "--limit-cycle", "heel_strike",
                 "--format", "json", "--search-degree", "0"])  # fmt: skip
    said = capsys.readouterr()
    assert code == 0, said.err
    import json

    cycle = json.loads(said.out)["limit_cycle"]
    assert cycle["stable"] and cycle["state"]["theta"] == pytest.approx(0.2003109003, abs=1e-9)
    code = main(["analyze", "examples/simplest_walker", "--limit-cycle", "toe_off",
                 "--search-degree", "0"])  # fmt: skip
    assert code == 2 and "'toe_off' is not a transition of the system" in capsys.readouterr().err


def test_paths_without_transitions_refuse_them_by_name() -> None:
    # a batch and exported code have one right-hand side: applying it through a heel strike
    # would let the walker fall, so both say why instead
    from lagrangian.errors import SimulationInputError

    walker = lg.examples.simplest_walker()
    with pytest.raises(SimulationInputError, match="simulate_batch does not apply transitions"):
        lg.simulate_batch(walker, {"theta": [0.2, 0.21]}, 1.0)
    for language in ("numpy", "c"):
        with pytest.raises(ModelError, match=r"its transitions \(heel_strike\) reset the state"):
            lg.export(walker, language)


def test_transitions_firing_ever_faster_stop_at_their_accumulation() -> None:
    """A ball bounced by a transition that halves its speed: the flights shrink by 1/2 each,
    so the bounces accumulate at t_inf = t1 (1 + e) / (1 - e) = 3 t1 (t1 = sqrt(2 h / g));
    the run stops there, saying so, instead of stepping ever smaller."""
    ball = lg.loads(
        """
        coordinates: [y]
        parameters: {g: 9.81}
        kinetic: y_dot**2/2
        potential: g*y
        transitions: [{name: bounce, guard: y, direction: falling, reset: {y_dot: -y_dot/2}}]
        initial: {y: 1.0, y_dot: 0.0}
        """
    )
    run = lg.simulate(ball, t_span=3.0, samples=11, method="DOP853", rtol=1e-10, atol=1e-12)
    assert run.success and "Zeno accumulation" in run.message
    t_inf = 3 * np.sqrt(2 / 9.81)
    assert run.impacts[-1].t == pytest.approx(t_inf, abs=1e-6)
    assert run.impacts[-1].t <= t_inf
