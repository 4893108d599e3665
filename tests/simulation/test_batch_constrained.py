"""simulate_batch of constrained systems against independent references: each member against
the single simulate run of it (multipliers and residuals included), the rod tension of the
Cartesian pendulum against m (g cos(theta) + l omega^2), the knife edge's lambda = -m v omega,
the cylinder rolling down an incline (a = 2 g sin(alpha) / 3, friction m g sin(alpha) / 3), the
stop time at the bottom against the pendulum's quarter period K(sin(theta0 / 2)) sqrt(l / g);
the path without the C loop (no compiler, RK4, a condition that is not an expression); and the
bad-input contract."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.errors import SimulationError, SimulationInputError
from lagrangian.numerics.fast import c_loop
from lagrangian.simulation.batch import run as batch_module
from lagrangian.simulation.batch.result import Batch

G = 9.81
THETA = np.array([0.3, 0.7, 1.2, 2.0])
LENGTH = np.array([1.0, 1.5, 0.8, 2.0])
MASS = np.array([2.0, 0.5, 1.0, 3.0])
TIGHT: dict[str, Any] = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}
GAINS = (10.0, 10.0)


def cartesian_pendulum(*constraints: Any) -> lg.System:
    x, y, m, g, l = sp.symbols("x y m g l")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: G, l: 1.0},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=constraints or [lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
    )


def knife_edge() -> lg.System:
    x, y, phi, m, inertia = sp.symbols("x y phi m I")
    x_dot, y_dot = sp.symbols("x_dot y_dot")
    return lg.System(
        coordinates=[x, y, phi],
        parameters={m: 1.5, inertia: 0.2},
        kinetic=m / 2 * (x_dot**2 + y_dot**2) + inertia / 2 * sp.Symbol("phi_dot") ** 2,
        constraints=[lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi))],
    )


def pendulum_starts(theta: np.ndarray = THETA, length: np.ndarray = LENGTH) -> dict[str, Any]:
    return {"x": length * np.sin(theta), "y": -length * np.cos(theta), "x_dot": 0.0, "y_dot": 0.0}


def member(values: dict[str, Any], i: int) -> dict[str, float]:
    return {name: float(np.broadcast_to(v, (len(THETA),))[i]) for name, v in values.items()}


@pytest.fixture
def without_c_loop(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """The default backend on a machine without a C compiler (SciPy's solvers)."""
    monkeypatch.setattr(c_loop, "available", lambda: False)
    yield


@pytest.fixture
def paths(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The path each constrained batch took: ``loop`` (the C loop) or ``simulate``."""
    taken: list[str] = []
    native = batch_module.native_constrained_members

    def in_loop(*args: Any, **kwargs: Any) -> Any:
        members = native(*args, **kwargs)
        taken.append("simulate" if members is None else "loop")
        return members

    monkeypatch.setattr(batch_module, "native_constrained_members", in_loop)
    return taken


def assert_member_is_simulate(batch: Batch, i: int, single: lg.Trajectory) -> None:
    """Member i of ``batch`` is the Trajectory ``single`` (to 1e-10, every column)."""
    alone = batch.trajectory(i)
    assert alone.names == single.names and alone.multiplier_names == single.multiplier_names
    assert alone.status == single.status
    assert [e.name for e in alone.events] == [e.name for e in single.events]
    np.testing.assert_allclose(alone.t, single.t, rtol=0, atol=1e-10)
    for name in single.names:
        np.testing.assert_allclose(alone[name], single[name], rtol=1e-10, atol=1e-10)
    assert alone.constraint_residual is not None and single.constraint_residual is not None
    np.testing.assert_allclose(
        alone.constraint_residual, single.constraint_residual, rtol=0, atol=1e-10
    )


# --- the Cartesian pendulum: members, tension, parameters per member -----------------------


@pytest.fixture(scope="module")
def pendulum() -> lg.EquationsOfMotion:
    return lg.derive(cartesian_pendulum())


@pytest.fixture(scope="module")
def pendulums(pendulum: lg.EquationsOfMotion) -> Batch:
    return lg.simulate_batch(
        pendulum,
        pendulum_starts(),
        2.0,
        parameters={"l": LENGTH, "m": MASS},
        baumgarte=GAINS,
        samples=21,
        **TIGHT,
    )


def test_each_pendulum_is_the_single_simulation_of_it(
    pendulum: lg.EquationsOfMotion, pendulums: Batch
) -> None:
    assert pendulums.status == ("success",) * len(THETA)
    assert pendulums.multiplier_names == ("lambda_1",)
    assert pendulums.multipliers is not None and pendulums.multipliers.shape == (4, 21, 1)
    for i in range(len(THETA)):
        single = lg.simulate(
            pendulum,
            member(pendulum_starts(), i),
            2.0,
            parameters={"l": LENGTH[i], "m": MASS[i]},
            baumgarte=GAINS,
            samples=21,
            **TIGHT,
        )
        assert_member_is_simulate(pendulums, i, single)


def test_the_multiplier_is_the_rod_tension_of_each_member(pendulums: Batch) -> None:
    assert pendulums.multipliers is not None and pendulums.constraint_residual is not None
    x, y = pendulums.q[..., 0], pendulums.q[..., 1]
    speed2 = np.sum(pendulums.q_dot**2, axis=-1)
    m, l = MASS[:, None], LENGTH[:, None]
    cos_theta, omega2 = -y / l, speed2 / l**2
    tension = m * (G * cos_theta + l * omega2)
    # lambda grad(x^2 + y^2 - l^2) = 2 lambda (x, y): the rod pulls with 2 |lambda| l
    np.testing.assert_allclose(-2 * pendulums.multipliers[..., 0] * l, tension, rtol=1e-8)
    np.testing.assert_allclose(np.hypot(x, y), np.broadcast_to(l, x.shape), atol=1e-9)
    assert np.max(pendulums.constraint_residual) < 1e-8
    final = pendulums.final_multipliers
    assert final is not None
    np.testing.assert_allclose(final[:, 0], pendulums.multipliers[:, -1, 0], rtol=1e-12)


# --- the knife edge: a velocity constraint --------------------------------------------------


def test_the_knife_edge_multiplier_is_minus_m_v_omega() -> None:
    skate = knife_edge()
    speed, spin, heading = np.array([2.0, 1.0, 0.5, 3.0]), np.array([1.0, -2.0, 0.3, 0.0]), 0.3
    starts = {
        "x": 0.0,
        "y": 0.0,
        "phi": heading,
        "x_dot": speed * np.cos(heading),
        "y_dot": speed * np.sin(heading),
        "phi_dot": spin,
    }
    batch = lg.simulate_batch(skate, starts, 3.0, parameters={"m": MASS}, samples=31, **TIGHT)
    assert batch.status == ("success",) * 4 and batch.multipliers is not None
    v = np.hypot(batch.q_dot[..., 0], batch.q_dot[..., 1])
    # the blade does no work: the speed stays
    np.testing.assert_allclose(v, np.broadcast_to(speed[:, None], v.shape), rtol=1e-8)
    expected = -MASS[:, None] * v * batch.q_dot[..., 2]
    np.testing.assert_allclose(batch.multipliers[..., 0], expected, rtol=1e-8, atol=1e-10)
    for i in (0, 1):
        single = lg.simulate(
            skate, member(starts, i), 3.0, parameters={"m": MASS[i]}, samples=31, **TIGHT
        )
        assert_member_is_simulate(batch, i, single)


# --- the cylinder on an incline: rolling without slipping -----------------------------------


def test_the_cylinder_rolls_down_each_incline_with_its_friction() -> None:
    incline = lg.examples.cylinder_on_incline()
    alpha = np.array([0.1, 0.3, 0.6])
    rest = {"x": 0.0, "phi": 0.0, "x_dot": 0.0, "phi_dot": 0.0}
    batch = lg.simulate_batch(incline, rest, 1.0, parameters={"alpha": alpha}, samples=11)
    assert batch.multipliers is not None and batch.status == ("success",) * 3
    t, sin = batch.t, np.sin(alpha)[:, None]
    x = batch.q[..., 0]
    rolled = np.broadcast_to(G * sin * t**2 / 3, x.shape)
    np.testing.assert_allclose(x, rolled, rtol=1e-7, atol=1e-12)
    # friction along the slope: m x_ddot = m g sin(alpha) + lambda, x_ddot = 2 g sin(alpha) / 3
    expected = np.broadcast_to(-G * sin / 3, batch.multipliers[..., 0].shape)
    np.testing.assert_allclose(batch.multipliers[..., 0], expected, rtol=1e-8)
    single = lg.simulate(incline, rest, 1.0, parameters={"alpha": 0.3}, samples=11)
    assert_member_is_simulate(batch, 1, single)


# --- stop_when -----------------------------------------------------------------------------


def at_the_bottom(t: Any, q: Any, q_dot: Any) -> Any:
    return q[..., 0]  # x: positive on the starting side, zero below the pivot


def quarter_period(theta: np.ndarray, length: np.ndarray) -> np.ndarray:
    return np.asarray(ellipk(np.sin(theta / 2) ** 2) * np.sqrt(length / G))


def stop_event(stop_when: Callable[..., Any]) -> Callable[..., float]:
    def stop_when_event(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(np.asarray(stop_when(np.array([t]), q[None, :], q_dot[None, :])).ravel()[0])

    stop_when_event.__name__ = "stop_when"
    stop_when_event.terminal = True  # type: ignore[attr-defined]
    stop_when_event.direction = -1.0  # type: ignore[attr-defined]
    return stop_when_event


def check_stops(pendulum: lg.EquationsOfMotion, stop_when: Callable[..., Any], **keywords: Any):
    theta = np.array([0.3, 1.0, -0.5, 2.5])  # the third starts on the other side: stops at once
    starts = pendulum_starts(theta)
    batch = lg.simulate_batch(
        pendulum,
        starts,
        3.0,
        parameters={"l": LENGTH},
        stop_when=stop_when,
        samples=31,
        **keywords,
    )
    assert batch.status == ("stopped",) * 4
    expected = quarter_period(np.abs(theta), LENGTH)
    expected[2] = 0.0
    np.testing.assert_allclose(batch.stop_time, expected, rtol=1e-8, atol=1e-12)
    assert batch.final_multipliers is not None and batch.multipliers is not None
    # at the bottom the tension is m (g + l omega^2), omega^2 = 2 g (1 - cos theta0) / l
    bottom = G * (1 + 2 * (1 - np.cos(theta)))
    for i in (0, 1, 3):
        tension = -2 * batch.final_multipliers[i, 0] * LENGTH[i]
        np.testing.assert_allclose(tension, bottom[i], rtol=1e-7)
        single = lg.simulate(
            pendulum,
            member(starts, i),
            3.0,
            parameters={"l": LENGTH[i]},
            events=[stop_event(stop_when)],
            samples=31,
            **keywords,
        )
        assert_member_is_simulate(batch, i, single)
    stopped = batch.trajectory(2)
    assert len(stopped.t) == 1 and stopped.events[0].t == 0.0
    assert stopped.multipliers is not None and stopped.multipliers[0, 0] < 0
    return batch


def test_stop_when_ends_each_pendulum_at_the_bottom(
    pendulum: lg.EquationsOfMotion, paths: list[str]
) -> None:
    check_stops(pendulum, at_the_bottom, **TIGHT)
    assert paths == (["loop"] if c_loop.available() else ["simulate"])


# --- without the C loop: simulate member by member -----------------------------------------


@pytest.mark.usefixtures("without_c_loop")
def test_without_a_c_compiler_members_are_simulated_one_by_one(
    pendulum: lg.EquationsOfMotion, pendulums: Batch, paths: list[str]
) -> None:
    batch = lg.simulate_batch(
        pendulum,
        pendulum_starts(),
        2.0,
        parameters={"l": LENGTH, "m": MASS},
        baumgarte=GAINS,
        samples=21,
        **TIGHT,
    )
    assert batch.status == pendulums.status
    assert batch.multipliers is not None and pendulums.multipliers is not None
    # SciPy's DOP853 and the C loop's: the same steps, to rounding
    np.testing.assert_allclose(batch.q, pendulums.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(batch.multipliers, pendulums.multipliers, rtol=1e-8)
    check_stops(pendulum, at_the_bottom, **TIGHT)
    assert paths == ["simulate", "simulate"]


def test_rk4_members_are_the_single_rk4_runs(
    pendulum: lg.EquationsOfMotion, paths: list[str]
) -> None:
    batch = lg.simulate_batch(
        pendulum,
        pendulum_starts(),
        1.0,
        parameters={"l": LENGTH},
        method="RK4",
        dt=0.01,
        t_eval=[0.0, 1.0],
    )
    assert batch.method == "RK4" and batch.t.tolist() == [0.0, 1.0]
    for i in (0, 3):
        single = lg.simulate(
            pendulum,
            member(pendulum_starts(), i),
            1.0,
            parameters={"l": LENGTH[i]},
            method="RK4",
            dt=0.01,
            t_eval=[0.0, 1.0],
        )
        assert_member_is_simulate(batch, i, single)
    assert paths == ["loop"]  # RK4 runs in the C loop too


def test_a_condition_that_is_not_an_expression_runs_through_simulate(
    pendulum: lg.EquationsOfMotion, paths: list[str]
) -> None:
    def branching(t: Any, q: Any, q_dot: Any) -> Any:
        x = np.asarray(q[..., 0], dtype=float)  # numbers only: SymEngine cannot trace it
        return np.where(x > 0, x, x)

    check_stops(pendulum, branching, **TIGHT)
    assert paths == ["simulate"]


# --- the start on the constraints, and bad input --------------------------------------------


def test_members_off_the_constraints_are_refused_together_or_projected(
    pendulum: lg.EquationsOfMotion,
) -> None:
    x = pendulum_starts()["x"]
    starts = {**pendulum_starts(), "x": x * [1.0, 1.3, 1.0, 0.5]}
    with pytest.raises(SimulationInputError, match=r"members 1, 3 start off the constraints"):
        lg.simulate_batch(pendulum, starts, 0.1, parameters={"l": LENGTH})
    batch = lg.simulate_batch(
        pendulum, starts, 0.1, parameters={"l": LENGTH}, project_initial=True, samples=3
    )
    radius = np.hypot(batch.q[..., 0], batch.q[..., 1])
    np.testing.assert_allclose(radius, np.broadcast_to(LENGTH[:, None], radius.shape))
    np.testing.assert_allclose(batch.initial["x"], batch.q[:, 0, 0])
    single = lg.simulate(
        pendulum,
        member(starts, 1),
        0.1,
        parameters={"l": LENGTH[1]},
        project_initial=True,
        samples=3,
    )
    assert_member_is_simulate(batch, 1, single)


def test_options_that_do_not_apply_are_refused_by_name(pendulum: lg.EquationsOfMotion) -> None:
    starts = pendulum_starts()
    with pytest.raises(SimulationInputError, match=r"method: simulate_batch has no method 'Radau'"):
        lg.simulate_batch(pendulum, starts, 0.1, parameters={"l": LENGTH}, method="Radau")
    with pytest.raises(SimulationInputError, match=r"baumgarte: baumgarte must be a pair"):
        lg.simulate_batch(pendulum, starts, 0.1, parameters={"l": LENGTH}, baumgarte=(-1, 1))
    with pytest.raises(SimulationInputError, match=r"baumgarte stabilizes constraints"):
        lg.simulate_batch(
            lg.examples.simple_pendulum(), {"theta": [0.1, 0.2]}, 0.1, baumgarte=(1, 1)
        )
    with pytest.raises(SimulationInputError, match=r"project_initial moves states"):
        lg.simulate_batch(
            lg.examples.simple_pendulum(), {"theta": [0.1, 0.2]}, 0.1, project_initial=True
        )
    x, y = sp.symbols("x y")
    string = cartesian_pendulum(lg.Unilateral(1 - x**2 - y**2, name="string"))
    with pytest.raises(SimulationInputError, match=r"constraints: .*unilateral"):
        lg.simulate_batch(string, pendulum_starts(length=np.ones(4)), 0.1)


def test_backend_numba_runs_a_constrained_batch_as_the_default(
    pendulum: lg.EquationsOfMotion,
) -> None:
    runs = [
        lg.simulate_batch(
            pendulum, pendulum_starts(), 0.1, parameters={"l": LENGTH}, backend=backend
        )
        for backend in ("numpy", "numba")
    ]
    np.testing.assert_array_equal(runs[0].q, runs[1].q)
    assert runs[1].backend == "numba"


def test_a_batch_takes_its_constraint_columns_together() -> None:
    fields: dict[str, Any] = {
        "t": [0.0],
        "q": np.zeros((1, 1, 1)),
        "q_dot": np.zeros((1, 1, 1)),
        "energy": np.zeros((1, 1)),
        "coordinates": ("x",),
        "status": ("success",),
        "message": ("",),
        "final_t": [0.0],
        "final_q": np.zeros((1, 1)),
        "final_q_dot": np.zeros((1, 1)),
        "final_energy": np.zeros(1),
    }
    with pytest.raises(SimulationError, match=r"together, or none of them"):
        Batch(**fields, multiplier_names=("lambda_1",), multipliers=np.zeros((1, 1, 1)))
    with pytest.raises(SimulationError, match=r"Batch.multipliers has shape"):
        Batch(
            **fields,
            multiplier_names=("lambda_1",),
            multipliers=np.zeros((1, 2, 1)),
            constraint_residual=np.zeros((1, 1)),
            final_multipliers=np.zeros((1, 1)),
            final_constraint_residual=np.zeros(1),
        )


# --- a sweep's constrained blocks -----------------------------------------------------------


def test_a_sweeps_constrained_block_runs_as_one_batch(monkeypatch: pytest.MonkeyPatch) -> None:
    from lagrangian.sweeps import chunk_run
    from lagrangian.sweeps.variables import sweep_variables

    incline = lg.examples.cylinder_on_incline()
    times = (0.0, 0.5, 1.0)
    settings = chunk_run.ChunkSettings(1.0, sweep_variables(incline), times, {"samples": 3})
    alone: list[int] = []
    one_member = chunk_run.simulate_member

    def counted(*args: Any, **kwargs: Any) -> lg.Trajectory:
        alone.append(1)
        return one_member(*args, **kwargs)

    monkeypatch.setattr(chunk_run, "simulate_member", counted)
    alpha = np.array([0.1, 0.3])
    block = chunk_run.run_chunk(incline, {}, {"alpha": alpha}, settings)
    assert alone == [] and block.status == ("success", "success")
    friction = np.broadcast_to(-G * np.sin(alpha)[:, None] / 3, (2, 3))
    np.testing.assert_allclose(block.series["lambda_1"], friction, rtol=1e-8)
    assert np.all(block.drifts["constraint_drift"] < 1e-12)
    # a member off the constraints: the batch refuses the block, each member runs alone
    block = chunk_run.run_chunk(incline, {"x": [0.0, 0.1]}, {"alpha": alpha}, settings)
    assert len(alone) == 2 and block.status == ("success", "failed")
    assert "violates the constraints" in block.message[1]


@pytest.mark.parametrize("loop", [True, False], ids=["C loop", "simulate"])
def test_a_member_that_fails_keeps_its_rows_and_says_why(
    pendulum: lg.EquationsOfMotion, monkeypatch: pytest.MonkeyPatch, loop: bool
) -> None:
    if not loop:
        monkeypatch.setattr(c_loop, "available", lambda: False)
    budget = {"max_steps": 30, "samples": 11}
    batch = lg.simulate_batch(pendulum, pendulum_starts(), 10.0, parameters={"l": LENGTH}, **budget)
    assert batch.status == ("failed",) * 4
    assert all("max_steps" in message for message in batch.message)
    single = lg.simulate(
        pendulum, member(pendulum_starts(), 0), 10.0, raise_on_failure=False, **budget
    )
    alone = batch.trajectory(0)
    assert alone.status == single.status == "failed"
    np.testing.assert_array_equal(alone.t, single.t)
    assert alone.multipliers is not None and single.multipliers is not None
    np.testing.assert_allclose(alone.multipliers, single.multipliers, rtol=1e-10)
