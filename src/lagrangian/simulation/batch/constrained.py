"""Batches of constrained systems: every member in the multiplier form, as simulate runs it.

A System with holonomic or velocity constraints integrates, member by member, the
multiplier form with Baumgarte's gains (``baumgarte``, default off), as a single
:func:`lagrangian.simulate` integrates it:

* in the C loop (:func:`lagrangian.simulation.batch.native.native_constrained_members`)
  for RK45 and DOP853 where it runs, with a stop condition that is an expression of the
  state compiled beside the equations;
* else (no C compiler, method RK4, a stop condition SymEngine cannot compile) through
  :func:`lagrangian.simulate` itself, one call per member: slower, the same members
  (:func:`simulated_members`).

Either way the Batch holds the multipliers lambda_j and the constraint residual of every
output row and final state, and ``Batch.trajectory(i)`` is the Trajectory of ``simulate``
of member i alone (its multiplier and residual columns included).  A member that fails on
the second path keeps ``simulate``'s message (where and why), and ends at its last output
row rather than its last step.

Every member starts as ``simulate`` starts it (:func:`started_members`): within
``INITIAL_TOLERANCE`` of the constraints, or moved onto them with ``project_initial``; the
members that start off them are refused together, by index.  What only a single simulation
does is refused by name (``simulation/options.py``): unilateral constraints (active
sets), the methods of SciPy's other solvers and the variational integrators.

>>> import numpy as np, sympy as sp, lagrangian as lg
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)],
...     particles=[lg.Particle("bead", 1, (x, y))])
>>> batch = lg.simulate_batch(ring, {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": [1.0, 2.0]},
...                           1.0)
>>> batch.multiplier_names, np.round(batch.multipliers[:, 0, 0], 6)  # -m v^2 / (2 r^2)
(('lambda_1',), array([-0.5, -2. ]))
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from lagrangian.constraints import ConstrainedEquations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Fix, LagrangianError, Problem, Setting, SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.constrained import compile_constrained
from lagrangian.numerics.status import Outcome, Status
from lagrangian.simulation.batch.inputs import BatchInputs
from lagrangian.simulation.batch.native import Members
from lagrangian.simulation.batch.result import ConstraintRows
from lagrangian.simulation.batch.stop import STOP_EVENT, negative_at_start, stop_event
from lagrangian.simulation.dynamics import INITIAL_TOLERANCE, MultiplierDynamics
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.options import Options
from lagrangian.simulation.run import simulate
from lagrangian.simulation.trajectory import Trajectory

#: Members named in a message about the members that start off the constraints.
NAMED = 8


def member_inputs(compiled: CompiledEquations, batch: BatchInputs, i: int) -> Inputs:
    """The Inputs of member i alone (its initial state and parameters)."""
    p = batch.P[i]
    parameters = dict(zip(compiled.parameters, p.tolist()))
    return dataclasses.replace(batch.inputs, x0=batch.X0[i].copy(), p=p, parameters=parameters)


def started_members(
    system: System,
    equations: ConstrainedEquations,
    compiled: CompiledEquations,
    batch: BatchInputs,
    options: Options,
) -> tuple[np.ndarray, list[Problem]]:
    """The initial states of the members, each on the constraints as ``simulate`` starts it
    (moved onto them with ``project_initial``), and the problem of those that are not."""
    form = compile_constrained(equations)
    X0, n, t0 = batch.X0.copy(), len(compiled.coordinates), batch.inputs.t_span[0]
    off: list[tuple[int, float]] = []
    failed: list[tuple[int, str]] = []
    for i in range(batch.size):
        inputs = member_inputs(compiled, batch, i)
        dynamics = MultiplierDynamics(system, form, inputs.p, options.gains)
        residual = dynamics.residual(t0, X0[i, :n], X0[i, n:])
        if residual <= INITIAL_TOLERANCE:  # False for NaN, as simulate decides
            continue
        if not options.project_initial:
            off.append((i, residual))
            continue
        try:
            X0[i] = dynamics.start(inputs, True).x0
        except LagrangianError as error:
            failed.append((i, str(error)))
    problems = []
    if off:
        members = _named([i for i, _ in off])
        largest = max((r for _, r in off), key=lambda r: math.inf if math.isnan(r) else r)
        message = (
            f"{members} start off the constraints: the largest residual is {largest:.3g} "
            f"(> {INITIAL_TOLERANCE:g})"
        )
        fix = Fix("move them onto the constraints: pass {}", (Setting("project_initial", True),))
        problems.append(Problem("initial", message, fix))
    for i, reason in failed[:NAMED]:
        problems.append(Problem("initial", f"member {i} cannot be moved onto them: {reason}"))
    return X0, problems


def _named(indices: list[int]) -> str:
    shown = ", ".join(str(i) for i in indices[:NAMED])
    more = f" and {len(indices) - NAMED} more" if len(indices) > NAMED else ""
    return f"member{'s' if len(indices) > 1 else ''} {shown}{more}"


def simulated_members(
    eom: EquationsOfMotion,
    equations: ConstrainedEquations,
    compiled: CompiledEquations,
    batch: BatchInputs,
    options: Options,
    stop_when: Callable[..., Any] | None = None,
    progress: Callable[[float], None] | None = None,
) -> tuple[Members, ConstraintRows, list[str | None]]:
    """Every member through :func:`lagrangian.simulate`: the batch's rows, the constraint
    rows, and the message of each member that failed (None for the others).  A member
    whose stop condition is negative at the start stops there, as in the C loop."""
    k, n, T = batch.size, len(compiled.coordinates), len(batch.t_out)
    t0, t1 = batch.inputs.t_span
    form = compile_constrained(equations)
    names = form.multipliers
    out = np.full((k, T, 2 * n), np.nan)
    status, t_final, x_final = np.full(k, Status.FINISHED), np.full(k, float(t1)), batch.X0.copy()
    rows = ConstraintRows(
        names,
        np.full((k, T, len(names)), np.nan),
        np.full((k, T), np.nan),
        np.full((k, len(names)), np.nan),
        np.full(k, np.nan),
    )
    messages: list[str | None] = [None] * k
    for i in range(k):
        inputs = member_inputs(compiled, batch, i)
        if stop_when is not None and negative_at_start(stop_when, t0, inputs.x0[:n], inputs.x0[n:]):
            first = int(np.searchsorted(batch.t_out, t0, side="right"))
            out[i, :first] = inputs.x0
            status[i], t_final[i] = Status.STOPPED, t0  # as the C loop: stopped at the start
            dynamics = MultiplierDynamics(eom.system, form, inputs.p, options.gains)
            _start_rows(dynamics, t0, inputs.x0, rows, i, first)
        else:
            member = _simulate(eom, compiled, inputs, batch.t_out, options, stop_when)
            status[i], messages[i] = _member(member, batch.t_out, i, out, t_final, x_final, rows)
            if isinstance(member, str):
                t_final[i] = t0
        if progress is not None:
            progress(t1 if i == k - 1 else t0 + (t1 - t0) * (i + 1) / k)
    return (out, status, t_final, x_final), rows, messages


def _start_rows(
    dynamics: MultiplierDynamics,
    t0: float,
    x0: np.ndarray,
    rows: ConstraintRows,
    i: int,
    first: int,
) -> None:
    """Member i's multipliers and residual at its start, in its first ``first`` rows and as
    its final values (a member stopped at the start)."""
    n = len(x0) // 2
    lam, residual = dynamics.constraint_rows(np.array([t0]), x0[None, :n], x0[None, n:])
    rows.multipliers[i, :first], rows.constraint_residual[i, :first] = lam, residual
    rows.final_multipliers[i], rows.final_constraint_residual[i] = lam[0], residual[0]


def _simulate(
    eom: EquationsOfMotion,
    compiled: CompiledEquations,
    inputs: Inputs,
    t_out: np.ndarray,
    options: Options,
    stop_when: Callable[..., Any] | None,
) -> Trajectory | str:
    """``simulate`` of one member (its start checked already), or why it cannot run."""
    stepping: dict[str, Any] = {"max_steps": inputs.max_steps}
    if inputs.max_wall_time is not None:
        stepping["max_wall_time"] = inputs.max_wall_time
    if options.spec.takes_tolerances:
        stepping.update(rtol=inputs.rtol, atol=inputs.atol)
        if math.isfinite(inputs.max_step):
            stepping["max_step"] = inputs.max_step
    else:
        stepping["dt"] = inputs.dt
    try:
        member = simulate(
            eom,
            dict(zip(compiled.state_names, inputs.x0.tolist())),
            inputs.t_span,
            parameters=inputs.parameters,
            events=() if stop_when is None else (stop_event(stop_when),),
            raise_on_failure=False,
            baumgarte=options.baumgarte,
            method=inputs.method,
            t_eval=t_out,
            **stepping,
        )
    except SimulationInputError as error:  # this member's values (member 0 was checked)
        return f"Cannot simulate this member: {error}"
    if member.status == Outcome.INTERRUPTED:
        raise KeyboardInterrupt  # as the other batches: Ctrl-C ends the whole batch
    return member


def _member(
    member: Trajectory | str,
    t_out: np.ndarray,
    i: int,
    out: np.ndarray,
    t_final: np.ndarray,
    x_final: np.ndarray,
    rows: ConstraintRows,
) -> tuple[int, str | None]:
    """Member i's rows of ``member`` put in the batch's arrays; its status and, where it
    failed, its message."""
    if isinstance(member, str):
        return Status.FAILED, member
    assert member.multipliers is not None and member.constraint_residual is not None
    x = np.hstack((member.q, member.q_dot))
    common = min(len(member.t), len(t_out))
    same = member.t[:common] == t_out[:common]
    r = common if np.all(same) else int(np.argmin(same))  # the output rows (not the stop)
    out[i, :r] = x[:r]
    rows.multipliers[i, :r] = member.multipliers[:r]
    rows.constraint_residual[i, :r] = member.constraint_residual[:r]
    if len(member.t):
        t_final[i], x_final[i] = member.t[-1], x[-1]
        rows.final_multipliers[i] = member.multipliers[-1]
        rows.final_constraint_residual[i] = member.constraint_residual[-1]
    if member.status != Outcome.SUCCESS:
        return Status.FAILED, member.message
    stopped = any(event.name == STOP_EVENT for event in member.events)
    return (Status.STOPPED if stopped else Status.FINISHED), None
