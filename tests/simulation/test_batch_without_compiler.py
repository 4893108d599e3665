"""A batch without the C loop: the members' steps computed together in NumPy
(simulation/batch/vectorized.py).  Checked against ``simulate`` of each member alone in the
Python loop (SciPy's steps: the same numbers), and that a round of steps costs one call of the
right-hand side per stage for all members (its failures: test_batch_failures.py)."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.fast import c_loop

ANGLES = np.array([-1.2, -0.4, 0.3, 1.1, 2.0])
REST = {"phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}


@pytest.fixture
def no_compiler(monkeypatch: pytest.MonkeyPatch) -> None:
    """The machine without a C compiler: batches and simulate step in Python."""
    monkeypatch.setattr(c_loop, "available", lambda: False)


@pytest.fixture(scope="module")
def double_pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.double_pendulum())


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
