"""The shape every integrator shares: what it is given and what it returns.

A simulation is three pieces, as in diffrax (a solver stepping a term) or jax-md (an
``init``/``step`` pair):

* a **dynamics** object, one per formulation of the motion (free state equations, the
  multiplier form with Baumgarte's stabilization or projection, active sets of unilateral
  constraints, the discrete Lagrangian of the variational integrator): the vector field
  dx/dt = f(t, x) on the state x = [q; q_dot] (or the discrete equations), how to read q and
  q_dot from x, and the constraint multipliers and residuals at the output rows;
* an **integrator** behind :class:`Integrator` that runs it from the checked inputs: the one
  Python loop (:mod:`lagrangian.simulation.integrators.loop`) stepping a :class:`Stepper`
  (SciPy's solvers, RK4, the variational and collocation steps) as one lane of its lanes
  axis (:mod:`lagrangian.simulation.integrators.lanes`; a batch's members are the lanes of
  one vectorized stepper), the compiled loops (the C
  loop of the Runge–Kutta methods, the numba marches of the variational ones), or the
  piecewise loop (:mod:`lagrangian.simulation.integrators.piecewise`) of a motion whose
  equations change at events;
* the **outcome**: one :class:`Integration` value that :mod:`lagrangian.simulation.outcome`
  turns into the Trajectory, deciding there, once, what a failure or an interruption means.

>>> import numpy as np
>>> run = Integration(t=np.array([0.0]), x=np.array([[1.0, 0.0]]), t_reached=0.0,
...                   x_reached=np.array([1.0, 0.0]))
>>> run.status
'success'
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

import numpy as np

from lagrangian.errors import Fix
from lagrangian.numerics.status import Outcome
from lagrangian.simulation.impacts import ImpactRecord
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.events import EventWatch

#: Called with the time reached after every accepted step (a progress bar).
Progress = Callable[[float], None]


@dataclass(frozen=True)
class Integration:
    """What an integrator computed: states x at the output times t, and how the run ended.

    ``events`` are (name, time, state) in the order of time; ``stopped_by`` names the
    terminal event that ended the run (its row is the last); ``failure`` is None unless the
    run failed, then the reason (a :class:`~lagrangian.errors.Fix` when it names options to
    change, such as ``max_steps``); ``interrupted`` is True after Ctrl-C.  ``t_reached`` and
    ``x_reached`` are the last accepted step.  ``multipliers`` and ``constraint_residual``
    (rows of t) are given by integrators that compute them on the way (else the dynamics
    evaluates them at the rows); ``note`` is what the integrator says about a run that
    reached the end; ``impacts`` the velocity jumps at impacts, in the order of time.
    """

    t: np.ndarray
    x: np.ndarray
    t_reached: float
    x_reached: np.ndarray
    events: tuple[tuple[str, float, np.ndarray], ...] = ()
    failure: str | Fix | None = None
    interrupted: bool = False
    stopped_by: str | None = None
    multipliers: np.ndarray | None = None
    constraint_residual: np.ndarray | None = None
    note: str = ""
    impacts: tuple[ImpactRecord, ...] = ()

    @property
    def status(self) -> Outcome:
        """``"success"`` (the end or a terminal event), ``"failed"`` or ``"interrupted"``:
        an :class:`~lagrangian.numerics.status.Outcome`, the words of every loop and batch."""
        if self.interrupted:
            return Outcome.INTERRUPTED
        return Outcome.FAILED if self.failure is not None else Outcome.SUCCESS


class Motion(Protocol):
    """What the Trajectory needs of a formulation besides the states: the multipliers'
    names, q and q_dot from a state, and the constraint rows."""

    @property
    def multiplier_names(self) -> tuple[str, ...]:
        """Names of the Lagrange multipliers (empty without constraints)."""
        ...

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, every q_dot) at (t, x)."""
        ...

    def residual(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        """The largest constraint residual max(|h|, |A q_dot + b|) (0 without constraints)."""
        ...

    def constraint_rows(
        self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The multipliers (rows, m) and the largest residual (rows,) at the output rows,
        or None without constraints (or when the integrator gives them)."""
        ...

    def start(self, inputs: Inputs, project_initial: bool) -> Inputs:
        """``inputs`` with an initial state this formulation can start from: checked against
        the constraints, projected onto them when asked (SimulationInputError if not)."""
        ...


class Dynamics(Motion, Protocol):
    """The motion as a vector field on the state x = [q; q_dot] (first-order coordinates
    keep only q)."""

    def field(self, t: float, x: np.ndarray) -> np.ndarray:
        """dx/dt at (t, x)."""
        ...

    def projection(self) -> Callable[[float, np.ndarray], np.ndarray] | None:
        """x -> the nearest state on the constraints, applied after every step, or None."""
        ...


class Stepper(Protocol):
    """One integration method, one step per call: the shape of SciPy's ``OdeSolver`` (and of
    diffrax's ``AbstractSolver``: init, step, dense output), which the one Python loop drives.

    ``t`` and ``y`` are the time and state after the last step, ``t_bound`` the end of the
    span, ``status`` ``"running"`` until the end is reached (``"finished"``) or a step fails
    (``"failed"``, its message returned by ``step``); ``dense_output`` is the state between
    the last two steps' times (a function of a time or an array of times, exact at both).
    A step may also raise SimulationError, ArithmeticError or LinAlgError: a failure.
    """

    t: float
    y: np.ndarray
    t_bound: float
    status: str

    def step(self) -> str | None:
        """Take one step; the message of a failed step, else None."""
        ...

    def dense_output(self) -> Callable[[Any], np.ndarray]:
        """The state over the last step."""
        ...


#: The formulation an integrator steps (a Dynamics, or the variational integrator's own).
D = TypeVar("D", contravariant=True)


class Integrator(Protocol[D]):
    """Steps a formulation over ``inputs.t_span`` from ``inputs.x0`` (already checked),
    keeping every row computed before a failure or an interruption."""

    def run(
        self,
        dynamics: D,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration: ...
