"""The one Python loop over lanes: a single run is one lane, a batch without the C loop is k
lanes of one vectorized stepper, both through ``integrators.loop.run_lanes``.  Checked
against SciPy's solve_ivp (the same steps), closed forms, and each member run alone."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import RK45, solve_ivp

import lagrangian as lg
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.status import Status
from lagrangian.simulation.batch import vectorized
from lagrangian.simulation.integrators import loop
from lagrangian.simulation.integrators.lanes import OneLane

x, k, m = sp.symbols("x k m")


@pytest.fixture
def no_compiler(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(c_loop, "available", lambda: False)


def oscillator() -> lg.System:
    """m x'' = -k x: x(t) = x0 cos(sqrt(k/m) t) from rest."""
    return lg.System(
        coordinates=[x],
        parameters={k: 1.0, m: 1.0},
        kinetic=m * lg.velocity(x) ** 2 / 2,
        potential=k * x**2 / 2,
    )


def test_one_lane_takes_solve_ivps_steps_and_rows() -> None:
    def field(t: float, y: np.ndarray) -> np.ndarray:
        return np.array([y[1], -np.sin(y[0])])

    times = np.linspace(0.0, 5.0, 41)
    y0 = np.array([1.0, 0.0])
    run = loop.integrate(lambda: RK45(field, 0.0, y0, 5.0, rtol=1e-10), 0.0, y0, times)
    reference = solve_ivp(field, (0.0, 5.0), y0, method="RK45", rtol=1e-10, t_eval=times)
    np.testing.assert_array_equal(run.t, reference.t)
    np.testing.assert_allclose(run.x, reference.y.T, rtol=0, atol=1e-15)


def test_lanes_of_one_run_report_each_lanes_end() -> None:
    def blows_up(t: float, y: np.ndarray) -> np.ndarray:
        return y**2  # y = 1 / (1 - t): infinite at t = 1

    start = np.array([[1.0]])
    lanes = loop.run_lanes(lambda: OneLane(RK45(blows_up, 0.0, start[0], 2.0)), 0.0, start)
    assert lanes.status.tolist() == [Status.FAILED]
    assert lanes.t_reached[0] == pytest.approx(1.0, abs=1e-3)
    assert "step size" in str(lanes.messages[0]) or "finite" in str(lanes.messages[0])


def test_a_batch_without_compiler_is_one_call_of_the_loop_with_a_lane_per_member(
    no_compiler: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls: list[int] = []
    run_lanes = loop.run_lanes

    def counted(start, t0, X0, *rest):
        calls.append(len(X0))
        return run_lanes(start, t0, X0, *rest)

    monkeypatch.setattr(vectorized, "run_lanes", counted)
    stiffness = np.array([0.5, 1.0, 4.0, 9.0])
    batch = lg.simulate_batch(
        oscillator(),
        {"x": 0.3, "x_dot": 0.0},
        6.0,
        parameters={"k": stiffness},
        rtol=1e-10,
        atol=1e-12,
        samples=13,
    )
    assert calls == [len(stiffness)]
    assert batch.status == ("success",) * len(stiffness)
    closed = 0.3 * np.cos(np.sqrt(stiffness)[:, None] * batch.t[None, :])
    np.testing.assert_allclose(batch.q[:, :, 0], closed, atol=1e-8)


def test_members_end_on_their_own_and_the_others_go_on(no_compiler: None) -> None:
    """x = 0.3 cos(w t) reaches 0.15 at w t = pi/3: each stops there, the slowest finishes."""
    stiffness = np.array([1.0, 4.0, 0.01])

    def below_half(t, q, q_dot):
        return q[..., 0] - 0.15

    batch = lg.simulate_batch(
        oscillator(),
        {"x": 0.3, "x_dot": 0.0},
        3.0,
        parameters={"k": stiffness},
        stop_when=below_half,
        rtol=1e-10,
        atol=1e-12,
        samples=31,
    )
    assert batch.status == ("stopped", "stopped", "success")
    expected = np.pi / 3 / np.sqrt(stiffness[:2])
    np.testing.assert_allclose(batch.stop_time[:2], expected, rtol=1e-8)
    for i in range(2):  # rows after a member's stop stay NaN
        assert np.isnan(batch.q[i, batch.t > expected[i], 0]).all()
        assert np.isfinite(batch.q[i, batch.t <= expected[i], 0]).all()
    assert np.isfinite(batch.q[2]).all()


def test_progress_of_a_batch_without_compiler_rises_to_the_end(no_compiler: None) -> None:
    seen: list[float] = []
    lg.simulate_batch(
        oscillator(), {"x": [0.1, 0.2, 0.3], "x_dot": 0.0}, 2.0, progress=seen.append, samples=5
    )
    assert seen and seen[-1] == 2.0
    assert all(a <= b for a, b in pairwise(seen))


def test_ctrl_c_ends_a_batch_without_compiler(no_compiler: None) -> None:
    calls = {"n": 0}

    def interrupted(t, q, q_dot):
        calls["n"] += 1
        if calls["n"] > 5:
            raise KeyboardInterrupt
        return np.ones(np.shape(t))

    with pytest.raises(KeyboardInterrupt):
        lg.simulate_batch(oscillator(), {"x": [0.1, 0.2], "x_dot": 0.0}, 2.0, stop_when=interrupted)
