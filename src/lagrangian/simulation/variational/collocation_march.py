"""The collocation integrators' steps over a time grid, in NumPy.

Each step solves the stage equations of :mod:`lagrangian.simulation.variational.collocation_step`
from
the stage velocities of the step before, extrapolated (:meth:`Tableau.extrapolation
<lagrangian.simulation.variational.collocation.Tableau.extrapolation>`), then, with constraints or
at an
output, the velocity equations of the step's end (the Legendre map, with the multiplier
Lambda_s of the Lobatto pair: :func:`lagrangian.simulation.variational.step.velocity_step`
with the weight dt b_s).  The result is the :class:`~lagrangian.simulation.variational.march.Run`
of the midpoint rule's march, without multipliers (NaN: the stage multipliers combined at a
node are only second-order accurate; the integrator takes those of the multiplier form at
each output state instead).

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> from lagrangian.simulation.variational.collocation import gauss
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> grid = np.linspace(0.0, 1.0, 11)
>>> run = collocation_march(mechanics, gauss(2), np.array([0.1, 0.0]),
...                         np.array([1.0, 9.81, 1.0]), grid, np.arange(11))
>>> bool(abs(run.q[-1, 0] - 0.1 * np.cos(np.sqrt(9.81))) < 2e-4)  # the small-angle solution
True
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.collocation_step import stage_step
from lagrangian.simulation.variational.march import Run
from lagrangian.simulation.variational.step import velocity_step


def collocation_march(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """Step from x0 = [q; q_dot] over the nodes ``grid`` by ``tableau``, keeping the
    ``outputs``; a failed step, or Ctrl-C, ends the march with the nodes computed before."""
    n, m, p, s = len(mechanics.coordinates), mechanics.constraint_count, parameters, tableau.stages
    row_of = np.full(len(grid), -1)
    row_of[outputs] = np.arange(len(outputs))
    q_out, v_out = np.full((len(outputs), n), np.nan), np.full((len(outputs), n), np.nan)
    residual_out = np.full(len(outputs), np.nan)
    q, v = x0[:n].astype(float), x0[n:].astype(float)
    momentum = mechanics.legendre(q, v, grid[0], p)[0]
    h, jacobian, rate = mechanics.constraints(q, grid[0], p)
    V, lam, previous = np.tile(v, (s, 1)), np.zeros((s - 1 if m else 0, m)), None
    failure, last, evaluations, interrupted = None, 0, 1, False
    for k in range(len(grid)):
        if row_of[k] >= 0:
            q_out[row_of[k]], v_out[row_of[k]] = q, v
            residual_out[row_of[k]] = np.max(np.abs((*h, *(jacobian @ v + rate))), initial=0.0)
        try:
            if progress is not None and k:
                progress(float(grid[k]))
            if k == len(grid) - 1:
                break
            dt = float(grid[k + 1] - grid[k])
            if previous is not None:
                V = tableau.extrapolation(dt / previous) @ V
            stage = stage_step(mechanics, tableau, q, momentum, float(grid[k]), dt, p, V, lam)
            momentum, evaluations = stage.momentum, evaluations + stage.evaluations
            if m or row_of[k + 1] >= 0:
                h, jacobian, rate = stage.h, stage.jacobian, stage.rate
                weight = dt * float(tableau.b[-1])
                end = velocity_step(
                    mechanics, stage.q, momentum, float(grid[k + 1]), weight, p, jacobian, rate,
                    stage.V[-1],
                )  # fmt: skip
                v, momentum, evaluations = end.v, end.momentum, evaluations + end.evaluations
        except SimulationError as error:
            failure = str(error)
            break
        except KeyboardInterrupt:
            interrupted = True
            break
        q, V, lam, previous, last = stage.q, stage.V, stage.multipliers, dt, k + 1
    rows = int(np.searchsorted(outputs, last, side="right"))
    return Run(
        outputs[:rows],
        q_out[:rows],
        v_out[:rows],
        np.full((rows, m), np.nan),
        residual_out[:rows],
        float(grid[last]),
        evaluations,
        failure,
        interrupted,
    )
