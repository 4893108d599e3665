"""The whole integration in one compiled call: the C loop of the default backend, and
simulate(..., backend="numba").

The default backend runs RK45 and DOP853 on a free system without events in the C loop
compiled once per machine (:mod:`lagrangian.numerics.fast.c_loop`, :class:`NativeIntegrator`):
SciPy's steps, the right-hand side compiled by SymEngine's LLVM backend, the budget of
:mod:`lagrangian.simulation.budget` checked after every step with the same messages, a
progress callback after every step and Ctrl-C keeping the rows so far.  Where there is no C
compiler, or SymEngine cannot compile the equations, :func:`native_integrator` is None and
SciPy's solvers run instead.

The numba backend (:mod:`lagrangian.numerics.fast`) runs SciPy's RK45 and DOP853, step for
step, and the fixed-step RK4, with the right-hand side and the loop compiled, so no Python
runs per step; it returns what the NumPy backend returns.  What it does not do is refused up
front by :class:`lagrangian.simulation.options.Options`, naming the feature: events (use
:func:`lagrangian.simulation.batch.simulate_batch` with ``stop_when`` for a stop condition),
constraints, the variational integrator, and the implicit or other SciPy methods.  A progress
callback is called once, at the end.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.outcome import FINISHED, SINGULAR, STEP_BUDGET
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.fast.tableaus import ADAPTIVE
from lagrangian.simulation.budget import (
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
from lagrangian.simulation.events import EventWatch
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integration import Dynamics, Integration, Progress
from lagrangian.simulation.options import Options


def native_integrator(
    eom: EquationsOfMotion, options: Options, events: Sequence[Any]
) -> NativeIntegrator | None:
    """The C loop's integrator for a run of the default backend that it can take (RK45 or
    DOP853, no constraints, no events), or None: another run, no C compiler, or equations
    SymEngine's LLVM backend cannot compile (SciPy's solvers take those)."""
    if options.backend != "numpy" or options.method not in ADAPTIVE:
        return None
    if events or options.constraints or not c_loop.available():
        return None
    fast = c_loop.native_equations(eom)
    return None if fast is None else NativeIntegrator(fast)


@dataclass(frozen=True)
class NativeIntegrator:
    """RK45 and DOP853 of a free system in the C loop (module docstring), the
    :class:`~lagrangian.simulation.integration.Integrator` of the default backend where it
    applies: what :class:`~lagrangian.simulation.stepping.SolverIntegrator` gives, to
    rounding (the same steps, failures, budget and messages)."""

    fast: FastEquations

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
        run = c_loop.integrate(self.fast, settings, inputs.x0, inputs.p, limits, progress)
        return Integration(
            t=run.t,
            x=run.x,
            t_reached=run.t_reached,
            x_reached=run.x_reached,
            failure=None if run.interrupted else failure(run, dynamics, inputs),
            interrupted=run.interrupted,
            note=Budget(inputs.method, stiff_since=run.stiff_since).note(),
        )


def failure(run: c_loop.LoopRun, dynamics: Dynamics, inputs: Inputs) -> str | None:
    """Why the C loop's ``run`` failed, in the words SciPy's path uses for it
    (:func:`lagrangian.simulation.stepping.integrate` and its Budget), or None."""
    status = run.status
    if status == FINISHED:
        return None
    if status == SINGULAR and run.failed_at is not None:
        try:  # the NumPy right-hand side's own message, with the time and the state
            with np.errstate(all="ignore"):
                dynamics.field(*run.failed_at)
        except SimulationError as error:
            return str(error)
    if status == STEP_BUDGET:
        return step_budget_message(inputs.max_steps, run.stiff_since)
    if status == c_loop.WALL_TIME and inputs.max_wall_time is not None:
        return wall_time_message(inputs.max_wall_time, run.steps, run.stiff_since)
    if status == c_loop.STIFF and run.stiff_since is not None:
        return stiffness_message(inputs.method, run.stiff_since, abs(run.last_step))
    if status == c_loop.COLLAPSED:
        return collapse_message(run.advanced, run.t_reached)
    return c_loop.describe_status(status)


def integrate_compiled(
    eom: EquationsOfMotion, inputs: Inputs, progress: Progress | None = None
) -> Integration:
    """Integrate with the numba backend; the result as
    :func:`lagrangian.simulation.stepping.integrate` gives it (rows up to a failure, the
    failure).  Needs ``pip install lagrangian[fast]`` (SimulationError naming it)."""
    from lagrangian.numerics.fast import fast_equations, require_numba
    from lagrangian.numerics.fast.outcome import describe, failed
    from lagrangian.numerics.fast.run import integrate

    require_numba()
    fast = fast_equations(eom)
    t_out = inputs.t_out if inputs.t_out is not None else np.zeros(0)
    run = integrate(fast, loop_settings(inputs, t_out), inputs.x0, inputs.p)
    if progress is not None:
        progress(run.t_reached)
    return Integration(
        t=run.t,
        x=run.x,
        t_reached=float(run.t_reached),
        x_reached=np.asarray(run.x_reached, dtype=float),
        failure=describe(run.status) if failed(run.status) else None,
    )


def loop_settings(inputs: Inputs, t_out: np.ndarray) -> Settings:
    """The settings of the hand-written loops (numba's and the NumPy batch's) from checked
    inputs, with the output times ``t_out`` (empty: every step)."""
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
