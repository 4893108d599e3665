"""The one piecewise loop: every hybrid motion (switching surfaces, active sets of unilateral
constraints) is a frozen value whose modes are values, so one run leaves nothing behind for
the next; and the one Python loop steps the variational integrators too (their budget and
Ctrl-C are the loop's)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.simulation.integrators.piecewise import PiecewiseIntegrator
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare
from lagrangian.simulation.switching import SwitchedDynamics, SwitchMode
from lagrangian.simulation.variational import midpoint


def friction_block() -> lg.System:
    """A block on a rough floor pushed by a spring: Coulomb friction mu m g sign(x_dot)."""
    x, m, k, mu, g = sp.symbols("x m k mu g")
    return lg.System(
        coordinates=[x],
        parameters={m: 1.0, k: 4.0, mu: 0.3, g: 9.81},
        kinetic=m * sp.Symbol("x_dot") ** 2 / 2,
        potential=k * x**2 / 2,
        generalized_forces={x: -mu * m * g * sp.sign(sp.Symbol("x_dot"))},
        initial={"x": 2.0, "x_dot": 0.0},
    )


def test_a_switched_motion_is_a_frozen_value_and_runs_twice_alike() -> None:
    setup = prepare(friction_block(), None, 6.0, {"samples": 61})
    dynamics, integrator = plan(setup)
    assert isinstance(dynamics, SwitchedDynamics) and isinstance(integrator, PiecewiseIntegrator)
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign"):
        dynamics.p = np.zeros(4)  # type: ignore[misc]
    inputs = dynamics.start(setup.inputs, False)
    first = integrator.run(dynamics, inputs, None, None)
    second = integrator.run(dynamics, inputs, None, None)
    assert np.array_equal(first.x, second.x)
    assert [e[0] for e in first.events] == [e[0] for e in second.events]
    # the block slides to x where the spring force k x no longer beats friction mu m g, and
    # sticks there: the swing loses 2 mu m g / k = 1.4715 of amplitude (2.0 -> -0.5285)
    assert any(name.endswith(": slide") for name, _, _ in first.events)
    assert abs(first.x[-1, 0] + (2.0 - 2 * 0.3 * 9.81 / 4.0)) < 1e-6
    assert abs(first.x[-1, 1]) < 1e-9


def test_a_mode_is_a_value() -> None:
    mode = SwitchMode((1.0, -1.0))
    assert mode.leaving(0, -1.0) == SwitchMode((-1.0, -1.0))
    assert mode.sliding_on(1).leaving(1, 1.0) == SwitchMode((1.0, 1.0), None)
    assert mode == SwitchMode((1.0, -1.0))  # unchanged by what was made from it


def test_the_numpy_variational_march_keeps_the_wall_time_budget(monkeypatch) -> None:
    # the NumPy steps go through the one Python loop, whose budget stops a run that takes too
    # long and keeps its rows (the compiled march runs to the end in milliseconds)
    monkeypatch.setattr(midpoint, "COMPILED", False)
    run = lg.simulate(
        lg.examples.double_pendulum(),
        t_span=100.0,
        method="variational",
        dt=0.001,
        samples=100_001,  # a row at every step
        max_wall_time=0.3,
        raise_on_failure=False,
    )
    assert run.status == "failed" and "max_wall_time" in run.message
    assert 10 < len(run.t) < 100_001 and run.t[-1] < 100.0
    assert np.allclose(np.diff(run.t), 0.001)
    assert np.all(np.isfinite(run.q))
