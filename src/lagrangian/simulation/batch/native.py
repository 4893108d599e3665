"""A batch in the C loop: member after member through the library compiled once per machine.

Batches of the C loop's methods (RK45, DOP853, RK4) run every member in the C loop
(:mod:`lagrangian.numerics.fast.c_loop`) with the one right-hand side compiled by SymEngine's
LLVM backend and the member's own parameters, so member i is ``simulate`` of member i alone
(SciPy's steps), as in the NumPy batch (:mod:`lagrangian.simulation.batch.vectorized`), whose
results this returns in the same shape.  A stop condition g(t, q, q_dot) runs in the loop as
a terminal event of falling zeros when it is an expression of the state
(:mod:`lagrangian.simulation.integrators.event_trace`; a sweep's text condition carries its
expression),
its zero located on the dense output; a member whose g is negative at the start stops there.

A constrained system runs the same way in its multiplier form with Baumgarte's gains
(:func:`native_constrained_members`, :mod:`lagrangian.numerics.fast.c_constrained`, as a
single ``simulate`` runs it), the multipliers and residuals of every output row computed
after the runs, all members at once.

Where the loop cannot run (no C compiler, equations or a condition SymEngine cannot
compile) both are None: the NumPy batch runs instead, or for a constrained system
``simulate`` member by member (:mod:`lagrangian.simulation.batch.constrained`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.c_constrained import (
    NativeConstrained,
    constraint_rows,
    native_constrained,
)
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.status import Status
from lagrangian.simulation.batch.result import ConstraintRows
from lagrangian.simulation.integrators.event_trace import traced_events

#: (out (members, times, state), status, t_final, x_final), as the NumPy batch returns them.
Members = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def native_members(
    eom: EquationsOfMotion,
    compiled: CompiledEquations,
    settings: Settings,
    X0: np.ndarray,
    P: np.ndarray,
    stop_when: Callable[..., Any] | None = None,
    progress: Callable[[float], None] | None = None,
) -> Members | None:
    """Integrate every row of X0 (parameters: the same row of P) in the C loop (module
    docstring), or None where it cannot.  ``progress`` gets, after each member, the time
    span's share of the members done (t0 + (t1 - t0) (i + 1) / k)."""
    if not c_loop.available():
        return None
    fast = c_loop.native_equations(eom)
    if fast is None:
        return None
    n = len(compiled.coordinates)

    def velocities(t: float, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.asarray(compiled.rhs(t, x, p)[:n], dtype=float)

    runs = _runs(eom, settings, stop_when, velocities, progress, X0, P)
    return None if runs is None else runs.members(fast, X0, P)


def native_constrained_members(
    eom: EquationsOfMotion,
    equations: ConstrainedEquations,
    settings: Settings,
    X0: np.ndarray,
    P: np.ndarray,
    gains: tuple[float, float],
    stop_when: Callable[..., Any] | None = None,
    progress: Callable[[float], None] | None = None,
) -> tuple[Members, ConstraintRows] | None:
    """Every member of a constrained system in the multiplier form with Baumgarte's
    ``gains`` (alpha, beta) in the C loop, with the multipliers and residuals of its output
    rows and final state; None where the loop cannot run (as :func:`native_members`)."""
    if not c_loop.available():
        return None
    form = native_constrained(equations)
    if form is None:
        return None
    n = len(equations.coordinates)

    def velocities(t: float, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return x[n:]  # the state of the multiplier form is [q; q_dot]

    runs = _runs(eom, settings, stop_when, velocities, progress, X0, P)
    if runs is None:
        return None
    # the gains are the last two parameters of the multiplier form (c_constrained.py)
    P_loop = np.column_stack((P, np.broadcast_to(np.asarray(gains, dtype=float), (len(P), 2))))
    members = runs.members(form.equations, X0, P_loop)
    names = tuple(s.name for s in equations.multipliers)
    return members, _constraint_rows(form, names, settings.t_out, members, P_loop)


def _constraint_rows(
    form: NativeConstrained,
    names: tuple[str, ...],
    t_out: np.ndarray,
    members: Members,
    P: np.ndarray,
) -> ConstraintRows:
    """The multipliers and residuals of every member's output rows (NaN where it has none)
    and final state, each computed by one call on the rows of every member."""
    out, _, t_final, x_final = members
    k, T, _ = out.shape
    multipliers, residual = np.full((k, T, len(names)), np.nan), np.full((k, T), np.nan)
    rows = np.all(np.isfinite(out), axis=2)
    member, row = np.nonzero(rows)
    multipliers[rows], residual[rows] = constraint_rows(form, t_out[row], out[rows], P[member])
    final_multipliers, final_residual = constraint_rows(form, t_final, x_final, P)
    return ConstraintRows(names, multipliers, residual, final_multipliers, final_residual)


@dataclass(frozen=True)
class _Runs:
    """How every member runs: the settings, the stop condition (``events``: compiled for the
    loop), q_dot of a state (``velocities(t, x, p)``, for the condition at the start) and the
    progress callback."""

    settings: Settings
    stop_when: Callable[..., Any] | None
    velocities: Callable[[float, np.ndarray, np.ndarray], np.ndarray]
    progress: Callable[[float], None] | None
    events: c_loop.LoopEvents | None = None

    def members(self, fast: Any, X0: np.ndarray, P: np.ndarray) -> Members:
        """Every row of X0 (parameters: the row of P) in the C loop, one after the other."""
        settings, progress = self.settings, self.progress
        k, nx = X0.shape
        t0, t1 = settings.span
        out = np.full((k, len(settings.t_out), nx), np.nan)
        status = np.zeros(k, dtype=np.int64)
        t_final, x_final = np.full(k, float(t1)), X0.astype(float).copy()
        limits = c_loop.Limits(max_steps=settings.max_steps)
        for i in range(k):
            g0 = math.inf if self.stop_when is None else self.condition(t0, X0[i], P[i])
            if not g0 >= 0 and not math.isnan(g0):
                first = int(np.searchsorted(settings.t_out, t0, side="right"))
                out[i, :first] = X0[i]
                status[i], t_final[i] = Status.STOPPED, t0  # negative at the start: stopped there
            else:
                run = c_loop.integrate(fast, settings, X0[i], P[i], limits, None, self.events)
                if run.interrupted:
                    raise KeyboardInterrupt  # as the NumPy batch: Ctrl-C ends the whole batch
                out[i, : len(run.t)] = run.x
                status[i] = run.status
                if run.status == Status.STOPPED and run.events:
                    t_final[i], x_final[i] = run.events[-1][1], run.events[-1][2]
                else:
                    t_final[i], x_final[i] = run.t_reached, run.x_reached
            if progress is not None:
                progress(t1 if i == k - 1 else t0 + (t1 - t0) * (i + 1) / k)
        return out, status, t_final, x_final

    def condition(self, t: float, x: np.ndarray, p: np.ndarray) -> float:
        """g of one member, called as the NumPy batch calls it (arrays of one member); NaN
        where the right-hand side is singular there (the loop then ends the member
        SINGULAR)."""
        assert self.stop_when is not None
        try:
            q_dot = self.velocities(t, x, p)
        except (SimulationError, np.linalg.LinAlgError):
            return math.nan
        q = x[: len(q_dot)]
        values = np.asarray(self.stop_when(np.array([t]), q[None, :], q_dot[None, :]), float)
        return float(values.reshape(-1)[0])


def _runs(
    eom: EquationsOfMotion,
    settings: Settings,
    stop_when: Callable[..., Any] | None,
    velocities: Callable[[float, np.ndarray, np.ndarray], np.ndarray],
    progress: Callable[[float], None] | None,
    X0: np.ndarray,
    P: np.ndarray,
) -> _Runs | None:
    """How the members run, ``stop_when`` compiled as the loop's terminal event of falling
    zeros; None where it is not an expression SymEngine compiles."""
    if stop_when is None:
        return _Runs(settings, None, velocities, progress)
    condition = _condition(eom, stop_when, velocities, settings.span[0], X0, P)
    function = None if condition is None else c_loop.loop_function(eom, [condition])
    if function is None:
        return None
    events = c_loop.LoopEvents(function, np.array([-1.0]), np.array([1.0]))
    return _Runs(settings, stop_when, velocities, progress, events)


def _condition(
    eom: EquationsOfMotion,
    stop_when: Callable[..., Any],
    velocities: Callable[[float, np.ndarray, np.ndarray], np.ndarray],
    t0: float,
    X0: np.ndarray,
    P: np.ndarray,
) -> sp.Expr | None:
    """The expression of ``stop_when``: its own ``expression`` (a sweep's text condition,
    in the names of t, the coordinates and NAME_dot), else traced; checked against the
    function at the first member's start (and a state near it)."""
    n = len(eom.coordinates)
    state = c_loop.state_symbols(eom)[: 1 + X0.shape[1]]

    def unpack(t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[:n], velocities(t, x, P[0])

    def member(t: float, q: np.ndarray, q_dot: np.ndarray) -> Any:
        if isinstance(q, np.ndarray) and q.dtype != object:  # numbers: as the batch calls it
            return np.asarray(stop_when(np.array([t]), q[None, :], q_dot[None, :])).reshape(-1)[0]
        return stop_when(t, q, q_dot)

    given = getattr(stop_when, "expression", None)
    if isinstance(given, sp.Expr):
        names = {s.name: s for s in (eom.time, *eom.coordinates, *eom.velocities)}
        renamed = given.xreplace({s: names.get(s.name, s) for s in given.free_symbols})

        def symbolic(t: Any, q: Any, q_dot: Any) -> Any:
            if isinstance(q, np.ndarray) and q.dtype == object:
                return renamed
            return member(t, q, q_dot)

        traced = traced_events(eom, [symbolic], state, t0, X0[0], unpack)
    else:
        traced = traced_events(eom, [member], state, t0, X0[0], unpack)
    return None if traced is None else traced[0]
