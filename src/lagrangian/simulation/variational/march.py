"""march: the variational integrator's steps over a time grid, and the multipliers at its nodes.

The steppers of :mod:`lagrangian.simulation.variational.stepper`, driven by the one Python
loop, in NumPy (the compiled marches of :mod:`lagrangian.simulation.variational.compiled` give
the same :class:`Run`).  Each step of the midpoint rule solves the equations of
:mod:`lagrangian.simulation.variational.step` for (q_{k+1}, lambda_k), then for
(q_dot_{k+1}, mu_k) and p_{k+1}.  lambda_k and mu_{k-1} are the
two halves of the constraint impulse at q_k; each is only a first-order approximation of the
multiplier lambda(t_k) (their errors are equal and opposite: the scheme is symmetric), so the
multiplier reported at node k is their combination that cancels those errors,

    lambda(t_k) = (dt_{k-1} lambda_k + dt_k mu_{k-1}) / (dt_{k-1} + dt_k) + O(dt^2)

(the mean for equal steps), and at the first and last node, which have one half only, the
line through the next two nodes' values.

>>> import numpy as np
>>> grid = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
>>> halves = np.array([[0.5], [1.5], [2.5], [3.5]])  # lambda(t) = t, errors +-0.5
>>> node_multipliers(grid, halves, halves, 4, np.arange(5))[:, 0]
array([0., 1., 2., 3., 4.])
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from lagrangian.errors import Fix
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.loop import integrate
from lagrangian.simulation.variational.stepper import MidpointStepper, NodeStepper


@dataclass(frozen=True)
class StepSchedule:
    """The nodes of a march: steps of ``dt`` from t0 to t1 (a shorter last one), and the output
    times ``t_out`` as nodes too (None: every node is an output).

    :meth:`grid` makes them all at once; the compiled marches make the same nodes one by one
    as they reach them (:mod:`lagrangian.numerics.fast.discrete_nodes`), so that a run of
    many steps keeps only its output rows.
    """

    t0: float
    t1: float
    dt: float
    t_out: np.ndarray | None = None

    @property
    def count(self) -> int:
        """The number of steps of dt (the last one shorter, to end at t1)."""
        return max(int(np.ceil((self.t1 - self.t0) / self.dt - 1e-9)), 1)

    @property
    def tolerance(self) -> float:
        """Output times within this of a node fall on it (no node of their own)."""
        return 1e-9 * self.dt

    @property
    def rows(self) -> int:
        """The number of output rows."""
        return self.count + 1 if self.t_out is None else len(self.t_out)

    def grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The node times (steps of dt, a shorter last one, plus every output time) and the
        indices of the output times in them (every node when no output times are asked
        for)."""
        t0, t1, dt = self.t0, self.t1, self.dt
        grid = np.minimum(t0 + dt * np.arange(self.count + 1), t1)
        grid[-1] = t1
        if self.t_out is None:
            return grid, np.arange(len(grid))
        grid = np.union1d(grid, self.t_out)
        grid = grid[np.concatenate(([True], np.diff(grid) > self.tolerance))]
        outputs = np.searchsorted(grid, self.t_out - self.tolerance)
        return grid, np.clip(outputs, 0, len(grid) - 1)


class Run(NamedTuple):
    """What :func:`march` computed at the output nodes it reached (``outputs`` index the grid,
    ``t`` are their times).

    ``constraint_residual`` is max(|h|, |A q_dot + dh/dt|) at each output; ``reached`` the
    last time reached; ``evaluations`` the number of evaluations of the compiled discrete
    equations (midpoint terms and Legendre map: the work done); ``failure`` what stopped the
    march early, or None; ``interrupted`` whether Ctrl-C did.
    """

    outputs: np.ndarray
    t: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    multipliers: np.ndarray
    constraint_residual: np.ndarray
    reached: float
    evaluations: int
    failure: str | Fix | None
    interrupted: bool = False


def march(
    mechanics: DiscreteMechanics,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
    budget: Budget | None = None,
) -> Run:
    """Step the midpoint rule from the state x0 = [q; q_dot] over the nodes ``grid``, keeping
    the ``outputs`` (:class:`~lagrangian.simulation.variational.stepper.MidpointStepper`).

    With constraints every step solves for the velocity (it fixes p_{k+1}); without, only the
    steps ending at an output do (the inverse Legendre map).  A failed step, Ctrl-C or the
    ``budget`` (default: none beyond the grid) ends the march with the nodes computed before.
    """
    stepper = MidpointStepper(mechanics, x0, parameters, grid, output_nodes(grid, outputs))
    return stepped(stepper, outputs, progress, budget)


def output_nodes(grid: np.ndarray, outputs: np.ndarray) -> np.ndarray:
    """Whether each node of ``grid`` is one of the ``outputs`` (indices)."""
    wanted = np.zeros(len(grid), dtype=bool)
    wanted[outputs] = True
    return wanted


def stepped(
    stepper: NodeStepper,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None,
    budget: Budget | None,
) -> Run:
    """Drive ``stepper`` by the one Python loop
    (:func:`lagrangian.simulation.integrators.loop.integrate`) to the end of its grid and
    gather the :class:`Run` of its ``outputs``: the multipliers at the midpoint rule's nodes
    (NaN for a collocation method, whose stage multipliers combined at a node are only
    second-order accurate) and the constraint residuals."""
    grid = stepper.grid
    budget = budget or Budget("", max_steps=len(grid), start=float(grid[0]))
    run = integrate(
        lambda: stepper, float(grid[0]), stepper.y, grid[outputs], None, progress, None, budget
    )
    n, rows = len(stepper.q), len(run.t)
    reached = outputs[:rows]
    if isinstance(stepper, MidpointStepper):
        multipliers = node_multipliers(grid, stepper.lam, stepper.mu, stepper.k, reached)
    else:
        multipliers = np.full((rows, stepper.mechanics.constraint_count), np.nan)
    return Run(
        reached,
        grid[reached],
        run.x[:, :n],
        run.x[:, n:],
        multipliers,
        stepper.residuals[reached],
        float(grid[stepper.k]),
        stepper.evaluations,
        run.failure,
        run.interrupted,
    )


def node_multipliers(
    grid: np.ndarray, lam: np.ndarray, mu: np.ndarray, last: int, nodes: np.ndarray
) -> np.ndarray:
    """The multipliers at the grid ``nodes`` (each <= ``last``, the last node reached) from
    lambda_k and mu_k of every step k (module docstring); NaN when no step was made."""
    values = np.full((len(nodes), lam.shape[1]), np.nan)
    if last == 0:
        return values
    dt = np.diff(grid[: last + 1])

    def interior(k: np.ndarray) -> np.ndarray:
        before, after = dt[k - 1, None], dt[k, None]
        return (before * lam[k] + after * mu[k - 1]) / (before + after)

    inside = (nodes > 0) & (nodes < last)
    values[inside] = interior(nodes[inside])
    for end, one_sided, neighbours in ((0, lam[0], (1, 2)), (last, mu[last - 1], (-1, -2))):
        if last >= 3:
            near = np.array([end + neighbours[0], end + neighbours[1]])
            a, b = interior(near)
            one_sided = a + (grid[end] - grid[near[0]]) * (b - a) / (grid[near[1]] - grid[near[0]])
        values[nodes == end] = one_sided
    return values


def end_multipliers(halves: np.ndarray, last: int, first: bool) -> np.ndarray:
    """The multipliers at node 0 (``first``) or at the ``last`` node reached, from the halves
    (lambda_k, mu_k, dt_k) of the first three steps (rows 0-2 of ``halves``) or of the last
    three (rows 3-5, by k mod 3), as :func:`node_multipliers` gives them from every step's."""
    m = (halves.shape[1] - 1) // 2
    steps = min(last, 3)
    rows = range(steps) if first else [3 + k % 3 for k in range(last - steps, last)]
    taken = halves[list(rows)]
    grid = np.concatenate(([0.0], np.cumsum(taken[:, 2 * m])))
    node = 0 if first else steps
    return node_multipliers(grid, taken[:, :m], taken[:, m : 2 * m], steps, np.array([node]))[0]
