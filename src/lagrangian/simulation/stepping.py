"""integrate: drive a SciPy OdeSolver step by step, keeping everything up to a failure.

The loop is solve_ivp's (step; locate events on the step's dense output; sample the output
times the step covered), written out so that a failure — a step size underflow, a singular
mass matrix raised from the right-hand side, a state that is no longer finite — ends the run
with what was computed so far instead of losing it.

>>> import numpy as np
>>> from scipy.integrate import RK45
>>> run = integrate(lambda: RK45(lambda t, x: -x, 0.0, np.array([1.0]), 1.0, rtol=1e-9),
...                 0.0, np.array([1.0]), np.linspace(0, 1, 3))
>>> run.failure is None, np.allclose(run.x[:, 0], np.exp(-run.t), atol=1e-8)
(True, True)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

from lagrangian.errors import SimulationError
from lagrangian.simulation.events import EventWatch

#: Errors from the right-hand side or a solver's linear algebra that end a run as a failure.
FAILURES = (SimulationError, ArithmeticError, np.linalg.LinAlgError)


@dataclass(frozen=True)
class Integration:
    """Output of one run: states x at times t, events, and how it ended.

    ``failure`` is None on success, else the reason; ``t_reached``/``x_reached`` are the last
    accepted step; ``terminal`` the index of the event that stopped the run, if any.
    """

    t: np.ndarray
    x: np.ndarray
    events: tuple[tuple[int, float, np.ndarray], ...]
    failure: str | None
    t_reached: float
    x_reached: np.ndarray
    terminal: int | None


class _Output:
    """Collects output rows: every step (``times`` None) or the given times as reached."""

    def __init__(self, times: np.ndarray | None, t0: float, x0: np.ndarray) -> None:
        self.times, self.t, self.x = times, [t0], [x0]
        self.next = 1
        if times is not None:
            self.next = int(np.searchsorted(times, t0, side="right"))
            self.t, self.x = list(times[: self.next]), [x0] * self.next

    def reach(
        self, t: float, dense: Callable[[], Callable[[Any], np.ndarray]], x: np.ndarray | None
    ) -> None:
        """Record output up to t (``x`` is the state at t when t is a step's end)."""
        if self.times is None:
            self.t.append(t)
            self.x.append(x if x is not None else dense()(t))
            return
        end = int(np.searchsorted(self.times, t, side="right"))
        if end > self.next:
            block = self.times[self.next : end]
            self.t.extend(block)
            self.x.extend(np.atleast_2d(dense()(block)).T)
            self.next = end

    def stop(self, t: float, x: np.ndarray) -> None:
        """End the output at a terminal event: its time and state are the last row."""
        if self.times is not None and t > self.t[-1]:
            self.t.append(t)
            self.x.append(x)

    def arrays(self, size: int) -> tuple[np.ndarray, np.ndarray]:
        x = np.array(self.x, dtype=float).reshape(-1, size)
        return np.array(self.t, dtype=float), x


def integrate(
    start: Callable[[], OdeSolver],
    t0: float,
    x0: np.ndarray,
    times: np.ndarray | None = None,
    watch: EventWatch | None = None,
    progress: Callable[[float], None] | None = None,
    project: Callable[[float, np.ndarray], np.ndarray] | None = None,
) -> Integration:
    """Run the solver ``start()`` to its end, a terminal event or a failure.

    ``times``: output times (None: every step).  Errors of :data:`FAILURES` raised while
    stepping become ``failure``; the output holds everything before them.  ``project``
    (explicit Runge–Kutta solvers only: they keep no history but the last state and its
    derivative) moves every accepted step's state, and every output row, onto a manifold
    (coordinate projection, Hairer, Lubich & Wanner, Geometric Numerical Integration IV.4).
    """
    output = _Output(times, t0, x0)
    events: list[tuple[int, float, np.ndarray]] = []
    t_reached, x_reached, failure, terminal = t0, x0, None, None
    try:
        solver = start()
        if watch is not None:
            watch.start(t0, x0)
        while solver.status == "running":
            t_old = solver.t
            message = solver.step()
            if solver.status == "failed":
                failure = message or "the solver failed"
                break
            if not np.all(np.isfinite(solver.y)):
                failure = "The state is no longer finite (the solution blew up)."
                break
            if project is not None:
                solver.y = project(solver.t, solver.y)
                solver.f = solver.fun(solver.t, solver.y)  # the next step starts from here
            t_reached, x_reached = solver.t, solver.y.copy()
            dense: Callable[[], Callable[[Any], np.ndarray]] = _lazy(solver)
            if project is not None:
                dense = _projected(_lazy(solver), project)
            t_stop, x_stop = solver.t, x_reached
            if watch is not None:
                found, stop = watch.check(t_old, solver.t, solver.y, dense())
                events.extend((i, t, dense()(t)) for i, t in found)
                if stop:
                    terminal, t_stop = found[-1][0], found[-1][1]
                    x_stop = events[-1][2]
            output.reach(t_stop, dense, x_stop)
            if progress is not None:
                progress(t_stop)
            if terminal is not None:
                output.stop(t_stop, x_stop)
                break
    except FAILURES as error:
        failure = str(error)
    t, x = output.arrays(len(x0))
    return Integration(t, x, tuple(events), failure, t_reached, x_reached, terminal)


def _projected(
    dense: Callable[[], DenseOutput], project: Callable[[float, np.ndarray], np.ndarray]
) -> Callable[[], Callable[[Any], np.ndarray]]:
    """The step's dense output with every interpolated state projected."""

    def evaluate(t: Any) -> np.ndarray:
        values = dense()(t)
        if np.ndim(t) == 0:
            return project(float(t), values)
        columns = [project(float(s), values[:, i]) for i, s in enumerate(np.atleast_1d(t))]
        return np.stack(columns, axis=1)

    return lambda: evaluate


def _lazy(solver: OdeSolver) -> Callable[[], DenseOutput]:
    """The step's dense output, built on first use only (it costs work for some methods)."""
    built: list[DenseOutput] = []

    def dense() -> DenseOutput:
        if not built:
            built.append(solver.dense_output())
        return built[0]

    return dense
