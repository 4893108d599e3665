"""simulate_batch(system, initial, t_span) -> Batch: many initial conditions or parameter sets.

Each initial value and parameter is a number or an array of k values (one per member); all k
members are integrated in one call, each with its own adaptive steps, so member i equals
``simulate`` of member i alone.  A batch is its members times one engine, the first of the
method's engines (:mod:`lagrangian.simulation.methods`) that can run here: the C loop member
by member (:mod:`lagrangian.simulation.batch.native`), else the members stepped together in
NumPy (:mod:`lagrangian.simulation.batch.vectorized`), or for a constrained system
``simulate`` member by member (:mod:`lagrangian.simulation.batch.constrained`).  A stop
condition ``stop_when(t, q, q_dot)`` ends a member where it turns negative and records that
time (the flip time of a pendulum, a collision...).  A System with holonomic or velocity
constraints runs each member in the multiplier form, as ``simulate`` runs it, and the Batch
holds the multipliers and the constraint residual.

>>> import numpy as np, lagrangian as lg
>>> batch = simulate_batch(lg.examples.simple_pendulum(), {"theta": [0.1, 0.2]}, 1.0,
...                        parameters={"l": 2.0}, method="DOP853")
>>> batch.q.shape, batch.status
((2, 1000, 1), ('success', 'success'))
>>> float(batch.trajectory(1).q[0, 0])
0.2
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from lagrangian.constraints import ConstrainedEquations, constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.status import Status
from lagrangian.simulation.batch.constrained import (
    simulated_members,
    started_members,
)
from lagrangian.simulation.batch.inputs import BatchInputs, checked_batch
from lagrangian.simulation.batch.native import Members, native_constrained_members, native_members
from lagrangian.simulation.batch.result import Batch, ConstraintRows
from lagrangian.simulation.batch.vectorized import integrate_members
from lagrangian.simulation.integrators.compiled import loop_settings
from lagrangian.simulation.methods import method_named
from lagrangian.simulation.options import Options, StepKeywords, check_keywords
from lagrangian.simulation.progress_bar import progress_bar
from lagrangian.simulation.setup import collect, describe_system, options_for

if TYPE_CHECKING:
    from typing_extensions import Unpack

#: g(t, q, q_dot): a member stops where it turns negative.
StopCondition = Callable[[Any, Any, Any], Any]
#: (members, constraint rows, failure messages) of a batch engine.
Ran = tuple[Members, ConstraintRows | None, Sequence[str | None]]


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
        Output times shared by every member; neither: the System's own ``samples``, else
        1000 evenly spaced times (fewer when k members would hold more than 2**24 numbers;
        :func:`lagrangian.simulation.batch.inputs.default_times`).
    stop_when:
        g(t, q, q_dot); a member stops where g turns negative, its time located on the dense
        output (``Batch.stop_time``).  It is called with arrays t (m,), q and q_dot (m, n);
        in the C loop it runs compiled when it is an expression of the state (write it with
        ``q[..., j]``).
    baumgarte, project_initial:
        With constraints, as for :func:`lagrangian.simulation.simulate`: Baumgarte's
        (alpha, beta) (default off), and moving each member's start onto the constraints
        (else members that start off them are refused).  A constrained batch runs member by
        member in the C loop, else (no C compiler, a stop condition SymEngine cannot
        compile) ``simulate`` runs each member: slower, the same members.  Unilateral
        constraints are refused.
    backend:
        "numpy" (default); "numba" is another name of it for one release (the C loop
        replaced the numba loops) and is recorded in ``Batch.backend``.
    progress:
        True: a bar on standard error over time; or a callback taking the time.
    workers:
        Accepted for one release and without effect (it chose the numba loops' threads).

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
    bar = _bar(progress, *batch.inputs.t_span, "t = ")
    members, rows, failures = run_members(MemberRun(eom, compiled, batch, loops, stop_when, bar))
    return _result(compiled, batch, backend, *members, rows, failures)


@dataclass(frozen=True)
class MemberRun:
    """What every batch engine is given: the equations, their compiled form, the checked
    members, the loop settings, the stop condition and the progress callback."""

    eom: EquationsOfMotion
    compiled: CompiledEquations
    batch: BatchInputs
    settings: Settings
    stop_when: StopCondition | None = None
    progress: Callable[[float], None] | None = None

    @property
    def options(self) -> Options:
        assert self.batch.options is not None  # prepared_batch checked them
        return self.batch.options

    def constrained(self) -> ConstrainedEquations | None:
        """The multiplier form's equations of a constrained system (None without)."""
        constraints = self.options.constraints
        return constrained_equations(self.eom, constraints) if constraints else None


def run_members(run: MemberRun) -> Ran:
    """Every member by the first engine of the method (:mod:`lagrangian.simulation.methods`)
    that runs here: the C loop where there is a compiler and SymEngine compiles the
    equations (and the stop condition), else the vectorized NumPy engine, or for a
    constrained system ``simulate`` member by member.  Returns the members (out, status,
    t_final, x_final), the constraint rows (None without constraints) and each member's
    failure message (empty: the status says it)."""
    for engine in method_named(run.settings.method).engines:
        ran = _ENGINES[engine](run)
        if ran is not None:
            return ran
    raise AssertionError(f"no batch engine runs {run.settings.method}")  # options check it


def _in_c_loop(run: MemberRun) -> Ran | None:
    batch, equations = run.batch, run.constrained()
    if equations is None:
        members = native_members(
            run.eom, run.compiled, run.settings, batch.X0, batch.P, run.stop_when, run.progress
        )
        return None if members is None else (members, None, ())
    native = native_constrained_members(
        run.eom,
        equations,
        run.settings,
        batch.X0,
        batch.P,
        run.options.gains,
        run.stop_when,
        run.progress,
    )
    return None if native is None else (native[0], native[1], ())


def _vectorized(run: MemberRun) -> Ran | None:
    if run.options.constraints:  # the members' multiplier forms are not vectorized
        return None
    batch = run.batch
    members, messages = integrate_members(
        run.compiled, run.settings, batch.X0, batch.P, run.stop_when, run.progress
    )
    return members, None, messages


def _simulated(run: MemberRun) -> Ran | None:
    equations = run.constrained()
    if equations is None:  # a free system always has the vectorized engine
        return None
    return simulated_members(
        run.eom, equations, run.compiled, run.batch, run.options, run.stop_when, run.progress
    )


_ENGINES = {"c": _in_c_loop, "vectorized": _vectorized, "python": _simulated}


def prepared_batch(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, ArrayLike] | None,
    parameters: Mapping[Any, ArrayLike] | None,
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    backend: str,
    driver: str,
    ends_only: bool = False,
    **options: Any,
) -> tuple[EquationsOfMotion, CompiledEquations, BatchInputs]:
    """The equations, their compiled form and the checked members of a batch, without
    integrating; SimulationInputError lists every problem (``driver`` names the caller;
    ``ends_only``: a sweep's default output times, :func:`checked_batch`).
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
    batch, found = checked_batch(compiled, given, fallbacks, ends_only)
    problems += found
    if not problems and checked is not None and checked.constraints:
        equations = constrained_equations(eom, checked.constraints)
        X0, found = started_members(system, equations, compiled, batch, checked)
        problems += found
        batch = dataclasses.replace(batch, X0=X0)
    raise_if_problems(problems, f"Cannot run {driver}", SimulationInputError)
    return eom, compiled, dataclasses.replace(batch, options=checked)


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
    names = [Status(int(s)).outcome for s in status]
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


def _message(code: int, t: float) -> str:
    status = Status(code)
    if status == Status.FINISHED:
        return status.message
    if status == Status.STOPPED:
        return f"Stopped by stop_when at t = {t:.6g}."
    return f"Integration failed at t = {t:.6g}: {status.message}"
