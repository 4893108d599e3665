"""Events: zeros of user functions g(t, q, q_dot) located during a simulation.

As in ``scipy.integrate.solve_ivp``: an event function may carry ``direction`` (> 0: only
zeros where g goes from negative to positive, < 0 the reverse, 0 both) and ``terminal``
(True: stop at the first zero; an integer k: stop at the k-th).  After each step g is checked
for a sign change; the zero is located on the step's dense output x(s) by Brent's method,

    g(s, q(s), q_dot(s)) = 0,    t_old <= s <= t.

A function that is at its zero where the watch starts (a guard that just fired, or one a
reset put the state on: a rimless wheel's strike lands on the zero of the strike of the rear
spoke) has no sign to compare with.  Its first step is read on the dense output at the
times t_old + h 2^-k (k = LEAVING_SAMPLES ... 1, h the step) and t: the first value off zero
is where it leaves to, and a later change of sign in its direction is a crossing within the
step (a slow wheel rocking back onto the spoke it just left), located between the two
samples that bracket it.  Leaving in its direction is a crossing at t_old itself, except for
a ``disarmed`` function, which has just fired there.

>>> def ground(t, q, q_dot):
...     return q[0]
>>> ground.terminal = True
>>> watch = EventWatch([ground], lambda t, x: (x[:1], x[1:]))
>>> watch.names
('ground',)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import pairwise
from typing import Protocol

import numpy as np

EPS = float(np.finfo(float).eps)
#: |g| at most this, relative to 1 + max |x|, is g at its zero (the rounding of a reset).
AT_ZERO = 1e-12
#: |g| beyond this, relative to max |x|, has left its zero (a few roundings of g): relative
#: to the state itself, since a ball bouncing ever lower leaves its floor by less each time.
ROUNDING = 8 * EPS
#: Samples of the first step of a function that starts at its zero: t_old + h 2^-k, k <= this.
LEAVING_SAMPLES = 30


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
        #: Functions that have just fired where the run starts: leaving their zero, if the
        #: run starts on it (nothing reset them off it), is no crossing.
        self.disarmed: set[int] = set()
        #: Functions at their zero, not yet left (index -> the |g| that is still zero: a few
        #: roundings, or a few times the value it started from).
        self.leaving: dict[int, float] = {}

    def value(self, i: int, t: float, x: np.ndarray) -> float:
        q, q_dot = self.unpack(t, x)
        return float(self.functions[i](t, q, q_dot))

    def start(self, t: float, x: np.ndarray) -> None:
        self.values = np.array([self.value(i, t, x) for i in range(len(self.functions))])
        size = float(np.max(np.abs(x), initial=0.0))
        at_zero = np.flatnonzero(np.abs(self.values) <= AT_ZERO * (1.0 + size)).tolist()
        self.leaving = {i: max(ROUNDING * size, 4 * abs(self.values[i])) for i in at_zero}
        # NaN compares false both ways: these are read sample by sample (module docstring)
        self.values[list(at_zero)] = np.nan

    def check(
        self, t_old: float, t: float, x: np.ndarray, dense: Callable[[float], np.ndarray]
    ) -> tuple[list[tuple[int, float]], bool]:
        """Events in (t_old, t] as (index, time) in order of time, and whether to stop."""
        old, new = self.values, np.array([self.value(i, t, x) for i in range(len(self.functions))])
        up, down = (old <= 0) & (new >= 0), (old >= 0) & (new <= 0)
        d = self.directions
        active = np.flatnonzero((up & (d > 0)) | (down & (d < 0)) | ((up | down) & (d == 0)))
        roots = [(self._root(int(i), t_old, t, dense), int(i)) for i in active]
        for i, zero in list(self.leaving.items()):
            left, root = self._leaving(i, zero, t_old, t, dense, new[i])
            if left:
                del self.leaving[i]
            else:
                new[i] = np.nan  # still on its zero: read again next step
            if root is not None:
                roots.append((root, i))
        self.values = new
        roots.sort()
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

    def _leaving(
        self,
        i: int,
        zero: float,
        t_old: float,
        t: float,
        dense: Callable[[float], np.ndarray],
        end: float,
    ) -> tuple[bool, float | None]:
        """The first step of function ``i`` from its zero (module docstring): whether it left
        the zero (|g| > ``zero``) in (t_old, t], and the time it crossed in its direction
        (None: it did not)."""
        h = t - t_old
        times = [t_old + h * 0.5**k for k in range(LEAVING_SAMPLES, 0, -1)]
        samples = [(s, self.value(i, s, dense(s))) for s in times if t_old < s < t]
        off = [(s, g) for s, g in [*samples, (t, end)] if abs(g) > zero]
        if not off:
            return False, None
        direction = self.directions[i]
        _, first = off[0]
        if i not in self.disarmed and (direction == 0 or np.sign(first) == direction):
            return True, t_old  # it leaves across its zero: the crossing is where it starts
        for (a, g_a), (b, g_b) in pairwise(off):
            if np.sign(g_a) != np.sign(g_b) and (direction == 0 or np.sign(g_b) == direction):
                return True, self._root(i, a, b, dense)
        return True, None


def _limit(terminal: bool | int) -> float:
    """How many zeros end the run: never (not terminal), 1 (True) or the given count."""
    if not terminal:
        return float("inf")
    return 1.0 if terminal is True else float(terminal)
