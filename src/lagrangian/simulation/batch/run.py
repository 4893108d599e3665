"""simulate_batch(system, initial, t_span) -> Batch: many initial conditions or parameter sets.

Each initial value and parameter is a number or an array of k values (one per member); all k
members are integrated in one call, each with its own adaptive steps, so member i equals
``simulate`` of member i alone.  backend "numpy" vectorizes over the members
(:mod:`lagrangian.simulation.batch.vectorized`); "numba" runs each member through the compiled loop
(:mod:`lagrangian.numerics.fast`).  A stop condition ``stop_when(t, q, q_dot)`` ends a member
where it turns negative and records that time (the flip time of a pendulum, a collision...).
A System with holonomic or velocity constraints runs each member in the multiplier form, as
``simulate`` runs it, and the Batch holds the multipliers and the constraint residual
(:mod:`lagrangian.simulation.batch.constrained`).

>>> import numpy as np, lagrangian as lg
>>> batch = simulate_batch(lg.examples.simple_pendulum(), {"theta": [0.1, 0.2]}, 1.0,
...                        parameters={"l": 2.0}, method="DOP853")
>>> batch.q.shape, batch.status
((2, 2, 1), ('success', 'success'))
>>> float(batch.trajectory(1).q[0, 0])
0.2
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from lagrangian.constraints import constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.fast.outcome import FINISHED, STOPPED, describe
from lagrangian.numerics.fast.settings import Settings
from lagrangian.simulation.batch.constrained import (
    simulated_members,
    started_members,
)
from lagrangian.simulation.batch.inputs import BatchInputs, checked_batch
from lagrangian.simulation.batch.native import native_constrained_members, native_members
from lagrangian.simulation.batch.result import Batch, ConstraintRows
from lagrangian.simulation.batch.vectorized import integrate_members
from lagrangian.simulation.integrators.compiled import loop_settings
from lagrangian.simulation.options import Options, StepKeywords, check_keywords
from lagrangian.simulation.progress_bar import progress_bar
from lagrangian.simulation.setup import collect, describe_system, options_for

if TYPE_CHECKING:
    from typing_extensions import Unpack

#: g(t, q, q_dot): a member stops where it turns negative.
StopCondition = Callable[[Any, Any, Any], Any]


def simulate_batch(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, ArrayLike] | None = None,
    t_span: float | tuple[float, float] | None = None,
    *,
    parameters: Mapping[Any, ArrayLike] | None = None,
    stop_when: StopCondition | None = None,
    baumgarte: tuple[float, float] | None = None,
    project_initial: bool = False,
    backend: str = "numpy",
    progress: bool | Callable[[float], None] = False,
    workers: int = 1,
    **stepping: Unpack[StepKeywords],
) -> Batch:
    """Integrate k members at once: initial values and parameters given as numbers or arrays.

    Parameters
    ----------
    initial, parameters:
        By name or symbol, each a number (every member) or an array of k values; arrays of
        different lengths are refused.  Unlisted values come from the System and defaults.
    t_span, method, rtol, atol, dt, max_step:
        As for :func:`lagrangian.simulation.simulate`; methods RK45, DOP853 and RK4.
    samples, t_eval:
        Output times shared by every member; neither: the initial and final times only.
    stop_when:
        g(t, q, q_dot); a member stops where g turns negative, its time located on the dense
        output (``Batch.stop_time``).  backend "numpy" calls it with arrays t (m,), q and
        q_dot (m, n) of the running members, "numba" compiles it and calls it per member
        with a float t and 1-d q, q_dot: write it with ``q[..., j]`` to serve both.
    baumgarte, project_initial:
        With constraints, as for :func:`lagrangian.simulation.simulate`: Baumgarte's
        (alpha, beta) (default off), and moving each member's start onto the constraints
        (else members that start off them are refused).  A constrained batch runs RK45 and
        DOP853 member by member in the C loop, else (no C compiler, RK4, a stop condition
        SymEngine cannot compile) ``simulate`` runs each member: slower, the same members.
        Unilateral constraints are refused.
    backend:
        "numpy" (default) or "numba" (``pip install lagrangian[fast]``; no constraints).
    progress:
        True: a bar on standard error (over time for numpy, over members for numba); or a
        callback taking the time (numpy) or the number of members done (numba).
    workers:
        numba only: threads running chunks of members at once.

    Raises
    ------
    SimulationInputError
        Bad input, every problem listed, naming the field (members that start off the
        constraints by index).
    """
    eom, compiled, batch = prepared_batch(
        system_or_eom,
        initial,
        parameters,
        t_span,
        stepping,
        backend,
        "simulate_batch",
        baumgarte=baumgarte,
        project_initial=project_initial,
    )
    loops = loop_settings(batch.inputs, batch.t_out)
    if batch.options is not None and batch.options.constraints:
        bar = _bar(progress, *batch.inputs.t_span, "t = ")
        return _constrained(eom, compiled, batch, batch.options, loops, stop_when, bar)
    if backend == "numba":
        out, status, t_final, x_final = _numba_members(
            eom, batch, loops, stop_when, progress, workers
        )
    else:
        bar = _bar(progress, *batch.inputs.t_span, "t = ")
        # RK45 and DOP853 member by member in the C loop where it can run, else vectorized
        members = native_members(eom, compiled, loops, batch.X0, batch.P, stop_when, bar)
        if members is None:
            members = integrate_members(compiled, loops, batch.X0, batch.P, stop_when, bar)
        out, status, t_final, x_final = members
    return _result(compiled, batch, backend, out, status, t_final, x_final)


def prepared_batch(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, ArrayLike] | None,
    parameters: Mapping[Any, ArrayLike] | None,
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    backend: str,
    driver: str,
    **options: Any,
) -> tuple[EquationsOfMotion, CompiledEquations, BatchInputs]:
    """The equations, their compiled form and the checked members of a batch, without
    integrating; SimulationInputError lists every problem (``driver`` names the caller).
    ``options``: baumgarte and project_initial (checked as simulate checks them, the
    members of a constrained system started on the constraints)."""
    check_keywords(stepping, driver)
    eom, system, fallbacks = describe_system(system_or_eom)
    compiled = compile_equations(eom)
    problems: list[Problem] = []
    chosen = options_for(
        system, compiled, stepping, fallbacks, backend=backend, driver="simulate_batch", **options
    )
    checked = collect(problems, chosen)
    given = {"initial": initial, "parameters": parameters, "t_span": t_span, **stepping}
    batch, found = checked_batch(compiled, given, fallbacks)
    problems += found
    if not problems and checked is not None and checked.constraints:
        equations = constrained_equations(eom, checked.constraints)
        X0, found = started_members(system, equations, compiled, batch, checked)
        problems += found
        batch = dataclasses.replace(batch, X0=X0)
    raise_if_problems(problems, f"Cannot run {driver}", SimulationInputError)
    return eom, compiled, dataclasses.replace(batch, options=checked)


def _constrained(
    eom: EquationsOfMotion,
    compiled: CompiledEquations,
    batch: BatchInputs,
    options: Options,
    settings: Settings,
    stop_when: StopCondition | None,
    progress: Callable[[float], None] | None,
) -> Batch:
    """A batch of a constrained system: in the C loop, else member by member through
    simulate (:mod:`lagrangian.simulation.batch.constrained`)."""
    equations = constrained_equations(eom, options.constraints)
    gains = options.gains
    native = native_constrained_members(
        eom, equations, settings, batch.X0, batch.P, gains, stop_when, progress
    )
    if native is not None:
        (out, status, t_final, x_final), rows = native
        return _result(compiled, batch, "numpy", out, status, t_final, x_final, rows)
    members, rows, messages = simulated_members(
        eom, equations, compiled, batch, options, stop_when, progress
    )
    return _result(compiled, batch, "numpy", *members, rows, messages)


def _numba_members(
    eom: EquationsOfMotion,
    batch: BatchInputs,
    settings: Settings,
    stop_when: StopCondition | None,
    progress: bool | Callable[[float], None],
    workers: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    from lagrangian.numerics.fast import fast_equations
    from lagrangian.numerics.fast.run import integrate_batch

    bar = _bar(progress, 0, batch.size, "members ")
    run = integrate_batch(fast_equations(eom), settings, batch.X0, batch.P, stop_when, bar, workers)
    return run.x, run.status, run.t_final, run.x_final


def _bar(
    progress: bool | Callable[[float], None], start: float, end: float, label: str
) -> Callable[[float], None] | None:
    if callable(progress):
        return progress
    return progress_bar(start, end, force=True, label=label) if progress else None


def _result(
    compiled: CompiledEquations,
    batch: BatchInputs,
    backend: str,
    out: np.ndarray,
    status: np.ndarray,
    t_final: np.ndarray,
    x_final: np.ndarray,
    constraints: ConstraintRows | None = None,
    failures: Sequence[str | None] = (),
) -> Batch:
    """The Batch value: velocities and energies of every output row, statuses and messages
    (``failures``: a member's own message where it failed), the constraint rows."""
    k, n = batch.size, len(compiled.coordinates)
    T = len(batch.t_out)
    states = out.reshape(k * T, -1)
    times = np.tile(batch.t_out, k)
    P = np.repeat(batch.P, T, axis=0)
    q, q_dot = _velocities(compiled, times, states, P, n)
    final_q, final_q_dot = _velocities(compiled, t_final, x_final, batch.P, n)
    energy = compiled.energy(q, q_dot, times, P) if k * T else np.zeros(0)
    words = {FINISHED: "success", STOPPED: "stopped"}
    names = [words.get(int(s), "failed") for s in status]
    given = list(failures) + [None] * (len(status) - len(failures))
    messages = [m or _message(int(s), float(t)) for m, s, t in zip(given, status, t_final)]
    columns = {}
    if constraints is not None:  # the fields of ConstraintRows are Batch's of the same names
        columns = {f.name: getattr(constraints, f.name) for f in dataclasses.fields(constraints)}
    inputs = batch.inputs
    return Batch(
        t=batch.t_out,
        q=q.reshape(k, T, n),
        q_dot=q_dot.reshape(k, T, n),
        energy=np.asarray(energy, dtype=float).reshape(k, T),
        coordinates=compiled.coordinates,
        status=tuple(names),
        message=tuple(messages),
        final_t=t_final,
        final_q=final_q,
        final_q_dot=final_q_dot,
        final_energy=np.asarray(compiled.energy(final_q, final_q_dot, t_final, batch.P)),
        initial={name: batch.X0[:, j] for j, name in enumerate(compiled.state_names)},
        parameters={name: batch.P[:, j] for j, name in enumerate(compiled.parameters)},
        method=inputs.method,
        backend=backend,
        **columns,
    )


def _velocities(
    compiled: CompiledEquations, t: np.ndarray, x: np.ndarray, p: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray]:
    """q and every q_dot of states x (NaN rows stay NaN)."""
    q_dot = np.full((len(x), n), np.nan)
    rows = np.all(np.isfinite(x), axis=1)
    if np.any(rows):
        q_dot[rows] = compiled.velocities(t[rows], x[rows], p[rows])
    return x[:, :n], q_dot


def _message(status: int, t: float) -> str:
    if status == FINISHED:
        return describe(FINISHED)
    if status == STOPPED:
        return f"Stopped by stop_when at t = {t:.6g}."
    return f"Integration failed at t = {t:.6g}: {describe(status)}"
