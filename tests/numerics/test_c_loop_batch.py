"""Batches in the C loop (simulation/batch/native.py): every member as simulate of that member
alone and as the NumPy batch, stop conditions at their closed-form times (a function or a
sweep's text condition), and the NumPy batch where the loop does not apply."""

from __future__ import annotations

import math

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.io.load import loads
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.settings import Settings
from lagrangian.simulation.batch import native as batch_native
from lagrangian.sweeps.stop_condition import stop_expression

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler")

TOL = {"rtol": 1e-10, "atol": 1e-10}
ANGLES = np.linspace(0.5, 2.5, 6)
REST = {"phi": 0.0, "theta_dot": 0.0, "phi_dot": 0.0}
FALLING = """
name: falling particle
coordinates: [y]
parameters: {m: 2.0, g: 9.81}
kinetic: m*y_dot**2/2
potential: m*g*y
"""
HEIGHTS = np.array([1.0, 2.0, 5.0, 50.0])


@pytest.fixture
def numpy_batch(monkeypatch: pytest.MonkeyPatch):
    """simulate_batch with the C loop switched off (the vectorized NumPy batch)."""

    def run(*arguments, **keywords):
        with monkeypatch.context() as patch:
            patch.setattr(c_loop, "available", lambda: False)
            return lg.simulate_batch(*arguments, **keywords)

    return run


def floor(t, q, q_dot):
    return q[..., 0]


def same_batch(native: lg.Batch, numpy: lg.Batch) -> None:
    assert native.status == numpy.status and native.message == numpy.message
    np.testing.assert_array_equal(np.isnan(native.q), np.isnan(numpy.q))
    np.testing.assert_allclose(native.q, numpy.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.q_dot, numpy.q_dot, rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.final_t, numpy.final_t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.final_q, numpy.final_q, rtol=0, atol=1e-9)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_members_are_simulate_of_each_member_and_the_numpy_batch(method, numpy_batch) -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    options = {"method": method, "samples": 21, **TOL}
    initial = {"theta": ANGLES, **REST}
    parameters = {"m2": np.linspace(0.5, 2.0, len(ANGLES))}
    native = lg.simulate_batch(eom, initial, 3.0, parameters=parameters, **options)
    for i in (0, 3, 5):
        alone = lg.simulate(
            eom,
            {"theta": ANGLES[i], **REST},
            3.0,
            parameters={"m2": parameters["m2"][i]},
            **options,
        )
        np.testing.assert_allclose(native.q[i], alone.q, rtol=0, atol=1e-9)
    same_batch(native, numpy_batch(eom, initial, 3.0, parameters=parameters, **options))


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_a_stop_condition_stops_each_member_at_its_closed_form_time(method, numpy_batch) -> None:
    eom = lg.derive(loads(FALLING))
    options = {"method": method, "samples": 11, **TOL}
    initial = {"y": HEIGHTS, "y_dot": 0.0}
    native = lg.simulate_batch(eom, initial, 3.0, stop_when=floor, **options)
    hits = np.sqrt(2 * HEIGHTS / 9.81)
    assert native.status == ("stopped", "stopped", "stopped", "success")
    np.testing.assert_allclose(native.final_t[:3], hits[:3], rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.final_q[:3, 0], 0.0, atol=1e-9)
    same_batch(native, numpy_batch(eom, initial, 3.0, stop_when=floor, **options))


def test_a_sweeps_text_condition_runs_in_the_loop(monkeypatch, numpy_batch) -> None:
    system = loads(FALLING)
    stop = stop_expression(system, "y - 0.5")
    ran: list[bool] = []
    original = batch_native.native_members

    def watched(*arguments, **keywords):
        result = original(*arguments, **keywords)
        ran.append(result is not None)
        return result

    monkeypatch.setattr("lagrangian.simulation.batch.run.native_members", watched)
    initial = {"y": HEIGHTS, "y_dot": 0.0}
    native = lg.simulate_batch(system, initial, 3.0, stop_when=stop, method="DOP853", **TOL)
    assert ran == [True]
    hits = np.sqrt(2 * (HEIGHTS - 0.5) / 9.81)
    np.testing.assert_allclose(native.final_t[:3], hits[:3], rtol=0, atol=1e-9)
    same_batch(native, numpy_batch(system, initial, 3.0, stop_when=stop, method="DOP853", **TOL))


def test_a_member_stopped_at_the_start_stops_there(numpy_batch) -> None:
    eom = lg.derive(loads(FALLING))
    initial = {"y": np.array([-1.0, 1.0]), "y_dot": 0.0}
    native = lg.simulate_batch(eom, initial, 1.0, stop_when=floor, samples=5, **TOL)
    assert native.status == ("stopped", "stopped") and native.final_t[0] == 0.0
    same_batch(native, numpy_batch(eom, initial, 1.0, stop_when=floor, samples=5, **TOL))


def test_where_the_loop_does_not_apply_the_numpy_batch_runs() -> None:
    eom = lg.derive(loads(FALLING))
    compiled = compile_equations(eom)
    X0, P = np.array([[1.0, 0.0]]), np.array([[2.0, 9.81]])

    def branching(t, q, q_dot):
        return np.where(q[..., 0] > 0, q[..., 0], -1.0)

    dop853 = Settings("DOP853", (0.0, 1.0), np.linspace(0, 1, 3), 1e-10, 1e-10)
    assert batch_native.native_members(eom, compiled, dop853, X0, P, branching) is None
    batch = lg.simulate_batch(eom, {"y": HEIGHTS, "y_dot": 0.0}, 3.0, stop_when=branching)
    hit = math.sqrt(2 * HEIGHTS[0] / 9.81)
    assert batch.final_t[0] == pytest.approx(hit, abs=1e-7)


def test_progress_goes_over_the_span_member_by_member() -> None:
    seen: list[float] = []
    eom = lg.derive(loads(FALLING))
    lg.simulate_batch(eom, {"y": HEIGHTS, "y_dot": 0.0}, 2.0, progress=seen.append)
    assert seen == [0.5, 1.0, 1.5, 2.0]


def test_a_member_without_inertia_fails_as_singular_with_a_stop_condition(numpy_batch) -> None:
    eom = lg.derive(loads(FALLING))
    options = {"initial": {"y": 1.0, "y_dot": 0.0}, "parameters": {"m": [2.0, 0.0]}}
    native = lg.simulate_batch(eom, t_span=1.0, stop_when=floor, **options)
    assert native.status == ("stopped", "failed") and "singular" in native.message[1]
    same_batch(native, numpy_batch(eom, t_span=1.0, stop_when=floor, **options))
