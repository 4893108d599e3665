"""Dense output of one step for many members at once, and the stop time located on it.

The interpolants are SciPy's (as ``c_loop.c`` writes them for one member), with an axis for
the members: F has shape (rows, members, state), t_old and h shape (members,).

>>> import numpy as np
>>> x_old, x_new = np.array([[0.0]]), np.array([[1.0]])
>>> dense = Dense(HERMITE, np.array([0.0]), np.array([1.0]), x_old,
...               np.stack([x_old, x_new, np.ones((1, 1)), np.ones((1, 1))]))
>>> dense.value(np.array([0.5]), np.array([0]))
array([[0.5]])
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

RK45, DOP853, HERMITE = 0, 1, 2
ULP = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Dense:
    """The interpolants of one step of several members (see the module docstring)."""

    kind: int
    t_old: np.ndarray
    h: np.ndarray
    y_old: np.ndarray
    F: np.ndarray

    def value(self, t: np.ndarray, members: np.ndarray) -> np.ndarray:
        """The states at times t (one per listed member), shape (len(members), state)."""
        h = self.h[members][:, None]
        s = (t - self.t_old[members])[:, None] / h
        F = self.F[:, members]
        if self.kind == HERMITE:
            h00, h10 = (1 + 2 * s) * (1 - s) ** 2, s * (1 - s) ** 2
            h01, h11 = s**2 * (3 - 2 * s), s**2 * (s - 1)
            return h00 * F[0] + h10 * h * F[2] + h01 * F[1] + h11 * h * F[3]
        y_old = self.y_old[members]
        if self.kind == RK45:
            powers = np.cumprod(np.repeat(s[None], len(F), axis=0), axis=0)
            return h * np.sum(F * powers, axis=0) + y_old
        value = np.zeros_like(y_old)
        for r, row in enumerate(F[::-1]):
            value += row
            value *= s if r % 2 == 0 else 1 - s
        return value + y_old

    def of(self, which: int) -> Callable[[Any], np.ndarray]:
        """The interpolant of member ``which`` alone, as SciPy's DenseOutput: a time gives
        (state,), an array of times (state, times)."""

        def interpolant(t: Any) -> np.ndarray:
            times = np.atleast_1d(np.asarray(t, dtype=float))
            values = self.value(times, np.full(len(times), which))
            return values[0] if np.ndim(t) == 0 else values.T

        return interpolant


#: g(t, x) for some members: the stop condition at the states x (members, state).
Condition = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


def locate_stops(
    dense: Dense,
    members: np.ndarray,
    g_old: np.ndarray,
    t_new: np.ndarray,
    g_new: np.ndarray,
    condition: Condition,
) -> np.ndarray:
    """The times in (t_old, t_new] where g turns negative, one per listed member (Illinois
    method on the dense output, to 4 ulp of t); ``condition(t, x, members)`` gives g."""
    a, b = dense.t_old[members].copy(), t_new.copy()
    ga, gb = g_old.copy(), np.where(g_new < 0, g_new, -1.0)
    side = np.zeros(len(members), dtype=int)
    for _ in range(200):
        going = b - a > 4 * ULP * np.maximum(np.abs(a), np.abs(b))
        if not np.any(going):
            break
        c = b - gb * (b - a) / (gb - ga)
        c = np.where((a < c) & (c < b), c, 0.5 * (a + b))
        gc = condition(c, dense.value(c, members), members)
        right = going & (gc >= 0)
        left = going & ~(gc >= 0)
        gb = np.where(right & (side == 1), 0.5 * gb, gb)
        ga = np.where(left & (side == -1), 0.5 * ga, ga)
        a, ga = np.where(right, c, a), np.where(right, gc, ga)
        b, gb = np.where(left, c, b), np.where(left, np.where(gc < 0, gc, -1.0), gb)
        side = np.where(right, 1, np.where(left, -1, side))
    return b
