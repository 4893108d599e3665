"""A batch without the C loop: the members' steps computed together in NumPy
(simulation/batch/vectorized.py).  Checked against ``simulate`` of each member alone in the
Python loop (SciPy's steps: the same numbers), against the C loop's batch (the same statuses
and messages), against the blow-up time of x_ddot = x**3 in closed form, and that a round of
steps costs one call of the right-hand side per stage for all members."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.fast import c_loop

ANGLES = np.array([-1.2, -0.4, 0.3, 1.1, 2.0])
REST = {"phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
x, m = sp.symbols("x m")


@pytest.fixture
def no_compiler(monkeypatch: pytest.MonkeyPatch) -> None:
    """The machine without a C compiler: batches and simulate step in Python."""
    monkeypatch.setattr(c_loop, "available", lambda: False)


@pytest.fixture(scope="module")
def double_pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.double_pendulum())


def quartic() -> lg.System:
    """x_ddot = x**3 / m: from x = 1 at rest it reaches infinity at t = K(1/2)."""
    return lg.System(
        coordinates=[x],
        parameters={m: 1.0},
        kinetic=m * lg.velocity(x) ** 2 / 2,
        potential=-(x**4) / 4,
    )


@pytest.mark.parametrize("method", ["RK45", "DOP853", "RK4"])
def test_each_member_is_simulate_of_that_member_in_the_same_loop(
    double_pendulum, method, no_compiler
) -> None:
    settings = {"dt": 0.01} if method == "RK4" else {"rtol": 1e-9, "atol": 1e-9}
    batch = lg.simulate_batch(
        double_pendulum, {"theta": ANGLES, **REST}, 4.0, method=method, samples=9, **settings
    )
    assert batch.status == ("success",) * len(ANGLES)
    for i, theta in enumerate(ANGLES):
        alone = lg.simulate(
            double_pendulum, {"theta": theta, **REST}, 4.0, method=method, samples=9, **settings
        )
        np.testing.assert_allclose(batch.q[i], alone.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(batch.q_dot[i], alone.q_dot, rtol=0, atol=1e-11)


def test_a_stop_condition_ends_each_member_where_simulate_locates_it(
    double_pendulum, no_compiler
) -> None:
    def theta_zero(t, q, q_dot):
        return q[..., 0] ** 2 - 0.01

    batch = lg.simulate_batch(
        double_pendulum, {"theta": ANGLES, **REST}, 4.0, stop_when=theta_zero, rtol=1e-10
    )
    assert set(batch.status) == {"stopped"}
    for i, theta in enumerate(ANGLES):
        event = lambda t, q, q_dot: q[0] ** 2 - 0.01  # noqa: E731
        event.terminal, event.direction = True, -1
        alone = lg.simulate(
            double_pendulum, {"theta": theta, **REST}, 4.0, events=[event], rtol=1e-10
        )
        assert batch.stop_time[i] == pytest.approx(alone.events[0].t, abs=1e-10)


@pytest.mark.skipif(not c_loop.available(), reason="no C compiler to compare with")
def test_failures_have_the_statuses_and_messages_of_the_c_loop(monkeypatch) -> None:
    runs = {
        "blow-up": ({"x": [0.1, 1.0], "x_dot": 0.0}, {}),
        "singular": ({"x": 0.5, "x_dot": 0.0}, {"parameters": {"m": [1, 0]}}),
        "budget": ({"x": [0.1, 0.2], "x_dot": 0.0}, {"max_steps": 3}),
    }
    for initial, options in runs.values():
        native = lg.simulate_batch(quartic(), initial, 3.0, **options)
        with monkeypatch.context() as patch:
            patch.setattr(c_loop, "available", lambda: False)
            stepped = lg.simulate_batch(quartic(), initial, 3.0, **options)
        assert stepped.status == native.status and stepped.message == native.message
        np.testing.assert_allclose(stepped.final_t, native.final_t, rtol=1e-9)


def test_a_member_blows_up_at_its_closed_form_time_and_the_other_finishes(no_compiler) -> None:
    batch = lg.simulate_batch(quartic(), {"x": [0.1, 1.0], "x_dot": 0.0}, 3.0)
    assert batch.status == ("success", "failed")
    assert batch.final_t[1] == pytest.approx(ellipk(0.5), rel=1e-4)


def test_a_round_costs_one_call_per_stage_for_all_members(
    double_pendulum, no_compiler, monkeypatch
) -> None:
    calls = {"rows": 0, "calls": 0}
    rhs = CompiledEquations.rhs

    def counted(self, t, state, p):
        if np.ndim(state) == 2:
            calls["calls"] += 1
            calls["rows"] += len(state)
        return rhs(self, t, state, p)

    monkeypatch.setattr(CompiledEquations, "rhs", counted)
    many = np.linspace(-1.5, 1.5, 40)
    batch = lg.simulate_batch(double_pendulum, {"theta": many, **REST}, 2.0, samples=5)
    assert set(batch.status) == {"success"}
    # every member's evaluations went through arrays of members, few calls for many rows
    assert calls["rows"] > 10 * calls["calls"]
