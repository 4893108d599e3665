"""The variational integrators on the compiled path: the marches of
:mod:`lagrangian.simulation.variational.march` (midpoint rule) and
:mod:`lagrangian.simulation.variational.collocation_march` (Gauss–Legendre, Lobatto IIIA–IIIB),
step for
step, in numba loops.

:func:`fast_march` takes the arguments of :func:`~lagrangian.simulation.variational.march.march`
and returns the same :class:`~lagrangian.simulation.variational.march.Run`: the same equations,
Newton iterations, tolerances and starting guesses, so the two trajectories agree to rounding
(the tests hold them to 1e-10).  The system's terms are compiled to C functions by SymEngine's
LLVM backend (milliseconds, :mod:`lagrangian.numerics.fast.discrete`) and the loop, compiled
once per machine, calls them (:mod:`lagrangian.numerics.fast.midpoint`,
:mod:`lagrangian.numerics.fast.collocation`): a few microseconds a step for a double
pendulum, against a few hundred for the NumPy march.  :func:`fast_collocation_march` does the
same for :func:`~lagrangian.simulation.variational.collocation_march.collocation_march`.

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> grid = np.linspace(0.0, 1.0, 101)
>>> run = fast_march(mechanics, np.array([0.5, 0.0]), np.array([1.0, 9.81, 1.0]), grid,
...                  np.arange(101))  # doctest: +SKIP
>>> run.failure is None, run.q.shape  # doctest: +SKIP
(True, (101, 1))
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.numerics.fast.discrete import native_mechanics
from lagrangian.numerics.fast.discrete_loops import (
    discrete_march,
    run_march,
    state_arrays,
    system_arguments,
)
from lagrangian.numerics.fast.newton import (
    POSITION_DIVERGED,
    POSITION_SINGULAR,
    VELOCITY_DIVERGED,
    VELOCITY_SINGULAR,
)
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.march import Run, node_multipliers
from lagrangian.simulation.variational.step import not_converged, singular


def fast_march(
    mechanics: DiscreteMechanics,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """Step from x0 = [q; q_dot] over the nodes ``grid``, keeping the ``outputs``, as
    :func:`lagrangian.simulation.variational.march.march` does.

    Raises SimulationError when numba is missing or the terms cannot be compiled (nothing
    has been integrated then); a failed step, or Ctrl-C, ends the march with the nodes
    computed before it.
    """
    march = _March(mechanics, x0, parameters, grid, outputs)
    n, m = march.sizes
    state = (*march.start[:2], march.start[2], np.zeros(m), *march.start[3:], np.zeros((2, n)))
    return march.run("midpoint", (state,), progress)


def fast_collocation_march(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    x0: np.ndarray,
    parameters: np.ndarray,
    grid: np.ndarray,
    outputs: np.ndarray,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """The march of :func:`lagrangian.simulation.variational.collocation_march.collocation_march`,
    compiled (raises as :func:`fast_march`)."""
    march = _March(mechanics, x0, parameters, grid, outputs)
    m, s = march.sizes[1], tableau.stages
    stages = (np.tile(march.start[1], (s, 1)), np.zeros((s - 1 if m else 0, m)), np.zeros(1))
    arrays = (tableau.a, tableau.a_hat, tableau.b, tableau.c)
    coefficients = (*(np.ascontiguousarray(a, dtype=float) for a in arrays), tableau.lobatto)
    run = march.run("collocation", (coefficients, (*march.start, *stages)), progress)
    return run._replace(multipliers=np.full((len(run.outputs), m), np.nan))


class _March:
    """What both marches start from: the system's C functions, the grid with its output
    rows, the output arrays and the state at the first node (q, v, p, h, A, dh/dt)."""

    def __init__(
        self,
        mechanics: DiscreteMechanics,
        x0: np.ndarray,
        parameters: np.ndarray,
        grid: np.ndarray,
        outputs: np.ndarray,
    ) -> None:
        self.native = native_mechanics(mechanics)  # owns the machine code while we run
        self.functions, self.data = system_arguments(self.native)
        self.linear = mechanics.legendre_linear
        n, m = len(mechanics.coordinates), mechanics.constraint_count
        self.sizes = n, m
        self.grid, self.outputs = np.ascontiguousarray(grid, dtype=float), outputs
        self.p = np.ascontiguousarray(parameters, dtype=float)
        self.row_of = np.full(len(grid), -1, dtype=np.int64)
        self.row_of[outputs] = np.arange(len(outputs))
        self.out = state_arrays(n, m, len(outputs), len(grid) - 1)
        q, v = (np.array(part, dtype=float) for part in (x0[:n], x0[n:]))  # updated in place
        momentum = np.array(mechanics.legendre(q, v, self.grid[0], self.p)[0], dtype=float)
        at_start = mechanics.constraints(q, self.grid[0], self.p)
        self.start = (q, v, momentum, *(np.ascontiguousarray(a, dtype=float) for a in at_start))
        self.counts = np.array([0, 1, 0], dtype=np.int64)  # known history, evaluations, last

    def run(
        self, kind: str, arguments: tuple[object, ...], progress: Callable[[float], None] | None
    ) -> Run:
        """Run the compiled march ``kind`` in chunks; ``arguments`` are its own (after
        ``linear``, before ``counts``)."""
        march, grid, counts, out = discrete_march(kind), self.grid, self.counts, self.out
        fixed = (*self.functions, self.data, self.p, grid, self.row_of)

        def chunk(nodes: tuple[int, int]) -> int:
            return int(march(*fixed, nodes, self.linear, *arguments, counts, out))

        status, interrupted = run_march(chunk, len(grid), lambda: float(grid[counts[2]]), progress)
        last, outputs = int(counts[2]), self.outputs
        rows = int(np.searchsorted(outputs, last, side="right"))
        return Run(
            outputs[:rows],
            out[0][:rows],
            out[1][:rows],
            node_multipliers(grid, out[3], out[4], last, outputs[:rows]),
            out[2][:rows],
            float(grid[last]),
            int(counts[1]),
            failure_message(status, grid, last),
            interrupted,
        )


def failure_message(status: int, grid: np.ndarray, last: int) -> str | None:
    """The message of a march that stopped with ``status`` after node ``last`` (None unless
    it failed), as the NumPy march words it."""
    t0 = float(grid[last])
    t1 = float(grid[min(last + 1, len(grid) - 1)])
    messages = {
        POSITION_DIVERGED: lambda: not_converged("position", t0),
        POSITION_SINGULAR: lambda: singular("position"),
        VELOCITY_DIVERGED: lambda: not_converged("velocity", t1),
        VELOCITY_SINGULAR: lambda: singular("velocity"),
    }
    message = messages.get(status)
    return None if message is None else message()
