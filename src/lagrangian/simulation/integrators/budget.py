"""How long a run may take: a step budget, a wall-time budget, and stiffness detection.

A run that cannot end in reasonable time is stopped with a message that says why and what to
change, keeping the rows computed so far:

* ``max_steps`` (default :data:`DEFAULT_MAX_STEPS`) accepted steps, and ``max_wall_time``
  seconds when given;
* **stiffness on an explicit method.**  An explicit Runge–Kutta method on a stiff problem
  takes steps as small as its stability region allows, however smooth the solution.  After
  each step the dominant eigenvalue of the Jacobian is estimated from two stages at the same
  time (the stage of the step's end, y_j, and the new state y1, Hairer & Wanner, *Solving
  Ordinary Differential Equations II*, §IV.2, the test of DOPRI5 and DOP853):

      h |lambda| ~ h ||f(y1) - f(y_j)|| / ||y1 - y_j||,

  and the problem is stiff for the method when h |lambda| stays near the edge of its
  stability region (3.3 for RK45, 6.1 for DOP853) for most of the recent steps.  A stiff
  run that still needs more than :data:`STIFF_STEPS_LEFT` steps at its current step size is
  stopped with the advice to use an implicit method (Radau, BDF, LSODA); a shorter one ends
  normally, with the advice in its note;
* one budget for the **whole run**: a run integrated piece by piece (switching, active
  sets, impacts: :mod:`lagrangian.simulation.integrators.piecewise`) hands the same Budget
  to every piece, so its steps, its wall time and its step-size history add up across
  the pieces (a motion switching a million times spends a million steps, not one per piece);
* a batch's members are the **lanes** of one run (:mod:`lagrangian.simulation.integrators.lanes`),
  each with ``max_steps`` steps of its own and the wall time shared, as the C loop runs a
  batch's members (stiffness and collapse are watched on a single run);
* a **collapsed step size** (the last :data:`COLLAPSE_STEPS` steps advanced t by less than
  :data:`COLLAPSE` of the time span) stops the run: an integrator creeping at 1e-12 per step
  at a singularity would otherwise fill the memory before its step budget is spent.
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from lagrangian.errors import Fix, Setting
from lagrangian.numerics.status import Status

if TYPE_CHECKING:  # the protocol module imports the inputs, which import this module
    from lagrangian.simulation.inputs import Inputs
    from lagrangian.simulation.integrators.lanes import LaneStepper
    from lagrangian.simulation.integrators.protocol import Stepper

#: Accepted steps a run may take unless ``max_steps`` says otherwise (about a minute and a
#: half of SciPy's Python stepping).
DEFAULT_MAX_STEPS = 1_000_000
#: A stiff run that still needs more steps than this at its current step size is stopped.
STIFF_STEPS_LEFT = 100_000
#: |h lambda| at the edge of each explicit method's stability region on the negative real axis.
STABILITY_EDGE = {"RK45": 3.3, "DOP853": 6.1}
#: The share of the last ``WINDOW`` steps near the edge that makes a run stiff.
WINDOW, SHARE, NEAR = 50, 0.8, 0.85
#: A run whose last COLLAPSE_STEPS steps advanced t by less than COLLAPSE of the time span
#: has a collapsed step size (LSODA creeping at 1e-12 per step, for ever).
COLLAPSE_STEPS, COLLAPSE = 10_000, 1e-9
#: What a stiff run should change, each interface naming the method its way.
IMPLICIT_ADVICE = Fix("use an implicit method: {} (or BDF, LSODA)", (Setting("method", "Radau"),))


# The reasons a run stops, in the words every integrator uses (SciPy's steps, the C loop),
# their options left for each front end to word (``max_steps=`` in Python, ``--max-steps``
# on the command line).


def collapse_message(advanced: float, t: float) -> Fix:
    """The last ``COLLAPSE_STEPS`` steps advanced t by only ``advanced``, near ``t``."""
    return (
        f"the step size collapsed: the last {COLLAPSE_STEPS:,} steps advanced t by "
        f"{advanced:.3g} near t = {t:.6g} — the equations may be singular "
        "there (a collision, a blow-up, a mass matrix losing rank) or stiff; "
        "check the model near that state, or " + IMPLICIT_ADVICE + "."
    )


def stiffness_message(method: str, stiff_since: float, step: float) -> Fix:
    """Stiff since ``stiff_since``, steps of ``step`` too small to finish."""
    return (
        f"the problem is stiff for {method} (since t = {stiff_since:.6g}, "
        f"steps of {step:.3g} held by stability, not accuracy): it would need more "
        f"than {STIFF_STEPS_LEFT:,} further steps — " + IMPLICIT_ADVICE + "."
    )


def step_budget_message(max_steps: int, stiff_since: float | None) -> Fix:
    """``max_steps`` taken before the end; the fix suggests ten times as many."""
    more = Fix("pass {} to allow more steps.", (Setting("max_steps", 10 * max_steps),))
    return f"the step budget of {max_steps:,} steps is used up" + _stiff_hint(stiff_since) + more


def wall_time_message(max_wall_time: float, steps: int, stiff_since: float | None) -> Fix:
    """``max_wall_time`` seconds spent after ``steps`` steps."""
    more = Fix("pass a larger {}.", (Setting("max_wall_time"),))
    spent = f"the wall-time budget of {max_wall_time:g} s is used up after {steps:,} steps"
    return spent + _stiff_hint(stiff_since) + more


def _stiff_hint(stiff_since: float | None) -> Fix:
    if stiff_since is None:
        return Fix(" — ")
    return " (the problem is stiff: " + IMPLICIT_ADVICE + ") — "


@dataclass
class Budget:
    """The budget of one run, checked after every accepted step."""

    method: str
    max_steps: int = DEFAULT_MAX_STEPS
    max_wall_time: float | None = None
    start: float = 0.0  # t0 of the run
    steps: int = 0
    started: float = field(default_factory=time.monotonic)
    stiff_since: float | None = None
    #: Why the budget ended the run, in the codes every loop shares (None: it did not).
    ended: Status | None = None
    #: The steps of each lane of a run of several lanes (None until they step).
    lane_steps: np.ndarray | None = None
    _recent: deque[bool] = field(default_factory=lambda: deque(maxlen=WINDOW))
    _near: int = 0  # how many of _recent are True (kept as they come and go)
    _times: deque[float] = field(default_factory=lambda: deque(maxlen=COLLAPSE_STEPS))

    @classmethod
    def of(cls, inputs: Inputs) -> Budget:
        """The budget of a run from its checked inputs (its method, step and time budgets)."""
        return cls(inputs.method, inputs.max_steps, inputs.max_wall_time, start=inputs.t_span[0])

    def spend(self, solver: Stepper, t_old: float, y_old: np.ndarray, t_end: float) -> Fix | None:
        """Count the step just taken; the reason to stop (with the options that would let
        the run go on), or None."""
        self.steps += 1
        self._watch_stiffness(solver, t_old, y_old)
        self._times.append(float(solver.t))
        if len(self._times) == COLLAPSE_STEPS:
            advanced = abs(self._times[-1] - self._times[0])
            if advanced <= COLLAPSE * max(abs(t_end - self.start), abs(solver.t), 1e-300):
                self.ended = Status.COLLAPSED
                return collapse_message(advanced, float(solver.t))
        if self.stiff_since is not None:
            step = abs(solver.t - t_old)
            if step > 0 and abs(t_end - solver.t) / step > STIFF_STEPS_LEFT:
                self.ended = Status.STIFF
                return stiffness_message(self.method, self.stiff_since, step)
        return self.used_up()

    def spend_lanes(self, stepper: LaneStepper, moved: np.ndarray) -> tuple[np.ndarray, Fix | None]:
        """Count the step each lane of ``moved`` just took; the lanes whose budget is spent
        and why (:attr:`ended` the code).  One lane stepping a solver (a single run) is
        :meth:`spend`; lanes of a batch each spend ``max_steps``, and the wall time."""
        solver = getattr(stepper, "solver", None)
        if solver is not None and len(moved) == 1:
            t_old, y_old = stepper.t_old, stepper.y_old  # type: ignore[attr-defined]
            reason = self.spend(solver, float(t_old[0]), y_old, stepper.t_bound)
            return (moved if reason is not None else moved[:0]), reason
        if self.lane_steps is None:
            self.lane_steps = np.zeros(len(stepper.t), dtype=np.int64)
        self.lane_steps[moved] += 1
        self.steps = int(self.lane_steps.max(initial=0))
        over = moved[self.lane_steps[moved] >= self.max_steps]
        if len(over):
            self.ended = Status.STEP_BUDGET
            return over, step_budget_message(self.max_steps, None)
        if self.max_wall_time is not None and time.monotonic() - self.started > self.max_wall_time:
            self.ended = Status.WALL_TIME
            return moved, wall_time_message(self.max_wall_time, self.steps, None)
        return moved[:0], None

    def used_up(self) -> Fix | None:
        """The reason to stop when the steps or the wall time are spent, else None (checked
        after every step, and by the piecewise loop between two pieces: a piece ended by its
        guard says nothing of the budget)."""
        if self.steps >= self.max_steps:
            self.ended = Status.STEP_BUDGET
            return step_budget_message(self.max_steps, self.stiff_since)
        if self.max_wall_time is not None and time.monotonic() - self.started > self.max_wall_time:
            self.ended = Status.WALL_TIME
            return wall_time_message(self.max_wall_time, self.steps, self.stiff_since)
        return None

    def note(self) -> str:
        """What a run that reached its end should say about stiffness ('' if nothing)."""
        if self.stiff_since is None:
            return ""
        return (
            f"The problem is stiff for {self.method} from t = {self.stiff_since:.6g}; "
            f"an implicit method (Radau, BDF, LSODA) would take fewer steps."
        )

    def _watch_stiffness(self, solver: Stepper, t_old: float, y_old: np.ndarray) -> None:
        edge = STABILITY_EDGE.get(self.method)
        if edge is None or self.stiff_since is not None:
            return
        h_lambda = step_eigenvalue(solver, t_old, y_old)
        if h_lambda is None:
            return
        recent, near = self._recent, h_lambda > NEAR * edge
        if len(recent) == WINDOW:
            self._near -= recent[0]  # the oldest leaves the window as this one comes
        recent.append(near)
        self._near += near
        if len(recent) == WINDOW and self._near >= SHARE * WINDOW:
            self.stiff_since = float(solver.t)


#: The stage with c_j = 1 of each solver class's tableau (None: it has none).
_END_STAGE: dict[type, int | None] = {}


def _end_stage(solver: Any, c: np.ndarray) -> int | None:
    """The first stage j > 0 with c_j = 1 (the step's end), found once per solver class
    (SciPy's tableaus are class attributes)."""
    kind = type(solver)
    if kind not in _END_STAGE:
        ends = [j for j in range(1, len(c)) if c[j] == 1.0]
        _END_STAGE[kind] = ends[0] if ends else None
    return _END_STAGE[kind]


def step_eigenvalue(solver: Any, t_old: float, y_old: np.ndarray) -> float | None:
    """h ||f(y1) - f(y_j)|| / ||y1 - y_j|| for the last step of an explicit Runge–Kutta
    solver of SciPy, y_j the stage with c_j = 1 (None for a solver without one)."""
    c = getattr(solver, "C", None)
    stages = getattr(solver, "K", None)
    if c is None or stages is None:
        return None
    j = _end_stage(solver, c)
    if j is None:
        return None
    h = solver.t - t_old
    apart = solver.y - (y_old + h * (solver.A[j, :j] @ stages[:j]))
    squared = float(apart @ apart)  # the norms by dot products: np.linalg.norm costs more
    if squared == 0.0 or not math.isfinite(squared):
        return None
    change = stages[-1] - stages[j]
    return abs(h) * math.sqrt(float(change @ change) / squared)
