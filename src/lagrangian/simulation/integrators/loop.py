"""integrate: the one Python loop, driving a stepper step by step, keeping everything up to a
failure.

Every method stepped in Python runs through it — SciPy's solvers, RK4, the variational and
collocation steps — since each is a :class:`~lagrangian.simulation.integrators.protocol.Stepper`
(the shape of SciPy's ``OdeSolver``).  The loop is solve_ivp's (step; locate events on the
step's dense output; sample the output times the step covered), written out so that a
failure — a step size underflow, a singular mass matrix raised from the right-hand side, a
state that is no longer finite — or Ctrl-C ends the run with what was computed so far instead
of losing it.

>>> import numpy as np
>>> from scipy.integrate import RK45
>>> run = integrate(lambda: RK45(lambda t, x: -x, 0.0, np.array([1.0]), 1.0, rtol=1e-9),
...                 0.0, np.array([1.0]), np.linspace(0, 1, 3))
>>> run.failure is None, np.allclose(run.x[:, 0], np.exp(-run.t), atol=1e-8)
(True, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import OdeSolver

from lagrangian.errors import Fix, SimulationError
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.events import EventWatch
from lagrangian.simulation.integrators.protocol import (
    Dynamics,
    Integration,
    Progress,
    Stepper,
)
from lagrangian.simulation.methods import method_named

#: Errors from the right-hand side or a solver's linear algebra that end a run as a failure.
FAILURES = (SimulationError, ArithmeticError, np.linalg.LinAlgError)


@dataclass(frozen=True)
class SolverIntegrator:
    """SciPy's ``solve_ivp`` methods and the fixed-step RK4 (the
    :class:`~lagrangian.simulation.integrators.protocol.Integrator` of every OdeSolver method),
    stepped by :func:`integrate`."""

    def run(
        self,
        dynamics: Dynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
        budget: Budget | None = None,
    ) -> Integration:
        """Step ``dynamics`` with the solver of ``inputs.method``; ``budget`` is the run's
        when this is one piece of it (the piecewise loop), else the inputs' own."""
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return integrate(
                solver_starter(dynamics.field, inputs),
                inputs.t_span[0],
                inputs.x0,
                inputs.t_out,
                watch,
                progress,
                dynamics.projection(),
                budget if budget is not None else Budget.of(inputs),
            )


def solver_starter(
    field: Callable[[float, np.ndarray], np.ndarray], inputs: Inputs
) -> Callable[[], OdeSolver]:
    """A function building the SciPy solver of ``inputs.method`` for dx/dt = field(t, x)
    (the integration loop calls it, since its first evaluation of the field may fail)."""
    t0, t1 = inputs.t_span
    method = method_named(inputs.method)
    solver = method.solver_class()
    if method.takes_step:
        return lambda: solver(field, t0, inputs.x0, t1, dt=inputs.dt)
    return lambda: solver(
        field, t0, inputs.x0, t1, rtol=inputs.rtol, atol=inputs.atol, max_step=inputs.max_step
    )


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
        # each row's state is computed before its time is kept: a Ctrl-C in between leaves
        # no time without a state
        if self.times is None:
            state = x if x is not None else dense()(t)
            self.t.append(t)
            self.x.append(state)
            return
        if self.next >= len(self.times) or self.times[self.next] > t:
            return  # no output time in this step (most steps of a fine output)
        end = int(np.searchsorted(self.times, t, side="right"))
        if end > self.next:
            block = self.times[self.next : end]
            states = list(np.atleast_2d(dense()(block)).T)
            self.t.extend(block)
            self.x.extend(states)
            self.next = end

    def stop(self, t: float, x: np.ndarray) -> None:
        """End the output at a terminal event: its time and state are the last row."""
        if self.times is not None and (not self.t or t > self.t[-1]):
            self.t.append(t)
            self.x.append(x)

    def arrays(self, size: int) -> tuple[np.ndarray, np.ndarray]:
        x = np.array(self.x, dtype=float).reshape(-1, size)
        return np.array(self.t, dtype=float), x


def integrate(
    start: Callable[[], Stepper],
    t0: float,
    x0: np.ndarray,
    times: np.ndarray | None = None,
    watch: EventWatch | None = None,
    progress: Progress | None = None,
    project: Callable[[float, np.ndarray], np.ndarray] | None = None,
    budget: Budget | None = None,
) -> Integration:
    """Run the solver ``start()`` to its end, a terminal event, a failure or Ctrl-C.

    Output rows are the ``times`` (None: every step).  Errors of :data:`FAILURES` raised while
    stepping become ``failure``, a KeyboardInterrupt ``interrupted``; the output holds
    everything before them.  ``project`` (explicit Runge–Kutta solvers only: they keep no
    history but the last state and its derivative) moves every accepted step's state, and
    every output row, onto a manifold (coordinate projection, Hairer, Lubich & Wanner,
    Geometric Numerical Integration IV.4).  ``budget`` (default: the default step budget)
    stops a run that takes too many steps or too long, or is stiff for an explicit method
    (:mod:`lagrangian.simulation.integrators.budget`).
    """
    budget = budget if budget is not None else Budget("", start=t0)
    output = _Output(times, t0, x0)
    events: list[tuple[str, float, np.ndarray]] = []
    t_reached, x_reached, stopped_by = t0, x0, None
    failure: str | Fix | None = None
    interrupted = False
    try:
        solver = start()
        if watch is not None:
            watch.start(t0, x0)
        while solver.status == "running":
            if not math.isfinite(getattr(solver, "h_abs", 0.0)):
                # SciPy's adaptive solvers shrink a step size that is NaN for ever
                failure = (
                    f"The equations of motion are not finite numbers at t = {solver.t:.6g}: "
                    "no step size can be chosen (an overflow or a division by zero there)."
                )
                break
            t_old, y_old = solver.t, solver.y.copy()
            message = solver.step()
            if solver.status == "failed":
                failure = message or "the solver failed"
                break
            if not np.isfinite(solver.y).all():
                failure = "The state is no longer finite (the solution blew up)."
                break
            over_budget = budget.spend(solver, t_old, y_old, solver.t_bound)
            if project is not None:
                solver.y = project(solver.t, solver.y)
                # explicit Runge–Kutta solvers only (Method.explicit): SciPy's, with f and fun
                solver.f = solver.fun(solver.t, solver.y)  # type: ignore[attr-defined]
            t_reached, x_reached = solver.t, solver.y.copy()
            dense: Callable[[], Callable[[Any], np.ndarray]] = _lazy(solver)
            if project is not None:
                dense = _projected(_lazy(solver), project)
            t_stop, x_stop = solver.t, x_reached
            if watch is not None:
                found, stop = watch.check(t_old, solver.t, solver.y, dense())
                events.extend((watch.names[i], t, dense()(t)) for i, t in found)
                if stop:
                    stopped_by, t_stop, x_stop = events[-1]
            output.reach(t_stop, dense, x_stop)
            if progress is not None:
                progress(t_stop)
            if stopped_by is not None:
                output.stop(t_stop, x_stop)
                break
            if over_budget is not None:
                failure = over_budget
                break
    except FAILURES as error:
        failure = str(error)
    except KeyboardInterrupt:  # Ctrl-C: keep what was computed, the caller decides
        interrupted = True
    t, x = output.arrays(len(x0))
    return Integration(
        t,
        x,
        t_reached,
        x_reached,
        tuple(events),
        failure,
        interrupted,
        stopped_by,
        note=budget.note(),
    )


def _projected(
    dense: Callable[[], Callable[[Any], np.ndarray]],
    project: Callable[[float, np.ndarray], np.ndarray],
) -> Callable[[], Callable[[Any], np.ndarray]]:
    """The step's dense output with every interpolated state projected."""

    def evaluate(t: Any) -> np.ndarray:
        values = dense()(t)
        if np.ndim(t) == 0:
            return project(float(t), values)
        columns = [project(float(s), values[:, i]) for i, s in enumerate(np.atleast_1d(t))]
        return np.stack(columns, axis=1)

    return lambda: evaluate


def _lazy(solver: Stepper) -> Callable[[], Callable[[Any], np.ndarray]]:
    """The step's dense output, built on first use only (it costs work for some methods)."""
    built: list[Callable[[Any], np.ndarray]] = []

    def dense() -> Callable[[Any], np.ndarray]:
        if not built:
            built.append(solver.dense_output())
        return built[0]

    return dense
