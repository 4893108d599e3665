"""The compiled variational marches make their nodes as they reach them: the same nodes and
output rows as the grid made in advance (StepSchedule.grid, the NumPy march's), the midpoint
rule's exact map on a harmonic oscillator to rounding, the multipliers of the NumPy march at
sampled outputs, and a run of 10^6 steps in the memory of its output rows."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
from lagrangian.simulation import simulate
from lagrangian.simulation.variational import midpoint as variational
from lagrangian.simulation.variational.collocation import gauss
from lagrangian.simulation.variational.collocation_march import collocation_march
from lagrangian.simulation.variational.march import StepSchedule, march

pytest.importorskip("numba")

from lagrangian.simulation.variational import compiled as variational_fast

X, X_DOT = sp.symbols("x x_dot")


def oscillator() -> lg.System:
    return lg.System(coordinates=[X], kinetic=X_DOT**2 / 2, potential=X**2 / 2)


SCHEDULES = {
    "every node": StepSchedule(0.0, 1.0, 0.1),
    "a shorter last step": StepSchedule(0.0, 1.05, 0.1),
    "outputs on the nodes": StepSchedule(0.0, 1.0, 0.1, np.linspace(0.0, 1.0, 6)),
    "outputs between the nodes": StepSchedule(0.0, 1.0, 0.1, np.array([0.0, 0.25, 0.33, 1.0])),
    "outputs a hair from a node": StepSchedule(
        0.0, 1.0, 0.1, np.array([0.1 + 1e-12, 0.3 - 1e-12, 0.55, 0.9999999999999])
    ),
    "outputs after the start only": StepSchedule(0.5, 2.0, 0.25, np.array([1.1, 1.9])),
}


@pytest.mark.parametrize("name", SCHEDULES)
def test_the_nodes_made_on_the_way_are_the_grid_made_in_advance(name: str) -> None:
    schedule = SCHEDULES[name]
    eom = lg.derive(lg.examples.simple_pendulum())
    mechanics = compile_discrete_mechanics(eom)
    p, x0 = np.array([1.0, 9.81, 1.0]), np.array([0.8, 0.0])
    grid, outputs = schedule.grid()
    compiled = variational_fast.fast_march(mechanics, x0, p, schedule)
    reference = march(mechanics, x0, p, grid, outputs)
    assert compiled.failure is None and reference.failure is None
    np.testing.assert_array_equal(compiled.outputs, outputs)
    np.testing.assert_array_equal(compiled.t, grid[outputs])
    assert compiled.reached == reference.reached == grid[-1]
    np.testing.assert_allclose(compiled.q, reference.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(compiled.q_dot, reference.q_dot, rtol=0, atol=1e-12)
    tableau = gauss(2)
    stages = variational_fast.fast_collocation_march(mechanics, tableau, x0, p, schedule)
    stage_reference = collocation_march(mechanics, tableau, x0, p, grid, outputs)
    np.testing.assert_array_equal(stages.t, grid[outputs])
    np.testing.assert_allclose(stages.q, stage_reference.q, rtol=0, atol=1e-12)


def test_the_midpoint_rule_is_the_cayley_map_of_the_harmonic_oscillator() -> None:
    # x'' = -x: the implicit midpoint map of y = (x, v), y' = A y, is exactly
    # y_{k+1} = (1 - dt A/2)^-1 (1 + dt A/2) y_k (Hairer, Lubich & Wanner, section VI.4)
    dt, steps = 0.05, 10_000
    run = simulate(oscillator(), {"x": 1.0, "x_dot": 0.0}, steps * dt, method="variational", dt=dt)
    a = np.array([[0.0, 1.0], [-1.0, 0.0]])
    step = np.linalg.solve(np.eye(2) - dt * a / 2, np.eye(2) + dt * a / 2)
    y, expected = np.array([1.0, 0.0]), []
    for _ in range(steps + 1):
        expected.append(y)
        y = step @ y
    expected_states = np.array(expected)
    np.testing.assert_allclose(run.q[:, 0], expected_states[:, 0], rtol=0, atol=1e-11)
    np.testing.assert_allclose(run.q_dot[:, 0], expected_states[:, 1], rtol=0, atol=1e-11)


def cartesian_pendulum() -> lg.System:
    x, y, m, l, g = sp.symbols("x y m l g")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, l: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
    )


@pytest.mark.parametrize("samples", [None, 2, 3, 11])
def test_the_multipliers_at_sampled_outputs_are_the_numpy_marchs(
    samples: int | None, monkeypatch: pytest.MonkeyPatch
) -> None:
    eom = lg.derive(cartesian_pendulum())
    start = {"x": np.sin(1.0), "y": -np.cos(1.0), "x_dot": 0.0, "y_dot": 0.0}
    options = {"method": "variational", "dt": 0.01, "samples": samples}
    compiled = simulate(eom, start, 2.0, **options)
    monkeypatch.setattr(variational, "COMPILED", False)
    reference = simulate(eom, start, 2.0, **options)
    np.testing.assert_array_equal(compiled.t, reference.t)
    np.testing.assert_allclose(compiled.q, reference.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(compiled.multipliers, reference.multipliers, rtol=0, atol=1e-9)
    # the rod's tension against the multiplier form's at the same states
    tension = -2 * compiled.multipliers[:, 0]  # lambda dh/dq = 2 lambda (x, y): inward pull
    speed2 = np.sum(compiled.q_dot**2, axis=1)
    expected = speed2 + 9.81 * -compiled.q[:, 1]  # m v^2 / l + m g cos(theta)
    np.testing.assert_allclose(tension, expected, rtol=5e-3)  # second order in dt


def test_a_million_steps_keep_only_their_output_rows() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())
    simulate(
        eom, {"theta": 1.0, "theta_dot": 0.0}, 0.1, method="variational", dt=0.01, samples=11
    )  # compile
    tracemalloc.start()
    try:
        run = simulate(
            eom,
            {"theta": 1.0, "theta_dot": 0.0},
            10_000.0,
            method="variational",
            dt=0.01,
            samples=101,
        )
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert run.success and len(run.t) == 101 and run.t[-1] == 10_000.0
    error = np.abs(run.energy / run.energy[0] - 1)
    assert error.max() < 1e-4
    # a grid of the 10^6 steps alone would be 8 MB
    assert peak < 1_000_000, peak
