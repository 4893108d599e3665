"""A batch records each member's failure with its status and message and keeps the others:
a member that blows up, one whose mass matrix is singular, one that spends its step budget;
without a C compiler (the vectorized NumPy batch) with the C loop's statuses and messages."""

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.numerics.fast import c_loop

x = sp.Symbol("x")
m = sp.Symbol("m")


def quartic() -> lg.System:
    """x_ddot = x**3 / m: from x = 1 at rest it reaches infinity in finite time."""
    return lg.System(
        coordinates=[x],
        parameters={m: 1.0},
        kinetic=m * lg.velocity(x) ** 2 / 2,
        potential=-(x**4) / 4,
    )


def test_a_member_that_blows_up_fails_at_the_blow_up_time_and_the_other_finishes():
    batch = lg.simulate_batch(quartic(), {"x": [0.1, 1.0], "x_dot": 0.0}, 3.0)
    assert batch.status == ("success", "failed")
    # x_dot**2 = (x**4 - 1)/2 gives t = sqrt(2) * int_1^inf dx / sqrt(x**4 - 1) = K(1/2)
    assert batch.final_t[1] == pytest.approx(ellipk(0.5), rel=1e-4)
    assert batch.final_t[0] == 3.0


def test_a_member_without_inertia_fails_as_singular():
    batch = lg.simulate_batch(quartic(), {"x": 0.5, "x_dot": 0.0}, 1.0, parameters={"m": [1, 0]})
    assert batch.status == ("success", "failed")
    assert "mass matrix is singular" in batch.message[1]


def test_the_step_budget_holds_for_every_member():
    batch = lg.simulate_batch(quartic(), {"x": [0.1, 0.2], "x_dot": 0.0}, 3.0, max_steps=3)
    assert batch.status == ("failed", "failed")
    assert all("max_steps" in message for message in batch.message)


def test_members_that_all_stop_at_once_end_the_batch():
    batch = lg.simulate_batch(
        quartic(), {"x": [0.1, 0.2], "x_dot": 0.0}, 1.0, stop_when=lambda t, q, v: q[..., 0] - 5
    )
    assert batch.status == ("stopped", "stopped")
    assert tuple(batch.stop_time) == (0.0, 0.0)


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


def test_a_member_blows_up_at_its_closed_form_time_without_a_compiler(monkeypatch) -> None:
    monkeypatch.setattr(c_loop, "available", lambda: False)  # the vectorized NumPy batch
    batch = lg.simulate_batch(quartic(), {"x": [0.1, 1.0], "x_dot": 0.0}, 3.0)
    assert batch.status == ("success", "failed")
    assert batch.final_t[1] == pytest.approx(ellipk(0.5), rel=1e-4)
