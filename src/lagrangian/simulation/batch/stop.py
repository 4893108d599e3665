"""A batch's stop condition g(t, q, q_dot) as the one Python loop watches it: a terminal
event where g turns negative, called with the arrays of one member as the batch calls it
(arrays t (1,), q and q_dot (1, n)); a member whose g is negative at its start stops there.

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

from lagrangian.simulation.integrators.events import EventFunction

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
