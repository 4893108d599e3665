"""The one Python loop, driving k lanes of a stepper step by step, keeping everything up to a
failure.

Every method stepped in Python runs through it — SciPy's solvers, RK4, the variational and
collocation steps, each a :class:`~lagrangian.simulation.integrators.protocol.Stepper` (the
shape of SciPy's ``OdeSolver``) run as one lane (:func:`integrate`), and the members of a
batch without the C loop, the lanes of one vectorized Runge–Kutta stepper
(:mod:`lagrangian.simulation.batch.vectorized`).  The loop is solve_ivp's (step; locate
events on the step's dense output; sample the output times the step covered) over arrays of
lanes (:func:`run_lanes`), written out so that a failure — a step size underflow, a singular
mass matrix raised from the right-hand side, a state that is no longer finite — or Ctrl-C
ends a run with what was computed so far instead of losing it.

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

import numpy as np
from scipy.integrate import OdeSolver

from lagrangian.errors import Fix, SimulationError
from lagrangian.numerics.status import Status
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.events import EventWatch
from lagrangian.simulation.integrators.lanes import (
    EachLane,
    Found,
    LaneDense,
    LaneStepper,
    LaneWatch,
    OneLane,
    Taken,
)
from lagrangian.simulation.integrators.output import Rows
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


#: The code of a lane still running.
RUNNING = -1


@dataclass
class LaneRun:
    """What the loop computed for k lanes: the output rows (:class:`Rows`), and per lane
    how it ended — its :class:`Status` code (FINISHED, STOPPED or a failure), its message
    where the code does not say it all (a single run's failure), the last accepted step
    (``t_reached``, ``x_reached``), where a watch stopped it (``t_stop``, ``x_stop``, NaN
    for the others, and the name of the event in ``stopped_by``), its events in the order
    of time; ``interrupted`` after Ctrl-C (every lane still running keeps its rows)."""

    rows: Rows
    status: np.ndarray
    messages: list[str | Fix | None]
    t_reached: np.ndarray
    x_reached: np.ndarray
    t_stop: np.ndarray
    x_stop: np.ndarray
    stopped_by: list[str | None]
    events: list[list[tuple[str, float, np.ndarray]]]
    interrupted: bool = False

    @classmethod
    def begun(cls, rows: Rows, t0: float, X0: np.ndarray) -> LaneRun:
        """Every lane running from (t0, X0)."""
        k, n = X0.shape
        return cls(
            rows,
            np.full(k, RUNNING, dtype=np.intp),
            [None] * k,
            np.full(k, float(t0)),
            np.array(X0, dtype=float),
            np.full(k, np.nan),
            np.full((k, n), np.nan),
            [None] * k,
            [[] for _ in range(k)],
        )

    @property
    def t_final(self) -> np.ndarray:
        """Where each lane ended: its stop, else its last accepted step."""
        return np.where(self.status == Status.STOPPED, self.t_stop, self.t_reached)

    @property
    def x_final(self) -> np.ndarray:
        """The state each lane ended at (its stop, else its last accepted step)."""
        stopped = (self.status == Status.STOPPED)[:, None]
        return np.where(stopped, self.x_stop, self.x_reached)


def _started(
    run: LaneRun, stepper: LaneStepper, watch: LaneWatch | None, t0: float, X0: np.ndarray
) -> np.ndarray:
    """The lanes that start: not those that fail at their first rates, nor those the watch
    stops where they begin (their stop is their start)."""
    _failed(run, stepper.begin())
    running = np.flatnonzero(run.status == RUNNING)
    if watch is not None:
        stopped = watch.start(stepper, running)
        _end(run, stopped, Status.STOPPED)
        run.t_stop[stopped], run.x_stop[stopped] = t0, X0[stopped]
        running = np.flatnonzero(run.status == RUNNING)
    return running


def run_lanes(
    start: Callable[[], LaneStepper],
    t0: float,
    X0: np.ndarray,
    times: np.ndarray | None = None,
    watch: LaneWatch | None = None,
    progress: Progress | None = None,
    project: Callable[[float, np.ndarray], np.ndarray] | None = None,
    budget: Budget | None = None,
) -> LaneRun:
    """Run the k lanes of the stepper ``start()`` from (t0, X0 (k, n)) each to its end, a
    watch's stop, a failure, or all of them to Ctrl-C.

    Every round, each lane still running takes one step (:class:`LaneStepper`); the lanes
    that moved are checked by the ``watch`` (:class:`LaneWatch`: events, a stop condition),
    their output rows at ``times`` (None: every step) read on their steps' interpolants, and
    their budget counted (:mod:`lagrangian.simulation.integrators.budget`).  Errors of
    :data:`FAILURES` raised while stepping end every lane still running with that message.
    ``project`` (explicit Runge–Kutta steppers: they keep no history but the last state and
    its derivative) moves every accepted step's state, and every interpolated state, onto a
    manifold (coordinate projection, Hairer, Lubich & Wanner, Geometric Numerical
    Integration IV.4).  ``progress`` gets the earliest time of the lanes still running (the
    latest reached once none is) after every round.
    """
    budget = budget if budget is not None else Budget("", start=t0)
    run = LaneRun.begun(Rows(times, t0, X0), t0, X0)
    running = np.arange(len(X0))
    stepper: LaneStepper | None = None
    try:
        stepper = start()
        running = _started(run, stepper, watch, t0, X0)
        while len(running):
            taken = stepper.step(running)
            ended = len(taken.failed) > 0
            if ended:
                _failed(run, taken)
            moved = taken.moved
            if len(moved):
                ended |= _advance(run, stepper, taken, watch, project, budget)
            if ended:
                running = running[run.status[running] == RUNNING]
            if progress is not None and len(moved):
                progress(_earliest(run, stepper, running, moved))
    except FAILURES as error:
        for lane in running[run.status[running] == RUNNING]:
            run.status[lane], run.messages[lane] = Status.FAILED, str(error)
    except KeyboardInterrupt:  # Ctrl-C: keep what was computed, the caller decides
        run.interrupted = True
        run.status[run.status == RUNNING] = Status.INTERRUPTED
    if stepper is not None:  # a lane's state changes only with its accepted steps
        run.t_reached[:], run.x_reached[:] = stepper.t, stepper.y
    return run


def _advance(
    run: LaneRun,
    stepper: LaneStepper,
    taken: Taken,
    watch: LaneWatch | None,
    project: Callable[[float, np.ndarray], np.ndarray] | None,
    budget: Budget,
) -> bool:
    """After a step of the lanes ``taken.moved``: budget, projection, watch, output rows,
    and the lanes that end (a stop first, then a spent budget, then the end of the span);
    whether any ended."""
    moved = taken.moved
    over, reason = budget.spend_lanes(stepper, moved)
    if project is not None:
        stepper.project(moved, project)
    t_end = stepper.t[moved]  # a copy: a stop replaces its lane's time
    x_end = stepper.y[moved] if run.rows.times is None else None  # read where needed
    stopped = False
    crossed = watch.crossed(stepper, moved) if watch is not None else None
    needed = run.rows.pending(moved, t_end)
    if crossed is not None:
        needed = crossed if needed is None else needed | crossed
    dense: LaneDense | None = None
    which = moved
    if needed is not None and needed.any():
        dense, which = _interpolants(stepper, moved, needed)
        if watch is not None and crossed is not None and crossed.any():
            on = np.flatnonzero(crossed)
            found = watch.locate(stepper, moved[on], taken.t_old[on], dense, which[on])
            stopped = len(found.stopped) > 0
            if found.events or stopped:
                if x_end is None and stopped:
                    x_end = stepper.y[moved]
                _found(run, found, np.searchsorted(moved, found.stopped), t_end, x_end)
    run.rows.reach(moved, t_end, x_end, dense, which)
    if len(over):
        for lane in over[run.status[over] == RUNNING]:
            run.status[lane] = budget.ended if budget.ended is not None else Status.FAILED
            run.messages[lane] = reason
    # (one lane read as a number: the reduction costs more than the lane)
    finished = bool(taken.finished[0] if len(moved) == 1 else taken.finished.any())
    if finished:
        _end(run, moved[taken.finished], Status.FINISHED)
    return stopped or finished or len(over) > 0


def _interpolants(
    stepper: LaneStepper, moved: np.ndarray, needed: np.ndarray
) -> tuple[LaneDense, np.ndarray]:
    """The interpolants of the lanes of ``moved`` that need one (``needed``), built in one
    call, and each moved lane's entry in them (-1: none)."""
    if needed.all():
        return stepper.dense_output(moved), np.arange(len(moved))
    local = np.flatnonzero(needed)
    which = np.full(len(moved), -1, dtype=np.intp)
    which[local] = np.arange(len(local))
    return stepper.dense_output(moved[local]), which


def _found(
    run: LaneRun, found: Found, at: np.ndarray, t_end: np.ndarray, x_end: np.ndarray | None
) -> None:
    """Record a watch's events; the lanes it stopped (entries ``at`` of the step's t_end
    and x_end) end there, their output up to the stop."""
    for lane, name, t, x in found.events:
        run.events[lane].append((name, t, x))
    stopped = found.stopped
    if len(stopped):
        assert x_end is not None  # read for the stopped lanes
        t_end[at], x_end[at] = found.t_stop, found.x_stop
        run.t_stop[stopped], run.x_stop[stopped] = found.t_stop, found.x_stop
        for lane, name in zip(stopped.tolist(), found.names):
            run.stopped_by[lane] = name
        _end(run, stopped, Status.STOPPED)


def _earliest(run: LaneRun, stepper: LaneStepper, running: np.ndarray, moved: np.ndarray) -> float:
    """The progress of the lanes: the earliest time of those still running, else the
    latest where the lanes that just moved ended."""
    if len(running):
        return float(np.min(stepper.t[running]))
    stopped = run.status[moved] == Status.STOPPED
    return float(np.max(np.where(stopped, run.t_stop[moved], stepper.t[moved])))


def _failed(run: LaneRun, taken: Taken) -> None:
    """The lanes ``taken.failed`` end with their codes and messages."""
    messages = taken.messages or [None] * len(taken.failed)
    for lane, code, message in zip(taken.failed.tolist(), taken.codes.tolist(), messages):
        run.status[lane], run.messages[lane] = code, message


def _end(run: LaneRun, lanes: np.ndarray, code: int) -> None:
    """The lanes ``lanes`` still running end with ``code``."""
    if len(lanes):
        lanes = lanes[run.status[lanes] == RUNNING]
        run.status[lanes] = code


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
    """Run the solver ``start()`` to its end, a terminal event, a failure or Ctrl-C: one
    lane of :func:`run_lanes` (:class:`~lagrangian.simulation.integrators.lanes.OneLane`).

    Output rows are the ``times`` (None: every step), a terminal event's time and state the
    last; the failure is the solver's message, or that of an error of :data:`FAILURES`
    raised while stepping; ``interrupted`` after Ctrl-C; the output holds everything
    before.  ``project`` and ``budget`` as for :func:`run_lanes` (the budget watches
    stiffness and a collapsed step size too).
    """
    budget = budget if budget is not None else Budget("", start=t0)
    x0 = np.asarray(x0, dtype=float)
    lanes = run_lanes(
        lambda: OneLane(start()),
        t0,
        x0[None, :],
        times,
        None if watch is None else EachLane([watch]),
        progress,
        project,
        budget,
    )
    t, x = lanes.rows.lane(0)
    stopped_by = lanes.stopped_by[0]
    if stopped_by is not None and times is not None and (not len(t) or lanes.t_stop[0] > t[-1]):
        t, x = np.append(t, lanes.t_stop[0]), np.vstack([x, lanes.x_stop[0]])
    code = int(lanes.status[0])
    failed = code not in (Status.FINISHED, Status.STOPPED, Status.INTERRUPTED)
    return Integration(
        t,
        x,
        float(lanes.t_reached[0]),
        lanes.x_reached[0].copy(),
        tuple(lanes.events[0]),
        (lanes.messages[0] or Status(code).message) if failed else None,
        lanes.interrupted,
        stopped_by,
        note=budget.note(),
    )
