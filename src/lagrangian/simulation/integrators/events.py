"""Events: zeros of user functions g(t, q, q_dot) located during a simulation.

As in ``scipy.integrate.solve_ivp``: an event function may carry ``direction`` (> 0: only
zeros where g goes from negative to positive, < 0 the reverse, 0 both) and ``terminal``
(True: stop at the first zero; an integer k: stop at the k-th).  After each step g is checked
for a sign change; the zero is located on the step's dense output x(s) by Brent's method,

    g(s, q(s), q_dot(s)) = 0,    t_old <= s <= t.

>>> def ground(t, q, q_dot):
...     return q[0]
>>> ground.terminal = True
>>> watch = EventWatch([ground], lambda t, x: (x[:1], x[1:]))
>>> watch.names
('ground',)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np

EPS = float(np.finfo(float).eps)


class EventFunction(Protocol):
    """g(t, q, q_dot) -> float; optional attributes ``terminal`` and ``direction``."""

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float: ...


#: The coordinates and every velocity at (t, x).
Unpack = Callable[[float, np.ndarray], tuple[np.ndarray, np.ndarray]]


class EventWatch:
    """Sign changes of the event functions along an integration (state of one run)."""

    def __init__(self, functions: Sequence[EventFunction], unpack: Unpack) -> None:
        self.functions = tuple(functions)
        self.unpack = unpack
        self.names = tuple(
            getattr(g, "__name__", f"event{i}") for i, g in enumerate(self.functions)
        )
        self.directions = np.array([float(getattr(g, "direction", 0.0)) for g in functions])
        self.limits = np.array([_limit(getattr(g, "terminal", False)) for g in functions])
        self.counts = np.zeros(len(self.functions), dtype=int)
        self.values = np.zeros(len(self.functions))
        #: Functions not watched during the first step (a run that starts on their zero).
        self.disarmed: set[int] = set()

    def value(self, i: int, t: float, x: np.ndarray) -> float:
        q, q_dot = self.unpack(t, x)
        return float(self.functions[i](t, q, q_dot))

    def start(self, t: float, x: np.ndarray) -> None:
        self.values = np.array([self.value(i, t, x) for i in range(len(self.functions))])
        # NaN compares false both ways: no crossing is seen before the first step's end
        self.values[list(self.disarmed)] = np.nan

    def check(
        self, t_old: float, t: float, x: np.ndarray, dense: Callable[[float], np.ndarray]
    ) -> tuple[list[tuple[int, float]], bool]:
        """Events in (t_old, t] as (index, time) in order of time, and whether to stop."""
        old, new = self.values, np.array([self.value(i, t, x) for i in range(len(self.functions))])
        self.values = new
        up, down = (old <= 0) & (new >= 0), (old >= 0) & (new <= 0)
        d = self.directions
        active = np.flatnonzero((up & (d > 0)) | (down & (d < 0)) | ((up | down) & (d == 0)))
        roots = sorted((self._root(int(i), t_old, t, dense), int(i)) for i in active)
        found: list[tuple[int, float]] = []
        for root, i in roots:
            found.append((i, root))
            self.counts[i] += 1
            if self.counts[i] >= self.limits[i]:
                return found, True
        return found, False

    def _root(self, i: int, t_old: float, t: float, dense: Callable[[float], np.ndarray]) -> float:
        from scipy.optimize import brentq  # SciPy loads with the first event, not on import

        def g(s: float) -> float:
            return self.value(i, s, dense(s))

        return float(brentq(g, t_old, t, xtol=4 * EPS, rtol=4 * EPS))


def _limit(terminal: bool | int) -> float:
    """How many zeros end the run: never (not terminal), 1 (True) or the given count."""
    if not terminal:
        return float("inf")
    return 1.0 if terminal is True else float(terminal)
