"""A batch's stop condition g(t, q, q_dot): a member ends where g turns negative.

The one Python loop watches it two ways: over the lanes of a batch stepped together
(:class:`StopWatch`, g called with the arrays of the lanes that moved, its zeros located on
their interpolants by the Illinois method, vectorized), and for a member run alone by
``simulate`` as a terminal event (:func:`stop_event`, called with the arrays of one member).
Either way a member whose g is negative at its start stops there (NaN is not negative: the
run decides, as in the C loop).

>>> import numpy as np
>>> event = stop_event(lambda t, q, q_dot: q[..., 0])
>>> event.__name__, event.terminal, event.direction, event(0.0, np.array([2.0]), np.array([0.0]))
('stop_when', True, -1.0, 2.0)
>>> negative_at_start(lambda t, q, q_dot: q[..., 0], 0.0, np.array([-1.0]), np.array([0.0]))
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from lagrangian.simulation.batch.dense import Dense, locate_stops
from lagrangian.simulation.integrators.events import EventFunction
from lagrangian.simulation.integrators.lanes import Found, LaneDense

#: The name of the terminal event a stop condition becomes.
STOP_EVENT = "stop_when"


def stop_event(stop_when: Callable[..., Any]) -> EventFunction:
    """``stop_when`` as the loop's terminal event where it turns negative."""

    def stop(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        value = stop_when(np.array([t]), np.asarray(q)[None, :], np.asarray(q_dot)[None, :])
        return float(np.asarray(value, dtype=float).reshape(-1)[0])

    stop.__name__ = STOP_EVENT
    setattr(stop, "terminal", True)  # noqa: B010 (attributes of a function, as solve_ivp's)
    setattr(stop, "direction", -1.0)  # noqa: B010
    return stop


def negative_at_start(
    stop_when: Callable[..., Any], t: float, q: np.ndarray, q_dot: np.ndarray
) -> bool:
    """Whether g is negative at the start (NaN is not: the run decides, as the C loop)."""
    value = float(
        np.asarray(stop_when(np.array([t]), q[None, :], q_dot[None, :]), float).reshape(-1)[0]
    )
    return not value >= 0 and not math.isnan(value)


class StopWatch:
    """The stop condition over the lanes of a batch
    (:class:`~lagrangian.simulation.integrators.lanes.LaneWatch`): g of the lanes that moved
    from the stepper's state and rates (q_dot the first n rates), and where it turned
    negative (or NaN) the time of its zero on the lane's interpolant."""

    def __init__(self, stop_when: Callable[..., Any], n: int) -> None:
        self.stop_when, self.n = stop_when, n
        self.g = np.zeros(0)
        self.moved, self.g_new = np.zeros(0, dtype=np.intp), np.zeros(0)

    def condition(self, t: np.ndarray, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """g at states x (lanes, state) with rates f."""
        n = self.n
        values = np.asarray(self.stop_when(t, x[:, :n], f[:, :n]), dtype=float)
        return np.broadcast_to(values, t.shape).astype(float)

    def start(self, stepper: Any, lanes: np.ndarray) -> np.ndarray:
        self.g = np.ones(len(stepper.t))
        self.g[lanes] = self.condition(stepper.t[lanes], stepper.y[lanes], stepper.f[lanes])
        return lanes[self.g[lanes] < 0]

    def crossed(self, stepper: Any, moved: np.ndarray) -> np.ndarray:
        g_new = self.condition(stepper.t[moved], stepper.y[moved], stepper.f[moved])
        self.moved, self.g_old, self.g_new = moved, self.g[moved], g_new
        self.g[moved] = g_new
        return ~(g_new >= 0)

    def locate(
        self,
        stepper: Any,
        lanes: np.ndarray,
        t_old: np.ndarray,
        dense: LaneDense,
        which: np.ndarray,
    ) -> Found:
        assert isinstance(dense, Dense)  # the interpolants of the batch's stepper
        at = np.searchsorted(self.moved, lanes)
        lane_of = np.zeros(int(which.max(initial=0)) + 1, dtype=np.intp)
        lane_of[which] = lanes

        def condition(t: np.ndarray, x: np.ndarray, entries: np.ndarray) -> np.ndarray:
            f, bad = stepper.rates(t, x, lane_of[entries])
            return np.where(bad, np.nan, self.condition(t, x, f))

        t_new = stepper.t[lanes]
        t_stop = locate_stops(dense, which, self.g_old[at], t_new, self.g_new[at], condition)
        x_stop = dense.value(t_stop, which)
        return Found([], lanes, t_stop, x_stop, [STOP_EVENT] * len(lanes))
