"""The collocation integrators' steps over a time grid, in NumPy: the
:class:`~lagrangian.simulation.variational.stepper.CollocationStepper` driven by the one Python
loop.

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

from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.march import Run, output_nodes, stepped
from lagrangian.simulation.variational.stepper import CollocationStepper


def collocation_march(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
    budget: Budget | None = None,
) -> Run:
    """Step from x0 = [q; q_dot] over the nodes ``grid`` by ``tableau``, keeping the
    ``outputs``; a failed step, Ctrl-C or the ``budget`` ends the march with the nodes
    computed before."""
    nodes = output_nodes(grid, outputs)
    stepper = CollocationStepper(mechanics, tableau, x0, parameters, grid, nodes)
    return stepped(stepper, outputs, progress, budget)
