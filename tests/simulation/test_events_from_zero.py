"""Event functions that start a step on their zero (a guard that just fired, or one a reset
put the state on) are read on the step's dense output: a crossing back within the first step
is found where the function's closed form has its root, a guard crossing in the same step is
found too, and leaving the zero is a crossing only in the function's direction and only for
a function that did not just fire there."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.simulation.integrators.events import EventWatch


def named(function, name: str, direction: float, terminal: bool = True):
    function.__name__, function.direction, function.terminal = name, direction, terminal
    return function


def watch_of(*functions) -> EventWatch:
    return EventWatch(functions, lambda t, x: (x[:1], x[1:]))


def dense(s):
    """The state is (s, 0) along the step: each function below is its own closed form."""
    return np.array([s, 0.0])


def test_a_guard_leaving_its_zero_and_crossing_back_in_one_step_is_found() -> None:
    # g(s) = s (s - 0.3): leaves 0 downwards, rises back through 0 at s = 0.3
    rock = named(lambda t, q, q_dot: q[0] * (q[0] - 0.3), "rock", +1.0)
    # another guard, away from its zero, crossing later in the same step
    wall = named(lambda t, q, q_dot: q[0] - 0.7, "wall", +1.0, terminal=False)
    watch = watch_of(rock, wall)
    watch.start(0.0, dense(0.0))
    found, stop = watch.check(0.0, 1.0, dense(1.0), dense)
    assert [watch.names[i] for i, _ in found] == ["rock"] and stop
    assert found[0][1] == pytest.approx(0.3, abs=1e-14)
    watch = watch_of(named(lambda t, q, q_dot: q[0] * (q[0] - 0.3), "rock", 1.0, False), wall)
    watch.start(0.0, dense(0.0))
    found, _ = watch.check(0.0, 1.0, dense(1.0), dense)
    assert [(watch.names[i], round(t, 12)) for i, t in found] == [("rock", 0.3), ("wall", 0.7)]


def test_a_return_early_in_a_long_step_is_found() -> None:
    """A rock ten thousand times shorter than the step (a rimless wheel near rest)."""
    rock = named(lambda t, q, q_dot: q[0] * (q[0] - 1e-4), "rock", +1.0)
    watch = watch_of(rock)
    watch.start(0.0, dense(0.0))
    found, _ = watch.check(0.0, 1.0, dense(1.0), dense)
    assert found and found[0][1] == pytest.approx(1e-4, rel=1e-10)


def test_leaving_the_zero_is_a_crossing_only_in_the_direction_and_unless_just_fired() -> None:
    down = named(lambda t, q, q_dot: -q[0], "down", -1.0)  # leaves 0 falling
    up = named(lambda t, q, q_dot: q[0], "up", -1.0)  # leaves 0 rising: no falling crossing
    watch = watch_of(down, up)
    watch.start(0.0, dense(0.0))
    found, _ = watch.check(0.0, 1.0, dense(1.0), dense)
    assert found == [(0, 0.0)]  # the start itself, as a sign change from 0 is
    watch = watch_of(down, up)
    watch.disarmed = {0}  # "down" has just fired here
    watch.start(0.0, dense(0.0))
    assert watch.check(0.0, 1.0, dense(1.0), dense) == ([], False)


def test_a_guard_that_stays_on_its_zero_is_read_again_next_step() -> None:
    # g = 0 over the whole first step; in the second it rises off zero at s = 1 and falls
    # back through it at s = 2.5
    def late(t, q, q_dot):
        s = q[0]
        return 0.0 if s <= 1.0 else -(s - 1.0) * (s - 2.5)

    watch = watch_of(named(late, "late", -1.0))
    watch.start(0.0, dense(0.0))
    assert watch.check(0.0, 1.0, dense(1.0), dense) == ([], False)
    found, _ = watch.check(1.0, 3.0, dense(3.0), dense)
    assert found and found[0][1] == pytest.approx(2.5, abs=1e-12)
