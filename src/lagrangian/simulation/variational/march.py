"""march: the variational integrator's steps over a time grid, and the multipliers at its nodes.

Each step solves the equations of :mod:`lagrangian.simulation.variational.step` for
(q_{k+1}, lambda_k), then for (q_dot_{k+1}, mu_k) and p_{k+1}.  lambda_k and mu_{k-1} are the
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
from typing import NamedTuple

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.simulation.variational.step import position_step, velocity_step


class Run(NamedTuple):
    """What :func:`march` computed at the output nodes it reached (``outputs`` index the grid).

    ``constraint_residual`` is max(|h|, |A q_dot + dh/dt|) at each output; ``reached`` the
    last time reached; ``evaluations`` the number of evaluations of the compiled discrete
    equations (midpoint terms and Legendre map: the work done); ``failure`` what stopped the
    march early, or None; ``interrupted`` whether Ctrl-C did.
    """

    outputs: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    multipliers: np.ndarray
    constraint_residual: np.ndarray
    reached: float
    evaluations: int
    failure: str | None
    interrupted: bool = False


def march(
    mechanics: DiscreteMechanics,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """Step from the state x0 = [q; q_dot] over the nodes ``grid``, keeping the ``outputs``.

    With constraints every step solves for the velocity (it fixes p_{k+1}); without, only the
    steps ending at an output do (the inverse Legendre map).  A failed step, or Ctrl-C,
    ends the march with the nodes computed before it.
    """
    n, m, p = len(mechanics.coordinates), mechanics.constraint_count, parameters
    row_of = np.full(len(grid), -1)
    row_of[outputs] = np.arange(len(outputs))
    q_out, v_out = np.full((len(outputs), n), np.nan), np.full((len(outputs), n), np.nan)
    residual_out = np.full(len(outputs), np.nan)
    lam_steps, mu_steps = np.full((len(grid) - 1, m), np.nan), np.full((len(grid) - 1, m), np.nan)
    q, v = x0[:n].copy(), x0[n:].copy()
    momentum = mechanics.legendre(q, v, grid[0], p)[0]
    h, jacobian, rate = mechanics.constraints(q, grid[0], p)
    lam = np.zeros(m)
    history: tuple[np.ndarray, ...] = ()
    failure, last, evaluations, interrupted = None, 0, 1, False
    for k in range(len(grid)):
        row = row_of[k]
        if row >= 0:
            q_out[row], v_out[row] = q, v
            residual_out[row] = np.max(np.abs((*h, *(jacobian @ v + rate))), initial=0.0)
        t0 = float(grid[k])
        try:  # node k is kept: a failure or Ctrl-C from here on ends the march at it
            if progress is not None and k:
                progress(t0)
            if k == len(grid) - 1:
                break
            dt = float(grid[k + 1]) - t0
            position = position_step(
                mechanics, q, momentum, t0, dt, p, jacobian, _guess(grid, k, q, history), lam
            )
            momentum, evaluations = position.momentum, evaluations + position.evaluations
            if m or row_of[k + 1] >= 0:
                jacobian, rate, h = position.jacobian, position.rate, position.h
                slope = (position.q - q) / dt
                velocity = velocity_step(
                    mechanics, position.q, momentum, t0 + dt, dt / 2, p, jacobian, rate, slope
                )
                v, mu_steps[k], momentum = velocity.v, velocity.multipliers, velocity.momentum
                evaluations += velocity.evaluations
        except SimulationError as error:
            failure = str(error)
            break
        except KeyboardInterrupt:
            interrupted = True
            break
        history = (q, *history[:1])
        q, lam = position.q, position.multipliers
        lam_steps[k], last = lam, k + 1
    rows = int(np.searchsorted(outputs, last, side="right"))
    multipliers = node_multipliers(grid, lam_steps, mu_steps, last, outputs[:rows])
    return Run(
        outputs[:rows],
        q_out[:rows],
        v_out[:rows],
        multipliers,
        residual_out[:rows],
        float(grid[last]),
        evaluations,
        failure,
        interrupted,
    )


def _guess(grid: np.ndarray, k: int, q: np.ndarray, history: tuple[np.ndarray, ...]) -> np.ndarray:
    """q_{k+1} extrapolated by the polynomial through q_k and the ``history`` q_{k-1},
    q_{k-2} (as many as there are): an error O(dt^3) that Newton's method removes in two
    corrections."""
    if not history:
        return q.copy()
    s1 = (q - history[0]) / (grid[k] - grid[k - 1])
    if len(history) < 2:
        return q + (grid[k + 1] - grid[k]) * s1
    s0 = (history[0] - history[1]) / (grid[k - 1] - grid[k - 2])
    curvature = (s1 - s0) / (grid[k] - grid[k - 2])
    return q + (grid[k + 1] - grid[k]) * (s1 + (grid[k + 1] - grid[k - 1]) * curvature)


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
