"""simulate_constrained: integrate a System with holonomic and velocity constraints.

The state is x = [q; q_dot] of every coordinate; at each evaluation the accelerations and
the multipliers solve the augmented system of :mod:`lagrangian.numerics.constrained`, with
Baumgarte's stabilization when ``baumgarte = (alpha, beta)`` is not (0, 0).  The initial
state must satisfy the constraints (to 1e-9); ``project_initial=True`` moves it onto them
with :func:`lagrangian.constraints.project_state`.  ``project_steps=True`` moves the state
back onto the constraints after every step (coordinate projection; explicit Runge–Kutta
methods), which holds the residuals at the projection's tolerance for any length of run.
Unilateral constraints g >= 0 are simulated by :mod:`lagrangian.simulation.unilateral` (active
while they push, released when their multiplier would pull; a re-contact, an impact, is not
modelled and fails the run).

>>> import lagrangian as lg, sympy as sp
>>> x, y, m, g = sp.symbols("x y m g")
>>> ring = lg.System(coordinates=[x, y], parameters={m: 1.0, g: 9.81}, gravity=(0, -g),
...     particles=[lg.Particle("bead", m, (x, y))],
...     constraints=[lg.Holonomic(x**2 + y**2 - 1)])
>>> start = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
>>> run = lg.simulate(ring, start, 0.5, samples=3, baumgarte=(10, 10))
>>> run.names
('t', 'x', 'y', 'x_dot', 'y_dot', 'lambda_1', 'energy')
>>> run.drift()["constraint_residual_max"] < 1e-6
True
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from lagrangian.constraints import constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.model.constraints import Unilateral
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.constrained import CompiledConstrained, compile_constrained
from lagrangian.simulation.constrained_start import start_on_constraints
from lagrangian.simulation.events import EventFunction, EventWatch
from lagrangian.simulation.inputs import Inputs, resolve_inputs
from lagrangian.simulation.run import solver_starter, trajectory_of
from lagrangian.simulation.stepping import integrate
from lagrangian.simulation.trajectory import Trajectory

#: Methods whose state may be moved between steps (they carry only the last state forward).
PROJECTABLE = ("RK45", "RK23", "DOP853", "RK4")


def simulate_constrained(
    system: System,
    eom: EquationsOfMotion,
    given: Mapping[str, Any],
    fallback_initial: Mapping[Any, float],
    settings: Mapping[str, Any],
    *,
    events: Sequence[EventFunction] = (),
    raise_on_failure: bool = True,
    progress: Callable[[float], None] | None = None,
    baumgarte: tuple[float, float] = (0.0, 0.0),
    project_initial: bool = False,
    project_steps: bool = False,
) -> Trajectory:
    """The motion of ``system`` (whose unconstrained equations are ``eom``) under its
    constraints; ``given`` holds the arguments of :func:`lagrangian.simulate` as in run.py."""
    alpha, beta = _baumgarte(baumgarte)
    compiled = compile_equations(eom)
    if not compiled.regular:
        raise SimulationError(
            "Simulating constraints with first-order coordinates (no inertia) is not "
            "supported: every coordinate needs a velocity in the state."
        )
    inputs = resolve_inputs(compiled, given, fallback_initial, settings)
    if any(isinstance(c, Unilateral) for c in system.constraints):
        if project_steps:
            raise SimulationError(
                "project_steps does not apply to unilateral constraints (they are active "
                "only part of the time); use baumgarte=(alpha, beta)."
            )
        from lagrangian.simulation.unilateral import simulate_unilateral

        trajectory = simulate_unilateral(
            system,
            eom,
            compiled,
            inputs,
            events=events,
            progress=progress,
            alpha=alpha,
            beta=beta,
            project_initial=project_initial,
        )
        if not trajectory.success and raise_on_failure:
            raise SimulationError(
                f"{trajectory.message} Pass raise_on_failure=False to keep the trajectory "
                "computed up to the failure."
            )
        return trajectory
    numeric = compile_constrained(constrained_equations(eom, system.constraints))
    inputs = checked_initial(system, numeric, inputs, project_initial)
    n, p = len(compiled.coordinates), inputs.p

    def field(t: float, x: np.ndarray) -> np.ndarray:
        q_ddot, _ = numeric.accelerations(x[:n], x[n:], t, p, alpha, beta)
        return np.concatenate((x[n:], q_ddot))

    def unpack(t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[:n], x[n:]

    watch = EventWatch(events, unpack) if events else None
    project = _projection(numeric, inputs) if project_steps else None
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        run = integrate(
            solver_starter(field, inputs),
            inputs.t_span[0],
            inputs.x0,
            inputs.t_out,
            watch,
            progress,
            project,
        )
    trajectory = trajectory_of(compiled, inputs, run, watch)
    multipliers, residual = multipliers_along(numeric, trajectory, p, alpha, beta)
    trajectory = dataclasses.replace(
        trajectory,
        multipliers=multipliers,
        multiplier_names=numeric.multipliers,
        constraint_residual=residual,
    )
    if run.failure is not None and raise_on_failure:
        raise SimulationError(
            f"{trajectory.message} Pass raise_on_failure=False to keep the trajectory "
            "computed up to the failure."
        )
    return trajectory


def _projection(
    numeric: CompiledConstrained, inputs: Inputs
) -> Callable[[float, np.ndarray], np.ndarray]:
    """x -> the nearest state on the constraints, applied after every step (explicit
    Runge–Kutta methods only: the implicit ones keep a history the projection would bypass)."""
    if inputs.method not in PROJECTABLE:
        raise SimulationError(
            f"project_steps works with the methods {', '.join(PROJECTABLE)}, not "
            f"{inputs.method}: choose one of them, or baumgarte=(alpha, beta) instead."
        )
    n, p = len(numeric.coordinates), inputs.p

    def project(t: float, x: np.ndarray) -> np.ndarray:
        q, qd = numeric.project(x[:n], x[n:], t, p)
        return np.concatenate((q, qd))

    return project


def _baumgarte(value: Any) -> tuple[float, float]:
    try:
        alpha, beta = (float(v) for v in value)
    except (TypeError, ValueError):
        alpha = beta = math.nan
    if not (math.isfinite(alpha) and math.isfinite(beta) and alpha >= 0 and beta >= 0):
        raise SimulationError(
            f"baumgarte must be a pair (alpha, beta) of non-negative numbers, not {value!r}."
        )
    return alpha, beta


def _residual(
    numeric: CompiledConstrained, q: np.ndarray, qd: np.ndarray, t: float, p: np.ndarray
) -> float:
    h, c = numeric.residuals(q, qd, t, p)
    return float(np.max(np.abs(np.concatenate((h, c))), initial=0.0))


def checked_initial(
    system: System, numeric: CompiledConstrained, inputs: Inputs, project_initial: bool
) -> Inputs:
    """``inputs`` with an initial state on the constraints (projected when asked), or raise
    (:func:`lagrangian.simulation.constrained_start.start_on_constraints`)."""
    n, x0 = len(numeric.coordinates), inputs.x0
    residual = _residual(numeric, x0[:n], x0[n:], inputs.t_span[0], inputs.p)
    return start_on_constraints(system, numeric.coordinates, inputs, residual, project_initial)


def multipliers_along(
    numeric: CompiledConstrained,
    trajectory: Trajectory,
    p: np.ndarray,
    alpha: float,
    beta: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The multipliers and the largest constraint residual at every output time."""
    rows = len(trajectory.t)
    multipliers = np.full((rows, len(numeric.multipliers)), np.nan)
    residual = np.full(rows, np.nan)
    for i, (t, q, qd) in enumerate(zip(trajectory.t, trajectory.q, trajectory.q_dot)):
        residual[i] = _residual(numeric, q, qd, float(t), p)
        with contextlib.suppress(SimulationError):  # singular there: the multipliers stay NaN
            multipliers[i] = numeric.accelerations(q, qd, float(t), p, alpha, beta)[1]
    return multipliers, residual
