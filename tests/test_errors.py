"""Errors decide their exit code by class: bad input (a ValueError) is 2, a failure 1."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian import errors


def _every_error_class() -> list[type[errors.LagrangianError]]:
    found, todo = [], [errors.LagrangianError]
    while todo:
        kind = todo.pop()
        found.append(kind)
        todo.extend(kind.__subclasses__())
    return found


def test_bad_input_is_2_and_a_failure_1_for_every_error_class() -> None:
    kinds = _every_error_class()
    assert {errors.ModelError, errors.SimulationInputError, errors.DerivationError} <= set(kinds)
    for kind in kinds:
        bad_input = issubclass(kind, (ValueError, errors.ArgumentError))
        expected = errors.BAD_INPUT if bad_input else errors.FAILURE
        assert kind.exit_code == expected, kind.__name__
    assert (errors.BAD_INPUT, errors.FAILURE) == (2, 1)


def test_bad_simulate_input_is_a_value_error_and_a_simulation_error() -> None:
    pendulum = lg.examples.simple_pendulum()
    with pytest.raises(ValueError, match="unknown method 'RK99'") as caught:
        lg.simulate(pendulum, t_span=1.0, method="RK99")
    assert isinstance(caught.value, lg.SimulationError)
    assert isinstance(caught.value, lg.SimulationInputError)
    assert caught.value.exit_code == 2
    assert [p.field for p in caught.value.problems] == ["method"]


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"t_span": (1.0, 0.0)}, "is not after the start"),
        ({"t_span": 1.0, "initial": {"thta": 0.1}}, "'thta' is not a coordinate or velocity"),
        ({"t_span": 1.0, "rtol": -1.0}, "rtol must be positive"),
    ],
)
def test_every_kind_of_bad_simulate_input_exits_2(options: dict, message: str) -> None:
    with pytest.raises(lg.SimulationInputError, match=message) as caught:
        lg.simulate(lg.examples.simple_pendulum(), **options)
    assert caught.value.exit_code == 2


def test_a_missing_initial_value_is_bad_input() -> None:
    (x,) = lg.coordinates("x")
    spring = lg.System(coordinates=[x], kinetic=lg.velocity(x) ** 2 / 2, potential=x**2 / 2)
    with pytest.raises(ValueError, match="no initial value for the coordinate x"):
        lg.simulate(spring, t_span=1.0)


def test_a_trajectory_of_mismatched_shapes_is_bad_input() -> None:
    with pytest.raises(lg.SimulationInputError, match=r"Trajectory.q has shape \(2, 2\)"):
        lg.Trajectory(
            t=[0.0, 1.0],
            q=np.zeros((2, 2)),
            q_dot=np.zeros((2, 1)),
            coordinates=("x",),
            energy=[0, 0],
        )


def test_a_failed_integration_stays_a_failure() -> None:
    (x,) = lg.coordinates("x")
    # x_ddot = 4 x**3 from x = 1 at rest blows up in finite time (t ~ 0.93)
    runaway = lg.System(coordinates=[x], kinetic=lg.velocity(x) ** 2 / 2, potential=-(x**4))
    with pytest.raises(lg.SimulationError, match="raise_on_failure=False") as caught:
        lg.simulate(runaway, {"x": 1.0, "x_dot": 0.0}, 5.0)
    assert not isinstance(caught.value, ValueError)
    assert caught.value.exit_code == 1
