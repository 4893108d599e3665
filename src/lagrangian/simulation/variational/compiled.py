"""The variational integrators on the compiled path: the marches of
:mod:`lagrangian.simulation.variational.march` (midpoint rule) and
:mod:`lagrangian.simulation.variational.collocation_march` (Gauss–Legendre, Lobatto IIIA–IIIB),
step for
step, in numba loops.

:func:`fast_march` takes the arguments of :func:`~lagrangian.simulation.variational.march.march`
(or, in place of the grid, a :class:`~lagrangian.simulation.variational.march.StepSchedule`,
whose nodes the march makes as it reaches them: the memory of a run is that of its output
rows) and returns the same :class:`~lagrangian.simulation.variational.march.Run`: the same
equations, Newton iterations, tolerances and starting guesses, so the two trajectories agree
to rounding (the tests hold them to 1e-10).  The system's terms are compiled to C functions
by SymEngine's LLVM backend (milliseconds, :mod:`lagrangian.numerics.fast.discrete`) and the
loop, compiled once per machine, calls them (:mod:`lagrangian.numerics.fast.midpoint`,
:mod:`lagrangian.numerics.fast.collocation`): about a microsecond a step for a double
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
    output_arrays,
    run_march,
    system_arguments,
)
from lagrangian.numerics.fast.discrete_nodes import CURSOR, EVALUATIONS, NODE
from lagrangian.numerics.fast.newton import (
    POSITION_DIVERGED,
    POSITION_SINGULAR,
    VELOCITY_DIVERGED,
    VELOCITY_SINGULAR,
)
from lagrangian.numerics.stage_prediction import HISTORY
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.march import Run, StepSchedule, end_multipliers
from lagrangian.simulation.variational.step import not_converged, singular


def fast_march(
    mechanics: DiscreteMechanics,
    x0: np.ndarray,
    parameters: np.ndarray,
    nodes: np.ndarray | StepSchedule,
    outputs: np.ndarray | None = None,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """Step from x0 = [q; q_dot] over the ``nodes`` (a grid, or a StepSchedule whose outputs
    it names), keeping the ``outputs`` (indices into the grid), as
    :func:`lagrangian.simulation.variational.march.march` does.

    Raises SimulationError when numba is missing or the terms cannot be compiled (nothing
    has been integrated then); a failed step, or Ctrl-C, ends the march with the nodes
    computed before it.
    """
    march = _March(mechanics, x0, parameters, nodes, outputs)
    n, m = march.sizes
    halves = np.full((6, 2 * m + 1), np.nan)
    state = (*march.start[:2], march.start[2], np.zeros(m), *march.start[3:], np.zeros((2, n)))
    run = march.run("midpoint", (state,), (halves,), progress)
    if m == 0 or not len(run.outputs):
        return run
    last = int(march.cursor[NODE])
    multipliers = run.multipliers.copy()
    for end, first in ((0, True), (last, False)):
        multipliers[run.outputs == end] = end_multipliers(halves, last, first) if last else np.nan
    return run._replace(multipliers=multipliers)


def fast_collocation_march(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    x0: np.ndarray,
    parameters: np.ndarray,
    nodes: np.ndarray | StepSchedule,
    outputs: np.ndarray | None = None,
    progress: Callable[[float], None] | None = None,
) -> Run:
    """The march of :func:`lagrangian.simulation.variational.collocation_march.collocation_march`,
    compiled (arguments and errors as :func:`fast_march`)."""
    march = _March(mechanics, x0, parameters, nodes, outputs)
    m, s = march.sizes[1], tableau.stages
    stages = (
        np.tile(march.start[1], (s, 1)), np.zeros((s - 1 if m else 0, m)), np.zeros(1),
        np.zeros((HISTORY, s * march.sizes[0])), np.zeros(1, dtype=np.int64),
    )  # fmt: skip
    arrays = (tableau.a, tableau.a_hat, tableau.b, tableau.c)
    coefficients = (*(np.ascontiguousarray(a, dtype=float) for a in arrays), tableau.lobatto)
    return march.run("collocation", (coefficients, (*march.start, *stages)), (), progress)


class _March:
    """What both marches start from: the system's C functions, the nodes (a grid made in
    advance, or a StepSchedule made as the march goes), the output arrays and the state at
    the first node (q, v, p, h, A, dh/dt)."""

    def __init__(
        self,
        mechanics: DiscreteMechanics,
        x0: np.ndarray,
        parameters: np.ndarray,
        nodes: np.ndarray | StepSchedule,
        outputs: np.ndarray | None,
    ) -> None:
        self.native = native_mechanics(mechanics)  # owns the machine code while we run
        self.functions, self.data = system_arguments(self.native)
        self.linear = mechanics.legendre_linear
        n, m = len(mechanics.coordinates), mechanics.constraint_count
        self.sizes = n, m
        self.schedule, rows, self.steps = schedule_arrays(nodes, outputs)
        self.out = output_arrays(n, m, rows)
        self.p = np.ascontiguousarray(parameters, dtype=float)
        self.cursor = np.zeros(CURSOR, dtype=np.int64)
        self.cursor[NODE], self.cursor[EVALUATIONS] = -1, 1
        self.clock = np.full(5, np.nan)  # t_{k-2}, t_{k-1}, t_k, t_{k+1}, last union time
        t0 = float(self.schedule[0][0])
        q, v = (np.array(part, dtype=float) for part in (x0[:n], x0[n:]))  # updated in place
        momentum = np.array(mechanics.legendre(q, v, t0, self.p)[0], dtype=float)
        at_start = mechanics.constraints(q, t0, self.p)
        self.start = (q, v, momentum, *(np.ascontiguousarray(a, dtype=float) for a in at_start))

    def run(
        self,
        kind: str,
        arguments: tuple[object, ...],
        after: tuple[object, ...],
        progress: Callable[[float], None] | None,
    ) -> Run:
        """Run the compiled march ``kind`` in chunks; ``arguments`` are its own (after
        ``linear``, before the chunk's steps), ``after`` its own after ``out``."""
        march, cursor, clock, out = discrete_march(kind), self.cursor, self.clock, self.out
        fixed = (*self.functions, self.data, self.p, self.schedule, self.linear)

        def chunk(steps: int) -> int:
            return int(march(*fixed, *arguments, steps, cursor, clock, out, *after))

        status, interrupted = run_march(chunk, self.steps, lambda: float(clock[2]), progress)
        rows = int(np.count_nonzero(out[4] >= 0))
        reached = float(clock[2]) if cursor[NODE] >= 0 else float(self.schedule[0][0])
        return Run(
            outputs=out[4][:rows],
            t=out[5][:rows],
            q=out[0][:rows],
            q_dot=out[1][:rows],
            multipliers=out[3][:rows],
            constraint_residual=out[2][:rows],
            reached=reached,
            evaluations=int(cursor[EVALUATIONS]),
            failure=failure_message(status, clock),
            interrupted=interrupted,
        )


def schedule_arrays(
    nodes: np.ndarray | StepSchedule, outputs: np.ndarray | None
) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray, bool], int, int]:
    """The schedule of :mod:`lagrangian.numerics.fast.discrete_nodes` for a grid made in
    advance (with the output indices) or a StepSchedule, its number of output rows and of
    steps."""
    if isinstance(nodes, StepSchedule):
        every = nodes.t_out is None
        # with every node an output none is left out: the grid is the uniform one alone
        tolerance = -1.0 if every else nodes.tolerance
        span = np.array([nodes.t0, nodes.dt, nodes.t1, tolerance, nodes.count], dtype=float)
        wanted = np.zeros(0) if nodes.t_out is None else np.sort(nodes.t_out)
        return (span, wanted, wanted, every), nodes.rows, nodes.count + len(wanted)
    grid = np.ascontiguousarray(nodes, dtype=float)
    chosen = np.arange(len(grid)) if outputs is None else np.asarray(outputs)
    bounds = np.array([grid[0], 0.0, grid[-1], 0.0, -1.0])
    given = np.ascontiguousarray(grid[chosen], dtype=float)
    return (bounds, grid, given, False), len(chosen), len(grid) - 1


def failure_message(status: int, clock: np.ndarray) -> str | None:
    """The message of a march that stopped with ``status`` at the node of time clock[2], the
    next at clock[3] (None unless it failed), as the NumPy march words it."""
    t0, t1 = float(clock[2]), float(clock[3])
    messages = {
        POSITION_DIVERGED: lambda: not_converged("position", t0),
        POSITION_SINGULAR: lambda: singular("position"),
        VELOCITY_DIVERGED: lambda: not_converged("velocity", t1),
        VELOCITY_SINGULAR: lambda: singular("velocity"),
    }
    message = messages.get(status)
    return None if message is None else message()
