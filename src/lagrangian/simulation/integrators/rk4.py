"""RK4: the classical fixed-step Runge–Kutta method of order 4, as a SciPy OdeSolver.

    k1 = f(t, x)
    k2 = f(t + h/2, x + h/2 k1)
    k3 = f(t + h/2, x + h/2 k2)
    k4 = f(t + h, x + h k3)
    x(t + h) = x + h/6 (k1 + 2 k2 + 2 k3 + k4)          global error O(h^4)

The step h is ``dt`` shortened so that a whole number of steps ends exactly at t_bound; f at
the end of a step is k1 of the next, so a step costs four evaluations.  Between steps the
solution is the cubic Hermite interpolant of x and f at both ends (error O(h^4) as well).

>>> import numpy as np
>>> solver = RK4(lambda t, x: -x, 0.0, np.array([1.0]), 1.0, dt=0.1)
>>> while solver.status == "running":
...     _ = solver.step()
>>> bool(abs(solver.y[0] - np.exp(-1.0)) < 1e-6)
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

Field = Callable[[float, np.ndarray], np.ndarray]


def rk4_step(f: Field, t: float, x: np.ndarray, h: float, k1: np.ndarray) -> np.ndarray:
    """x(t + h) by one classical Runge–Kutta step, given k1 = f(t, x)."""
    k2 = f(t + h / 2, x + h / 2 * k1)
    k3 = f(t + h / 2, x + h / 2 * k2)
    k4 = f(t + h, x + h * k3)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


class RK4(OdeSolver):
    """Fixed-step classical Runge–Kutta (see the module docstring); ``dt`` is the step."""

    t: float
    y: np.ndarray

    def __init__(
        self,
        fun: Field,
        t0: float,
        y0: np.ndarray,
        t_bound: float,
        dt: float,
        vectorized: bool = False,
        **_ignored: Any,
    ) -> None:
        super().__init__(fun, t0, y0, t_bound, vectorized)
        self.t_start = t0
        self.steps = max(1, math.ceil(abs(t_bound - t0) / dt - 1e-9))
        self.h = (t_bound - t0) / self.steps
        self.taken = 0
        self.f = self.fun(self.t, self.y)
        self.previous: tuple[float, np.ndarray, np.ndarray] | None = None

    def _step_impl(self) -> tuple[bool, str | None]:
        t, x, f = self.t, self.y, self.f
        x_new = rk4_step(self.fun, t, x, self.h, f)
        if not np.all(np.isfinite(x_new)):
            return False, "The state is no longer finite (the solution blew up)."
        self.taken += 1
        # count steps rather than add h, so the steps land on t0 + i h exactly
        last = self.taken == self.steps
        t_new = self.t_bound if last else self.t_start + self.taken * self.h
        self.previous = (t, x, f)
        self.t, self.y, self.f = t_new, x_new, self.fun(t_new, x_new)
        return True, None

    def _dense_output_impl(self) -> DenseOutput:
        assert self.previous is not None  # dense output exists only after a step
        t_old, x_old, f_old = self.previous
        return HermiteOutput(t_old, self.t, x_old, self.y, f_old, self.f)


class HermiteOutput(DenseOutput):
    """Cubic Hermite interpolation of x between two steps from x and dx/dt at both ends."""

    def __init__(
        self,
        t_old: float,
        t: float,
        x_old: np.ndarray,
        x: np.ndarray,
        f_old: np.ndarray,
        f: np.ndarray,
    ) -> None:
        super().__init__(t_old, t)
        self.ends = (x_old, x, f_old, f)

    def _call_impl(self, t: np.ndarray) -> np.ndarray:
        x0, x1, f0, f1 = self.ends
        h = self.t - self.t_old
        s = (np.asarray(t) - self.t_old) / h
        h00 = (1 + 2 * s) * (1 - s) ** 2
        h10 = s * (1 - s) ** 2
        h01 = s**2 * (3 - 2 * s)
        h11 = s**2 * (s - 1)
        if s.ndim == 0:
            return h00 * x0 + h10 * h * f0 + h01 * x1 + h11 * h * f1
        columns = [x0[:, None], f0[:, None] * h, x1[:, None], f1[:, None] * h]
        return h00 * columns[0] + h10 * columns[1] + h01 * columns[2] + h11 * columns[3]
