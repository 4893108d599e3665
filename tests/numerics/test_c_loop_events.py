"""Events in the C loop (numerics/fast/c_loop.c, simulation/integrators/event_trace.py): zeros at
the times
of closed forms, the same event records, rows and messages as SciPy's path, directions and
terminal counts, and SciPy's path for event functions that are not expressions of the state
or when there is no C compiler."""

from __future__ import annotations

import math

import numpy as np
import pytest
from c_loop_setup import scipy_path
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.io.load import loads
from lagrangian.numerics.fast import c_loop
from lagrangian.simulation.integrators.compiled import NativeIntegrator
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler")

FALLING = """
name: falling particle
coordinates: [x, y]
parameters: {m: 2.0, g: 9.81}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
"""
TOL = {"rtol": 1e-10, "atol": 1e-10}
PENDULUM_START = {"theta": 1.0, "theta_dot": 0.0}


def integrator_of(eom, initial, t_end, events, **options):
    return plan(prepare(eom, initial, t_end, options, events=events))[1]


def floor(t, q, q_dot):
    return q[1]


floor.terminal = True
floor.direction = -1


def crossing(t, q, q_dot):
    return q[0]


def rising(t, q, q_dot):
    return q_dot[0]


rising.direction = 1


def third_swing(t, q, q_dot):
    return q[0] - 0.5


third_swing.terminal = 3


def same_events(native: lg.Trajectory, scipy: lg.Trajectory) -> None:
    assert [e.name for e in native.events] == [e.name for e in scipy.events]
    for mine, theirs in zip(native.events, scipy.events):
        assert mine.t == pytest.approx(theirs.t, abs=1e-9)
        for name, value in mine.state.items():
            assert value == pytest.approx(theirs.state[name], abs=1e-9)
    assert native.message == scipy.message and native.status == scipy.status


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
@pytest.mark.parametrize("samples", [None, 41])
def test_a_falling_particle_hits_the_floor_at_the_closed_form_time(method, samples) -> None:
    eom = lg.derive(loads(FALLING))
    start = {"x": 0.0, "y": 3.0, "x_dot": 0.5, "y_dot": 1.0}
    options = {"method": method, "samples": samples, **TOL}
    assert isinstance(integrator_of(eom, start, 5.0, [floor], **options), NativeIntegrator)
    native = lg.simulate(eom, start, 5.0, events=[floor], **options)
    g, v, h = 9.81, 1.0, 3.0
    hit = (v + math.sqrt(v**2 + 2 * g * h)) / g  # h + v t - g t^2 / 2 = 0
    assert len(native.events) == 1 and native.events[0].t == pytest.approx(hit, abs=1e-9)
    assert native.t[-1] == native.events[0].t and native.q[-1, 1] == pytest.approx(0.0, abs=1e-9)
    assert native.events[0].state["x"] == pytest.approx(0.5 * hit, abs=1e-9)
    scipy = scipy_path(eom, start, 5.0, events=[floor], **options)
    same_events(native, scipy)
    if samples:  # every step: step sizes from an error estimate that cancels (exact here)
        np.testing.assert_allclose(native.t, scipy.t, rtol=0, atol=1e-12)
        np.testing.assert_allclose(native.q, scipy.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.q[-1], scipy.q[-1], rtol=0, atol=1e-9)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_pendulum_crossings_are_at_the_quarter_periods(method: str) -> None:
    """theta = 0 at T/4, 3T/4, ... with T = 4 sqrt(l/g) K(sin^2(theta0/2)); rising zeros of
    theta_dot (direction +1) at the turning points T/2, T, ..."""
    eom = lg.derive(lg.examples.simple_pendulum())
    period = 4 * math.sqrt(1.0 / 9.81) * ellipk(math.sin(0.5) ** 2)
    options = {"method": method, "samples": 101, **TOL}
    events = [crossing, rising]
    assert isinstance(integrator_of(eom, PENDULUM_START, 10.0, events), NativeIntegrator)
    native = lg.simulate(eom, PENDULUM_START, 10.0, events=events, **options)
    zeros = [e.t for e in native.events if e.name == "crossing"]
    turns = [e.t for e in native.events if e.name == "rising"]
    expected = period / 4 + period / 2 * np.arange(len(zeros))
    np.testing.assert_allclose(zeros, expected, rtol=0, atol=1e-8)
    assert len(zeros) == int((10.0 - period / 4) // (period / 2)) + 1
    # theta_dot rises through zero where theta is at its lowest, -1 (times T/2, 3T/2, ...)
    np.testing.assert_allclose(turns, period / 2 + period * np.arange(len(turns)), atol=1e-8)
    assert all(e.state["theta"] == pytest.approx(-1.0, abs=1e-8) for e in native.events[1::3])
    same_events(native, scipy_path(eom, PENDULUM_START, 10.0, events=events, **options))


def test_a_terminal_count_stops_at_its_kth_zero_as_on_scipys_path() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())
    events = [crossing, third_swing]
    native = lg.simulate(eom, PENDULUM_START, 20.0, events=events, method="DOP853", **TOL)
    scipy = scipy_path(eom, PENDULUM_START, 20.0, events=events, method="DOP853", **TOL)
    assert sum(e.name == "third_swing" for e in native.events) == 3
    assert native.events[-1].name == "third_swing" and native.t[-1] == native.events[-1].t
    same_events(native, scipy)
    np.testing.assert_allclose(native.q[-1], scipy.q[-1], rtol=0, atol=1e-9)


def test_many_zeros_grow_the_event_records() -> None:
    """A fast oscillator crosses zero hundreds of times (more than the first records)."""
    eom = lg.derive(loads(FALLING.replace("m*g*y", "m*400*(x**2 + y**2)/2")))
    start = {"x": 1.0, "y": 0.5, "x_dot": 0.0, "y_dot": 0.0}
    events = [crossing, rising]
    native = lg.simulate(eom, start, 5.0, events=events, method="RK45", **TOL)
    scipy = scipy_path(eom, start, 5.0, events=events, method="RK45", **TOL)
    zeros = [e.t for e in native.events if e.name == "crossing"]
    assert len(zeros) == 32  # x = cos(20 t): zeros at (k + 1/2) pi / 20
    np.testing.assert_allclose(zeros, (np.arange(32) + 0.5) * np.pi / 20, rtol=0, atol=1e-8)
    same_events(native, scipy)


def test_events_that_are_not_expressions_take_scipys_path() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())

    def branching(t, q, q_dot):
        return q[0] if q_dot[0] > 0 else -q[0]

    def numeric(t, q, q_dot):
        return math.sin(q[0])

    def stateful_constant(t, q, q_dot):  # a number: an expression too
        return 1.0

    assert isinstance(integrator_of(eom, PENDULUM_START, 3.0, [branching]), SolverIntegrator)
    assert isinstance(integrator_of(eom, PENDULUM_START, 3.0, [numeric]), SolverIntegrator)
    assert isinstance(
        integrator_of(eom, PENDULUM_START, 3.0, [stateful_constant]), NativeIntegrator
    )
    run = lg.simulate(eom, PENDULUM_START, 3.0, events=[numeric], **TOL)
    period = 4 * math.sqrt(1.0 / 9.81) * ellipk(math.sin(0.5) ** 2)
    assert run.events[0].t == pytest.approx(period / 4, abs=1e-8)


def test_an_expression_that_is_not_the_function_is_not_compiled() -> None:
    """A function whose value on numbers is not its value on symbols keeps SciPy's path."""
    eom = lg.derive(lg.examples.simple_pendulum())

    def two_faced(t, q, q_dot):
        return q[0] if isinstance(q[0], float) else q[0] + 1

    assert isinstance(integrator_of(eom, PENDULUM_START, 3.0, [two_faced]), SolverIntegrator)


def test_events_run_on_scipys_path_without_a_compiler() -> None:
    eom = lg.derive(loads(FALLING))
    start = {"x": 0.0, "y": 3.0, "x_dot": 0.5, "y_dot": 1.0}
    run = scipy_path(eom, start, 5.0, events=[floor], method="DOP853", **TOL)
    hit = (1.0 + math.sqrt(1.0 + 2 * 9.81 * 3.0)) / 9.81
    assert run.events[0].t == pytest.approx(hit, abs=1e-9)


def test_progress_with_events_ends_at_the_stop() -> None:
    eom = lg.derive(loads(FALLING))
    start = {"x": 0.0, "y": 3.0, "x_dot": 0.5, "y_dot": 1.0}
    seen: list[float] = []
    run = lg.simulate(eom, start, 5.0, events=[floor], progress=seen.append, **TOL)
    assert seen == sorted(seen) and len(seen) > 3 and seen[-1] >= run.events[0].t


def test_first_order_coordinates_events_of_the_state_run_in_the_loop() -> None:
    """The RC + RL circuit: q1 has no inertia, so q1_dot is not in the state; an event of
    the charges runs in the loop, one of q1_dot on SciPy's path, both as SciPy locates them."""
    eom = lg.derive(lg.examples.rc_rl_circuit())
    start = {"q1": 0.0, "q2": 0.0, "q2_dot": 0.0}

    def charges(t, q, q_dot):
        return q[1] - 0.5 * q[0] - 1e-5

    def current(t, q, q_dot):
        return q_dot[0] - 0.05

    assert isinstance(integrator_of(eom, start, 1.0, [charges]), NativeIntegrator)
    assert isinstance(integrator_of(eom, start, 1.0, [current]), SolverIntegrator)
    native = lg.simulate(eom, start, 1.0, events=[charges], **TOL)
    same_events(native, scipy_path(eom, start, 1.0, events=[charges], **TOL))
    assert len(native.events) >= 1
