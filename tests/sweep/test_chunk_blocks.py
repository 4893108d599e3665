"""A sweep's block of a constrained and of an unconstrained system runs as one simulate_batch
with the block's settings: the stored rows are the batch's own, a constrained start is moved
onto the constraints when project_initial asks it, and an unconstrained system refuses
project_initial as simulate_batch does."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.sweeps import chunk_run
from lagrangian.sweeps.chunk_run import ChunkSettings, run_chunk
from lagrangian.sweeps.variables import sweep_variables

TIMES = (0.0, 0.25, 0.5)
STEPPING: dict[str, Any] = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}


# a bob on a rod of length l, in the plane, in Cartesian coordinates
ROD_PENDULUM = """\
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, l: 1.0}
gravity: [0, -g]
particles: [{name: bob, mass: m, position: [x, y]}]
constraints: [{name: rod, holonomic: x**2 + y**2 - l**2}]
"""


def cartesian_pendulum() -> lg.System:
    return lg.loads(ROD_PENDULUM)


# two bobs started off the rod's circle (radii 1.04 and 1.17), at rest
OFF_THE_ROD = {"x": np.array([0.3, 0.6]), "y": np.array([-1.0, -1.0])}
AT_REST = {"x_dot": np.zeros(2), "y_dot": np.zeros(2)}


def settings(system: lg.System, **options: Any) -> ChunkSettings:
    return ChunkSettings(0.5, sweep_variables(system), TIMES, STEPPING, **options)


def no_member_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if a member runs alone (the block must run as one batch)."""

    def alone(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("a member ran by simulate: the block did not run as one batch")

    monkeypatch.setattr(chunk_run, "simulate_member", alone)


def test_an_unconstrained_block_stores_the_rows_of_simulate_batch(monkeypatch) -> None:
    no_member_runs(monkeypatch)
    system = lg.examples.double_pendulum()
    initial = {"theta": np.array([0.1, 0.4]), "phi": np.array([0.0, -0.3])}
    result = run_chunk(system, initial, {"m2": np.array([1.0, 2.0])}, settings(system))
    batch = lg.simulate_batch(
        system, initial, 0.5, parameters={"m2": [1.0, 2.0]}, t_eval=np.array(TIMES), **STEPPING
    )
    assert result.status == ("success", "success")
    np.testing.assert_array_equal(result.series["theta"], batch.q[:, :, 0])
    np.testing.assert_array_equal(result.series["phi_dot"], batch.q_dot[:, :, 1])


def test_a_constrained_block_is_moved_onto_the_constraints_in_one_batch(monkeypatch) -> None:
    no_member_runs(monkeypatch)
    system = cartesian_pendulum()
    start = {**OFF_THE_ROD, **AT_REST}
    result = run_chunk(system, start, {}, settings(system, project_initial=True))
    assert result.status == ("success", "success")
    radius = np.hypot(result.series["x"], result.series["y"])
    np.testing.assert_allclose(radius, 1.0, atol=1e-8)  # the rod's length, at every time
    batch = lg.simulate_batch(
        system, start, 0.5, project_initial=True, t_eval=np.array(TIMES), **STEPPING
    )
    np.testing.assert_array_equal(result.series["x"], batch.q[:, :, 0])


def test_a_constrained_block_off_the_constraints_without_projection_records_why() -> None:
    system = cartesian_pendulum()
    result = run_chunk(system, {**OFF_THE_ROD, **AT_REST}, {}, settings(system))
    assert result.status == ("failed", "failed")
    assert all("pass project_initial=True" in message for message in result.message)
    assert np.isnan(result.series["x"]).all()


def test_an_unconstrained_block_refuses_project_initial_by_name() -> None:
    system = lg.examples.simple_pendulum()
    with pytest.raises(SimulationInputError, match=r"project_initial moves states onto the"):
        run_chunk(
            system, {"theta": np.array([0.1, 0.2])}, {}, settings(system, project_initial=True)
        )
