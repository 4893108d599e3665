"""The run setup: one simulation checked and ready, as a frozen value.

:func:`prepare` reads what simulate was given — the System (derived here) or its equations,
the initial values, time span, parameters, options and events — checks all of it at once
(the :class:`~lagrangian.simulation.options.Options`, the inputs, the conserved quantities:
every problem in one SimulationInputError) and returns the :class:`RunSetup` every
integrator starts from.

>>> import lagrangian as lg
>>> setup = prepare(lg.examples.simple_pendulum(), {"theta": 0.1}, 2.0, {"samples": 3})
>>> setup.inputs.t_out, setup.options.method
(array([0., 1., 2.]), 'RK45')
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from numbers import Integral, Real
from typing import Any, TypeVar

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion, derive
from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.fast import c_loop
from lagrangian.simulation.conserved import conserved_expressions
from lagrangian.simulation.gimbal import GimbalGuard, gimbal_guard
from lagrangian.simulation.inputs import Fallbacks, Inputs, checked_inputs
from lagrangian.simulation.integrators.events import EventFunction
from lagrangian.simulation.methods import DEFAULT_METHOD
from lagrangian.simulation.options import Options

T = TypeVar("T")


@dataclass(frozen=True)
class RunSetup:
    """Everything one simulation needs, checked: the System and its equations, their
    compiled functions, the options, the inputs (initial state, parameters, times), the
    events to watch (the caller's and the gimbal locks'), the conserved quantities to
    follow, and the guard against gimbal lock."""

    system: System
    eom: EquationsOfMotion
    compiled: CompiledEquations
    options: Options
    inputs: Inputs
    events: tuple[EventFunction, ...]
    quantities: Mapping[str, sp.Expr]
    guard: GimbalGuard


def prepare(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, float] | None,
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    *,
    parameters: Mapping[Any, float] | None = None,
    events: Sequence[EventFunction] = (),
    conserved: Mapping[str, Any] | None = None,
    progress: Any = None,
    ends_only: bool = False,
    **options: Any,
) -> RunSetup:
    """Check one simulate call and return its setup; SimulationInputError with every problem
    found.  ``stepping`` holds the :class:`~lagrangian.simulation.options.StepKeywords`
    given, ``options`` the other :class:`~lagrangian.simulation.options.Options` (backend,
    baumgarte, project_initial, project_steps); ``progress`` is only checked here;
    ``ends_only``: a sweep's default output times
    (:func:`~lagrangian.simulation.inputs.checked_inputs`)."""
    eom, system, fallbacks = describe_system(system_or_eom)
    compiled = compile_equations(eom)
    events, problems = callback_problems(events, progress)
    chosen = options_for(system, compiled, stepping, fallbacks, events=len(events), **options)
    checked = collect(problems, chosen)
    given = {"initial": initial, "parameters": parameters, "t_span": t_span, **stepping}
    inputs, found = checked_inputs(compiled, given, fallbacks, ends_only)
    problems.extend(found)
    quantities = collect(problems, lambda: conserved_expressions(eom, system, conserved or {}))
    raise_if_problems(problems, "Cannot simulate", SimulationInputError)
    assert checked is not None and quantities is not None  # no problems: both were made
    takes_events = checked.backend == "numpy" and checked.spec.takes_events
    guard = gimbal_guard(eom, system, inputs, takes_events)
    # the C loop's right-hand side evaluates M where the run will compile it anyway
    free_loop = checked.spec.compiled
    require_positive_inertia(
        compiled, inputs, eom if free_loop and not checked.constraints else None
    )
    return RunSetup(
        system, eom, compiled, checked, inputs, (*events, *guard.events), quantities, guard
    )


def callback_problems(
    events: Any, progress: Any
) -> tuple[tuple[EventFunction, ...], list[Problem]]:
    """The event functions of ``events`` and every problem with them and with ``progress``:
    ``events`` is a list of functions g(t, q, q_dot), each with an optional ``direction``
    (a number) and ``terminal`` (True, False or a count); ``progress`` is None or a
    function of the time reached."""
    problems = []
    if progress is not None and not callable(progress):
        fix = "pass a function of the time reached, or leave progress out"
        problems.append(Problem("progress", f"{progress!r:.60} is not a function", fix))
    if callable(events) or isinstance(events, (str, bytes)) or not isinstance(events, Iterable):
        fix = "pass a list of functions g(t, q, q_dot): events=[g]"
        problems.append(Problem("events", f"{events!r:.60} is not a list of functions", fix))
        return (), problems
    functions = tuple(events)
    for i, g in enumerate(functions):
        field = f"events[{i}]"
        if not callable(g):
            fix = "pass a function g(t, q, q_dot) whose zeros are the events"
            problems.append(Problem(field, f"{g!r:.60} is not a function", fix))
            continue
        direction = getattr(g, "direction", 0.0)
        if isinstance(direction, bool) or not isinstance(direction, Real):
            fix = "set g.direction to 1 (upward zeros), -1 (downward) or 0 (both)"
            problems.append(
                Problem(f"{field}.direction", f"{direction!r:.60} is not a number", fix)
            )
        terminal = getattr(g, "terminal", False)
        if not (isinstance(terminal, (bool, Integral)) and int(terminal) >= 0):
            fix = "set g.terminal to True (stop at the first zero), False, or a count"
            message = f"{terminal!r:.60} is not True, False or a count"
            problems.append(Problem(f"{field}.terminal", message, fix))
    return functions, problems


def require_positive_inertia(
    compiled: CompiledEquations, inputs: Inputs, eom: EquationsOfMotion | None = None
) -> None:
    """SimulationInputError when the mass matrix at the start has a negative eigenvalue: the
    kinetic energy is not positive there (a negative mass, inertia or inductance, often from
    ``--set m=-1``), and the motion would be unphysical.  Systems with first-order
    coordinates (circuits with resistors and capacitors only) are not checked.

    Given ``eom``, M is evaluated by the state equations compiled for the C loop where it
    runs (the right-hand side the run itself calls: no compilation of M alone)."""
    if not compiled.regular:
        return
    with np.errstate(all="ignore"):
        mass = _start_mass_matrix(compiled, inputs, eom)
    if not np.all(np.isfinite(mass)):
        return  # reported by the run itself, with the time and the quantity
    symmetric = (mass + mass.T) / 2
    diagonal = np.diagonal(symmetric)
    if np.all(diagonal > 0) and not np.any(symmetric - np.diag(diagonal)):
        return  # a diagonal M (a gas's 200 masses): its entries are its eigenvalues
    eigenvalues = np.linalg.eigvalsh(symmetric)
    if eigenvalues[0] < -1e-12 * max(1.0, float(np.max(np.abs(eigenvalues)))):
        values = ", ".join(f"{name}={value:g}" for name, value in inputs.parameters.items())
        raise SimulationInputError(
            f"The kinetic energy is negative for some velocities at the start: the mass matrix "
            f"has the eigenvalue {eigenvalues[0]:.6g} (parameters {values}). A mass, "
            "inertia or inductance is negative: give it a positive value."
        )


def _start_mass_matrix(
    compiled: CompiledEquations, inputs: Inputs, eom: EquationsOfMotion | None
) -> np.ndarray:
    """M at the initial state of a system whose coordinates are all of second order."""
    t0, x0, p = inputs.t_span[0], inputs.x0, inputs.p
    fast = c_loop.native_equations(eom) if eom is not None and c_loop.available() else None
    if fast is not None:
        return c_loop.state_matrix(fast, t0, x0, p)
    n = len(compiled.coordinates)
    return np.asarray(compiled.mass_matrix(x0[:n], t0, p, x0[n:]), dtype=float)


def options_for(
    system: System,
    compiled: CompiledEquations,
    stepping: Mapping[str, Any],
    fallbacks: Fallbacks,
    **options: Any,
) -> Callable[[], Options]:
    """The Options of a call, to be made (and checked) by the caller: the method given, else
    the System's, else the default; the step keywords given explicitly."""
    method = stepping.get("method") or fallbacks.settings.get("method") or DEFAULT_METHOD
    steering = ("rtol", "atol", "max_step", "dt", "max_steps", "max_wall_time")
    given = frozenset(k for k in steering if stepping.get(k) is not None)
    return lambda: Options(
        method=method,
        given=given,
        constraints=tuple(system.constraints),
        transitions=len(system.transitions),
        inertia=compiled.regular,
        **options,
    )


def collect(problems: list[Problem], make: Callable[[], T]) -> T | None:
    """``make()``, or None with its problems added to ``problems`` when it raises
    SimulationInputError (so that every problem is raised once, together)."""
    try:
        return make()
    except SimulationInputError as error:
        problems.extend(error.problems or [Problem("input", str(error))])
        return None


def describe_system(
    system_or_eom: System | EquationsOfMotion,
) -> tuple[EquationsOfMotion, System, Fallbacks]:
    """The equations, the System, and the initial values and simulation settings to fall
    back on: a System gives its own (derived once, :func:`lagrangian.derive`); equations of
    motion give none, and the System they were derived from."""
    if isinstance(system_or_eom, System):
        fallbacks = Fallbacks(system_or_eom.initial, system_or_eom.simulation)
        return derive(system_or_eom), system_or_eom, fallbacks
    if isinstance(system_or_eom, EquationsOfMotion):
        return system_or_eom, system_or_eom.system, Fallbacks()
    raise SimulationInputError(
        f"simulate needs a System or the EquationsOfMotion of one, not "
        f"{type(system_or_eom).__name__}."
    )
