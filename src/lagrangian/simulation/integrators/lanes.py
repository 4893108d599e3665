"""Lanes: k runs stepped side by side, the shape the one Python loop drives.

The loop (:mod:`lagrangian.simulation.integrators.loop`) carries k runs as arrays — the time
t (k,), the state y (k, n), and per lane its status, output rows, events and budget — and
asks a :class:`LaneStepper` for one step of the lanes still running.  A single simulation
is one lane: :class:`OneLane` adapts any per-step :class:`~.protocol.Stepper` (SciPy's
``OdeSolver``, RK4, the variational and collocation steps); the members of a batch are k
lanes of the vectorized Runge–Kutta stepper
(:mod:`lagrangian.simulation.batch.vectorized`), each lane with its own adaptive step.

What may end a lane early is watched by a :class:`LaneWatch`: the event functions of a
single run (:class:`EachLane`, one :class:`~.events.EventWatch` per lane) or a batch's
stop condition (:mod:`lagrangian.simulation.batch.stop`, vectorized over the lanes).

>>> import numpy as np
>>> from scipy.integrate import RK45
>>> lane = OneLane(RK45(lambda t, x: -x, 0.0, np.array([1.0]), 1.0))
>>> taken = lane.step(np.array([0]))
>>> taken.moved, bool(lane.t[0] > 0), lane.dense_output(taken.moved).value(lane.t, [0]).shape
(array([0]), True, (1, 1))
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple, Protocol

import numpy as np

from lagrangian.errors import Fix
from lagrangian.numerics.status import Status
from lagrangian.simulation.integrators.events import EventWatch
from lagrangian.simulation.integrators.protocol import Stepper

NOWHERE = np.zeros(0, dtype=np.intp)
#: x -> the nearest state on a manifold, at time t.
Projection = Callable[[float, np.ndarray], np.ndarray]
#: What a single run says when its state stops being finite.
BLEW_UP = "The state is no longer finite (the solution blew up)."


class Taken(NamedTuple):
    """What one call of :meth:`LaneStepper.step` did: the lanes that took an accepted step
    (``moved``), which of them reached the end of the span (``finished``) and the times
    their steps began (``t_old``), both aligned with ``moved``; the lanes that failed, with
    their :class:`Status` codes and, where the code does not say it all, their messages
    (aligned with ``failed``; None: the code's)."""

    moved: np.ndarray
    finished: np.ndarray
    t_old: np.ndarray = np.zeros(0)
    failed: np.ndarray = NOWHERE
    codes: np.ndarray = NOWHERE
    messages: Sequence[str | Fix | None] = ()


#: A call that moved no lane and ended none.
NOTHING = Taken(NOWHERE, NOWHERE)


class LaneDense(Protocol):
    """The interpolants of the last step of some lanes (``lanes``, in the order asked)."""

    def value(self, t: np.ndarray, which: Any) -> np.ndarray:
        """States (len(t), n) at the times t, entry j on lane ``lanes[which[j]]``."""
        ...

    def of(self, which: int) -> Callable[[Any], np.ndarray]:
        """The interpolant of lane ``lanes[which]`` alone, as SciPy's DenseOutput: a time
        gives (n,), an array of times (n, m)."""
        ...


class LaneStepper(Protocol):
    """k runs, one accepted step per lane per call (a rejected trial is no step).

    ``t`` (k,) and ``y`` (k, n) are each lane's time and state after its last accepted
    step, ``t_bound`` the end of the span; ``f`` (k, n), where a stepper keeps it, dx/dt at
    them (a watch may read it).  ``dense_output(lanes)`` interpolates the last step of lanes
    that moved in the last call; ``project(lanes, project)`` moves their states onto a
    manifold after the step (explicit Runge–Kutta steppers only).
    """

    t: np.ndarray
    y: np.ndarray
    t_bound: float

    def begin(self) -> Taken:
        """The lanes that fail where they start (their first rates), before any step."""
        ...

    def step(self, lanes: np.ndarray) -> Taken:
        """One step of each of the running ``lanes``."""
        ...

    def dense_output(self, lanes: np.ndarray) -> LaneDense:
        """The interpolants of the last step of ``lanes``."""
        ...

    def project(self, lanes: np.ndarray, project: Projection) -> None:
        """Replace the states of ``lanes`` by ``project(t, y)`` (and what depends on them)."""
        ...


class Found(NamedTuple):
    """What a watch found in the last step of some lanes: every event as (lane, name, time,
    state) in the order of time per lane, and the lanes it ends with the time, state and
    name of the event that ends each."""

    events: list[tuple[int, str, float, np.ndarray]]
    stopped: np.ndarray
    t_stop: np.ndarray
    x_stop: np.ndarray
    names: Sequence[str]


#: A watch's answer for steps where nothing happened.
NOT_FOUND = Found([], NOWHERE, np.zeros(0), np.zeros((0, 0)), ())


class LaneWatch(Protocol):
    """Zeros watched along the lanes: events, a stop condition."""

    def start(self, stepper: LaneStepper, lanes: np.ndarray) -> np.ndarray:
        """Begin at the lanes' first states; the lanes that stop where they start."""
        ...

    def crossed(self, stepper: LaneStepper, moved: np.ndarray) -> np.ndarray:
        """Whether each lane that moved may hold a zero in its step (bool, as ``moved``):
        the loop builds the interpolants of those lanes and of those with output rows."""
        ...

    def locate(
        self,
        stepper: LaneStepper,
        lanes: np.ndarray,
        t_old: np.ndarray,
        dense: LaneDense,
        which: np.ndarray,
    ) -> Found:
        """The zeros in the last step of ``lanes`` (those ``crossed`` said), each lane's
        interpolant the entry ``which`` of ``dense``."""
        ...


class OneLane:
    """A per-step :class:`~.protocol.Stepper` as one lane: a single run in the loop.

    Its failures are the stepper's own messages (a run's ``failure``); the state and the
    interpolant of a projected run (``project``, explicit Runge–Kutta solvers of SciPy, with
    ``f`` and ``fun``) are projected after every step.
    """

    def __init__(self, solver: Stepper) -> None:
        self.solver = solver
        self.t_bound = solver.t_bound
        self.t = np.array([float(solver.t)])
        self.y = np.array(solver.y, dtype=float)[None, :]
        #: The time (1,) and state before the last step (the budget's stiffness test).
        self.t_old, self.y_old = self.t.copy(), self.y[0]
        self._project: Projection | None = None
        # what a step says, made once: the lane, its t_old updated in place
        self._going = Taken(_LANE, _GOING, self.t_old)
        self._done = Taken(_LANE, _DONE, self.t_old)

    def begin(self) -> Taken:
        return NOTHING  # the solver evaluated its start when it was made

    def step(self, lanes: np.ndarray) -> Taken:
        solver = self.solver
        if not math.isfinite(getattr(solver, "h_abs", 0.0)):
            # SciPy's adaptive solvers shrink a step size that is NaN for ever
            return self._failed(
                f"The equations of motion are not finite numbers at t = {solver.t:.6g}: "
                "no step size can be chosen (an overflow or a division by zero there)."
            )
        self.t_old[0], self.y_old = self.t[0], solver.y.copy()
        message = solver.step()
        if solver.status == "failed":
            return self._failed(message or "the solver failed")
        if not np.isfinite(solver.y).all():
            return self._failed(BLEW_UP)
        self.t[0] = solver.t
        self.y = solver.y[None, :]  # a view: SciPy's steps make a new state, not change it
        return self._done if solver.status == "finished" else self._going

    def _failed(self, message: str | Fix) -> Taken:
        return Taken(NOWHERE, NOWHERE, NOWHERE, np.zeros(1, dtype=np.intp), _FAILED, (message,))

    def project(self, lanes: np.ndarray, project: Projection) -> None:
        solver = self.solver
        solver.y = project(solver.t, solver.y)
        # explicit Runge–Kutta solvers only (Method.explicit): SciPy's, with f and fun
        solver.f = solver.fun(solver.t, solver.y)  # type: ignore[attr-defined]
        self.y = solver.y[None, :]
        self._project = project

    def dense_output(self, lanes: np.ndarray) -> LaneDense:
        return _SolverDense(self.solver, self._project)


_FAILED = np.array([Status.FAILED])
_LANE = np.zeros(1, dtype=np.intp)  # the one lane
_DONE, _GOING = np.ones(1, dtype=bool), np.zeros(1, dtype=bool)


class _SolverDense:
    """One lane's interpolant: the solver's dense output, built on first use (it costs
    work for some methods), every state projected in a projected run."""

    def __init__(self, solver: Stepper, project: Projection | None) -> None:
        self.solver, self.project = solver, project
        self.built: Callable[[Any], np.ndarray] | None = None

    def of(self, which: int) -> Callable[[Any], np.ndarray]:
        if self.built is None:
            self.built = self.solver.dense_output()
        if self.project is None:
            return self.built
        return _projected(self.built, self.project)

    def value(self, t: np.ndarray, which: Any) -> np.ndarray:
        return np.atleast_2d(self.of(0)(np.asarray(t))).T


def _projected(
    dense: Callable[[Any], np.ndarray], project: Projection
) -> Callable[[Any], np.ndarray]:
    """The step's dense output with every interpolated state projected."""

    def evaluate(t: Any) -> np.ndarray:
        values = dense(t)
        if np.ndim(t) == 0:
            return project(float(t), values)
        columns = [project(float(s), values[:, i]) for i, s in enumerate(np.atleast_1d(t))]
        return np.stack(columns, axis=1)

    return evaluate


class EachLane:
    """The event functions of each lane (one :class:`~.events.EventWatch` per lane, None for
    a lane without): a single run's events, located lane by lane."""

    def __init__(self, watches: Sequence[EventWatch | None]) -> None:
        self.watches = watches
        # crossed() of each lane alone, made once (a single run asks it every step)
        self._alone = [np.array([watch is not None]) for watch in watches]

    def start(self, stepper: LaneStepper, lanes: np.ndarray) -> np.ndarray:
        for lane in lanes:
            watch = self.watches[lane]
            if watch is not None:
                watch.start(float(stepper.t[lane]), stepper.y[lane])
        return NOWHERE

    def crossed(self, stepper: LaneStepper, moved: np.ndarray) -> np.ndarray:
        if len(moved) == 1:
            return self._alone[moved[0]]
        return np.array([self.watches[lane] is not None for lane in moved], dtype=bool)

    def locate(
        self,
        stepper: LaneStepper,
        lanes: np.ndarray,
        t_old: np.ndarray,
        dense: LaneDense,
        which: np.ndarray,
    ) -> Found:
        events: list[tuple[int, str, float, np.ndarray]] = []
        stopped, t_stop, x_stop, names = [], [], [], []
        for j, lane in enumerate(lanes):
            watch = self.watches[lane]
            assert watch is not None  # crossed() named only lanes with a watch
            interpolant = dense.of(int(which[j]))
            found, stop = watch.check(
                float(t_old[j]), float(stepper.t[lane]), stepper.y[lane], interpolant
            )
            events.extend((int(lane), watch.names[i], t, interpolant(t)) for i, t in found)
            if stop:
                _, name, t, x = events[-1]
                stopped.append(lane)
                t_stop.append(t)
                x_stop.append(x)
                names.append(name)
        if not events:
            return NOT_FOUND
        n = stepper.y.shape[1]
        return Found(
            events,
            np.array(stopped, dtype=np.intp),
            np.array(t_stop, dtype=float),
            np.array(x_stop, dtype=float).reshape(-1, n),
            names,
        )
