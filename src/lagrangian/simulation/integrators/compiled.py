"""The whole integration in one compiled call: the C loop of the explicit Runge–Kutta methods.

RK45, DOP853 and RK4 (the methods whose engines include ``"c"`` in
:mod:`lagrangian.simulation.methods`) run on a free system, or on the multiplier form of a
constrained one (Baumgarte's gains; not ``project_steps``), in the C loop compiled once per
machine (:mod:`lagrangian.numerics.fast.c_loop`, :class:`NativeIntegrator`): SciPy's steps
(RK4: those of :mod:`lagrangian.simulation.integrators.rk4`), the right-hand side compiled by
SymEngine's LLVM backend, the budget of :mod:`lagrangian.simulation.integrators.budget` checked
after every step with the same messages, a progress callback after every step and Ctrl-C
keeping the rows so far.  Event functions that are expressions of the state
(:mod:`lagrangian.simulation.integrators.event_trace`) are compiled beside the right-hand side
and their zeros located in the loop, as SciPy's path locates them
(:mod:`lagrangian.simulation.integrators.events`).  Where there is no C compiler, SymEngine
cannot compile the equations, or an event function is not an expression it can compile,
:func:`native_integrator` is None and the Python loop over SciPy's solvers runs instead.
``backend="numba"`` runs here too (another name of the default for one release).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lagrangian.constraints import ConstrainedEquations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Fix, SimulationError
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.c_constrained import (
    NativeConstrained,
    constraint_rows,
    native_constrained,
)
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.status import Status
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import (
    COLLAPSE,
    COLLAPSE_STEPS,
    NEAR,
    SHARE,
    STABILITY_EDGE,
    STIFF_STEPS_LEFT,
    WINDOW,
    Budget,
    collapse_message,
    step_budget_message,
    stiffness_message,
    wall_time_message,
)
from lagrangian.simulation.integrators.event_trace import traced_events
from lagrangian.simulation.integrators.events import EventFunction, EventWatch, Unpack
from lagrangian.simulation.integrators.protocol import Dynamics, Integration, Progress
from lagrangian.simulation.methods import runs_in
from lagrangian.simulation.options import Options


def native_integrator(
    eom: EquationsOfMotion,
    options: Options,
    events: Sequence[EventFunction],
    inputs: Inputs,
    unpack: Unpack,
    constrained: ConstrainedEquations | None = None,
) -> NativeIntegrator | None:
    """The C loop's integrator for a run that it can take, or None (SciPy's solvers take
    those): a method the C loop runs (RK45, DOP853, RK4) of the free equations of ``eom`` or, given
    ``constrained``, of their multiplier form with Baumgarte's gains (not ``project_steps``,
    not unilateral constraints), with events that are expressions of the state; None also
    without a C compiler, or where SymEngine's LLVM backend cannot compile the equations or
    the events.  ``inputs`` and ``unpack`` (q and q_dot at (t, x)) check the events'
    expressions against the functions at the start."""
    if not runs_in(options.method, "c") or not c_loop.available():
        return None
    if constrained is None and options.constraints:
        return None
    if constrained is not None and (options.project_steps or options.unilateral):
        return None
    multiplier_form = None if constrained is None else native_constrained(constrained)
    if constrained is None:
        fast = c_loop.native_equations(eom)
    else:
        fast = None if multiplier_form is None else multiplier_form.equations
    if fast is None:
        return None
    gains = () if constrained is None else tuple(float(g) for g in options.gains)
    if not events:
        return NativeIntegrator(fast, None, gains, multiplier_form)
    # the state x: every velocity in the multiplier form, those of order 2 in the free form
    state = c_loop.state_symbols(eom)[: 1 + len(fast.state_names)]
    if constrained is not None:
        state = [eom.time, *eom.coordinates, *eom.velocities]
    loop_events = _loop_events(eom, events, state, inputs, unpack)
    if loop_events is None:
        return None
    return NativeIntegrator(fast, loop_events, gains, multiplier_form)


def _loop_events(
    eom: EquationsOfMotion,
    events: Sequence[EventFunction],
    state: list[Any],
    inputs: Inputs,
    unpack: Unpack,
) -> c_loop.LoopEvents | None:
    """The events compiled for the loop (``state``: [t, the symbols of x]), or None."""
    expressions = traced_events(eom, events, state, inputs.t_span[0], inputs.x0, unpack)
    if expressions is None:
        return None
    function = c_loop.c_function([*state, *eom.parameters], expressions)
    if function is None:
        return None
    watch = EventWatch(events, unpack)
    return c_loop.LoopEvents(function, watch.directions, watch.limits)


@dataclass(frozen=True)
class NativeIntegrator:
    """RK45, DOP853 and RK4 in the C loop (module docstring): ``fast`` the free state equations
    or the multiplier form ``multiplier_form.equations``
    (:mod:`lagrangian.numerics.fast.c_constrained`, its parameters followed by
    ``extra_parameters``, Baumgarte's gains; the multipliers and residuals of the output rows
    from it), ``events`` the compiled event functions; the
    :class:`~lagrangian.simulation.integrators.protocol.Integrator` of the default backend where it
    applies: what :class:`~lagrangian.simulation.integrators.loop.SolverIntegrator` gives, to
    rounding (the same steps, failures, budget and messages)."""

    fast: FastEquations
    events: c_loop.LoopEvents | None = None
    extra_parameters: tuple[float, ...] = ()
    multiplier_form: NativeConstrained | None = None

    def run(
        self,
        dynamics: Dynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        t_out = inputs.t_out if inputs.t_out is not None else np.zeros(0)
        limits = c_loop.Limits(
            max_steps=inputs.max_steps,
            max_wall_time=inputs.max_wall_time,
            stiffness_edge=STABILITY_EDGE.get(inputs.method, 0.0),
            near=NEAR,
            share=SHARE,
            window=WINDOW,
            stiff_steps_left=STIFF_STEPS_LEFT,
            collapse_steps=COLLAPSE_STEPS,
            collapse=COLLAPSE,
        )
        settings = loop_settings(inputs, t_out)
        p = np.concatenate((inputs.p, self.extra_parameters))
        run = c_loop.integrate(self.fast, settings, inputs.x0, p, limits, progress, self.events)
        names = watch.names if watch is not None else ()
        events = tuple((names[i], t, x) for i, t, x in run.events)
        stopped = run.status == Status.STOPPED and bool(events)
        t, x = run.t, run.x
        if stopped and t_out.size and (not t.size or events[-1][1] > t[-1]):
            # the output ends at the terminal event, as SciPy's path ends it
            t, x = np.append(t, events[-1][1]), np.vstack((x, events[-1][2]))
        multipliers, residual = None, None
        if self.multiplier_form is not None:  # every row at once (c_constrained.py)
            multipliers, residual = constraint_rows(self.multiplier_form, t, x, p)
        return Integration(
            t=t,
            x=x,
            t_reached=run.t_reached,
            x_reached=run.x_reached,
            events=events,
            multipliers=multipliers,
            constraint_residual=residual,
            failure=None if run.interrupted else failure(run, dynamics, inputs),
            interrupted=run.interrupted,
            stopped_by=events[-1][0] if stopped else None,
            note=Budget(inputs.method, stiff_since=run.stiff_since).note(),
        )


def failure(run: c_loop.LoopRun, dynamics: Dynamics, inputs: Inputs) -> str | Fix | None:
    """Why the C loop's ``run`` failed, in the words SciPy's path uses for it
    (:func:`lagrangian.simulation.integrators.loop.integrate` and its Budget), or None."""
    status = run.status
    if not status.failed:
        return None
    if status == Status.SINGULAR and run.failed_at is not None:
        try:  # the NumPy right-hand side's own message, with the time and the state
            with np.errstate(all="ignore"):
                dynamics.field(*run.failed_at)
        except SimulationError as error:
            return str(error)
    if status == Status.STEP_BUDGET:
        return step_budget_message(inputs.max_steps, run.stiff_since)
    if status == Status.WALL_TIME and inputs.max_wall_time is not None:
        return wall_time_message(inputs.max_wall_time, run.steps, run.stiff_since)
    if status == Status.STIFF and run.stiff_since is not None:
        return stiffness_message(inputs.method, run.stiff_since, abs(run.last_step))
    if status == Status.COLLAPSED:
        return collapse_message(run.advanced, run.t_reached)
    return status.message


def loop_settings(inputs: Inputs, t_out: np.ndarray) -> Settings:
    """The settings of the hand-written loops (the C loop's and the vectorized batch's) from
    checked inputs, with the output times ``t_out`` (empty: every step)."""
    return Settings(
        inputs.method,
        inputs.t_span,
        t_out,
        inputs.rtol,
        inputs.atol,
        inputs.max_step,
        inputs.dt,
        inputs.max_steps,
    )
