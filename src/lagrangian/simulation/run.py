"""simulate(system, initial, t_span) -> Trajectory: integrate the equations of motion.

    M(q, t) q_ddot = forcing(q, q_dot, t),    x = [q; q_dot],    dx/dt = [q_dot; M^-1 forcing]

(first-order coordinates keep only q in the state, see :mod:`lagrangian.numerics.state`),
integrated by any ``scipy.integrate.solve_ivp`` method, the fixed-step RK4 or the variational
integrator (:mod:`lagrangian.simulation.variational`).

>>> import lagrangian as lg
>>> trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.1}, 1.0, samples=3)
>>> trajectory.t
array([0. , 0.5, 1. ])
>>> trajectory.drift()["energy_relative"] < 1e-8
True
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolver, Radau

from lagrangian.derivation import EquationsOfMotion, derive
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.simulation.compiled_run import check_backend, integrate_compiled
from lagrangian.simulation.conserved import conserved_expressions, with_conserved
from lagrangian.simulation.events import EventFunction, EventWatch
from lagrangian.simulation.gimbal import gimbal_guard
from lagrangian.simulation.inputs import VARIATIONAL, Inputs, resolve_inputs
from lagrangian.simulation.rk4 import RK4
from lagrangian.simulation.stepping import Integration, integrate
from lagrangian.simulation.trajectory import Event, Trajectory

SOLVERS: dict[str, type[OdeSolver]] = {
    "RK45": RK45,
    "RK23": RK23,
    "DOP853": DOP853,
    "Radau": Radau,
    "BDF": BDF,
    "LSODA": LSODA,
    "RK4": RK4,
}


def simulate(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, float] | None = None,
    t_span: float | tuple[float, float] | None = None,
    *,
    parameters: Mapping[Any, float] | None = None,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    samples: int | None = None,
    t_eval: ArrayLike | None = None,
    dt: float | None = None,
    max_step: float = np.inf,
    events: Sequence[EventFunction] = (),
    raise_on_failure: bool = True,
    progress: Callable[[float], None] | None = None,
    baumgarte: tuple[float, float] = (0.0, 0.0),
    project_initial: bool = False,
    backend: str = "numpy",
    conserved: Mapping[str, Any] | None = None,
    project_steps: bool = False,
) -> Trajectory:
    """Integrate the motion of a System (derived here) or of its EquationsOfMotion.

    Parameters
    ----------
    system_or_eom:
        What to simulate; pass the EquationsOfMotion to reuse one derivation and compilation.
    initial:
        Initial coordinates and velocities by name or symbol (``theta``, ``theta_dot``), over
        ``System.initial``.  First-order coordinates need no velocity (their equation fixes
        it; a given one is ignored).
    t_span:
        T or (t0, T); default (0, ``System.simulation["t_end"]``).
    parameters:
        Parameter values by name or symbol, over the defaults.
    method:
        ``RK45`` (default), ``RK23``, ``DOP853``, ``Radau``, ``BDF``, ``LSODA`` (solve_ivp)
        or ``RK4`` (fixed step ``dt``, or the spacing of ``samples``), or ``variational``
        (fixed step ``dt``: the symplectic midpoint-rule integrator of
        :mod:`lagrangian.simulation.variational`, with applied forces, dissipation and
        holonomic constraints held exactly at every step; on a conservative system the energy
        error stays bounded instead of drifting).
    rtol, atol, max_step:
        Tolerances (default 1e-8, 1e-10) and largest step of the adaptive methods.
    samples, t_eval:
        ``samples`` evenly spaced output times, or the output times ``t_eval``; neither: every
        step.  method, rtol, atol, samples and dt also fall back to ``System.simulation``.
    events:
        Functions g(t, q, q_dot) whose zeros are recorded (``terminal``, ``direction``
        attributes as in solve_ivp).
    raise_on_failure:
        False: a failed integration returns a Trajectory with status ``"failed"``, the
        message, and every output computed before the failure.
    progress:
        Called with the time reached after every accepted step (for a progress bar).
    baumgarte:
        With constraints: Baumgarte's (alpha, beta) stabilization of the constraint drift
        (default (0, 0), off); see :mod:`lagrangian.simulation.constrained_run`.
    project_initial:
        With constraints: move an initial state that violates them onto them
        (:func:`lagrangian.constraints.project_state`) instead of raising.
    project_steps:
        With holonomic or velocity constraints: project the state back onto them after every
        step (RK45, RK23, DOP853, RK4), the other drift control besides ``baumgarte``.
    conserved:
        Quantities to follow, by name: expressions (model-file text or SymPy) of the
        coordinates, ``NAME_dot``, the parameters and t.  They join the momenta of the
        cyclic coordinates in ``Trajectory.conserved`` and its drift report
        (:mod:`lagrangian.simulation.conserved`).
    backend:
        ``"numpy"`` (default, the reference) or ``"numba"``: the right-hand side and the whole
        RK45, DOP853 or RK4 loop compiled (:mod:`lagrangian.simulation.compiled_run`; needs
        ``pip install lagrangian[fast]``; no events or constraints; the steps are SciPy's).

    A System with holonomic or velocity constraints is integrated in the multiplier form
    (``method="variational"``: holonomic ones only, in the discrete equations); its
    Trajectory also holds the multipliers lambda_j and the constraint residual.

    Raises
    ------
    SimulationError
        Bad input (every problem listed), unsupported systems, or a failed integration.
    """
    eom, fallback_initial, settings, system = describe_system(system_or_eom)
    quantities = conserved_expressions(eom, system, conserved or {})
    check_backend(backend, method if method is not None else settings.get("method"), system, events)
    given = {
        "initial": initial,
        "parameters": parameters,
        "t_span": t_span,
        "samples": samples,
        "t_eval": t_eval,
        "method": method,
        "rtol": rtol,
        "atol": atol,
        "dt": dt,
        "max_step": max_step,
    }
    # Euler angles of 3-D bodies: stop at gimbal lock with the body named (simulation/gimbal.py)
    guard = gimbal_guard(eom, system, given, fallback_initial, settings, backend)
    events = (*events, *guard.events)
    if (method if method is not None else settings.get("method")) == VARIATIONAL:
        from lagrangian.simulation.variational import simulate_variational  # imports run

        trajectory = simulate_variational(
            eom,
            system,
            given,
            fallback_initial,
            settings,
            events=events,
            raise_on_failure=raise_on_failure,
            progress=progress,
            project_initial=project_initial,
        )
        return guard.finish(with_conserved(trajectory, eom, quantities), raise_on_failure)
    if system.constraints:
        from lagrangian.simulation.constrained_run import simulate_constrained  # imports run

        trajectory = simulate_constrained(
            system,
            eom,
            given,
            fallback_initial,
            settings,
            events=events,
            raise_on_failure=raise_on_failure,
            progress=progress,
            baumgarte=baumgarte,
            project_initial=project_initial,
            project_steps=project_steps,
        )
        return guard.finish(with_conserved(trajectory, eom, quantities), raise_on_failure)
    compiled = compile_equations(eom)
    inputs = resolve_inputs(compiled, given, fallback_initial, settings)

    def field(t: float, x: np.ndarray) -> np.ndarray:
        return compiled.rhs(t, x, inputs.p)

    def unpack(t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[: len(compiled.coordinates)], compiled.velocities(t, x, inputs.p)

    watch = EventWatch(events, unpack) if events else None
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if backend == "numba":
            run = integrate_compiled(eom, inputs, progress)
        else:
            run = integrate(
                solver_starter(field, inputs),
                inputs.t_span[0],
                inputs.x0,
                inputs.t_out,
                watch,
                progress,
            )
    trajectory = trajectory_of(compiled, inputs, run, watch)
    if run.failure is not None and raise_on_failure:
        raise SimulationError(
            f"{trajectory.message} Pass raise_on_failure=False to keep the trajectory "
            "computed up to the failure."
        )
    return guard.finish(with_conserved(trajectory, eom, quantities), raise_on_failure)


def describe_system(
    system_or_eom: System | EquationsOfMotion,
) -> tuple[EquationsOfMotion, Mapping[Any, float], Mapping[str, Any], System]:
    """The equations, the initial values and simulation settings to fall back on, and the
    System: a System gives its own (derived once, :func:`lagrangian.derive`); equations of
    motion give none, and the System they were derived from."""
    if isinstance(system_or_eom, System):
        return derive(system_or_eom), system_or_eom.initial, system_or_eom.simulation, system_or_eom
    if isinstance(system_or_eom, EquationsOfMotion):
        return system_or_eom, {}, {}, system_or_eom.system
    raise SimulationError(
        f"simulate needs a System or the EquationsOfMotion of one, not "
        f"{type(system_or_eom).__name__}."
    )


def solver_starter(
    field: Callable[[float, np.ndarray], np.ndarray], inputs: Inputs
) -> Callable[[], OdeSolver]:
    """A function building the SciPy solver of ``inputs.method`` for dx/dt = field(t, x)
    (the integration loop calls it, since its first evaluation of the field may fail)."""
    t0, t1 = inputs.t_span
    solver = SOLVERS[inputs.method]
    if inputs.method == "RK4":
        return lambda: solver(field, t0, inputs.x0, t1, dt=inputs.dt)
    return lambda: solver(
        field, t0, inputs.x0, t1, rtol=inputs.rtol, atol=inputs.atol, max_step=inputs.max_step
    )


def trajectory_of(
    compiled: CompiledEquations, inputs: Inputs, run: Integration, watch: EventWatch | None
) -> Trajectory:
    """The Trajectory of an integration ``run``: velocities, energies, events and the status
    message at every output row."""
    n, p = len(compiled.coordinates), inputs.p
    t, x = run.t, run.x
    q_dot = compiled.velocities(t, x, p) if len(t) else np.zeros((0, n))
    q = x[:, :n]
    energy_function = None
    if compiled.energy_function_differs:
        energy_function = compiled.energy_function(q, q_dot, t, p) if len(t) else np.zeros(0)
    names = watch.names if watch is not None else ()
    return Trajectory(
        t=t,
        q=q,
        q_dot=q_dot,
        coordinates=compiled.coordinates,
        energy=compiled.energy(q, q_dot, t, p) if len(t) else np.zeros(0),
        energy_function=energy_function,
        events=tuple(
            Event(names[i], time, state_by_name(compiled, time, state, p))
            for i, time, state in run.events
        ),
        status="failed" if run.failure is not None else "success",
        message=_message(compiled, run, names, p),
        method=inputs.method,
        parameters=inputs.parameters,
    )


def state_by_name(
    compiled: CompiledEquations, t: float, x: np.ndarray, p: np.ndarray
) -> dict[str, float]:
    """Every coordinate and velocity at state x, by name."""
    q_dot = compiled.velocities(t, x, p)
    values = dict(zip(compiled.coordinates, x[: len(compiled.coordinates)].tolist()))
    values.update((name + "_dot", float(v)) for name, v in zip(compiled.coordinates, q_dot))
    return values


def _message(
    compiled: CompiledEquations, run: Integration, names: tuple[str, ...], p: np.ndarray
) -> str:
    if run.failure is not None:
        state = ", ".join(
            f"{name}={value:.6g}" for name, value in zip(compiled.state_names, run.x_reached)
        )
        return f"Integration failed at t = {run.t_reached:.6g} ({state}): {run.failure}"
    if run.terminal is not None:
        time = run.events[-1][1]
        return f"Stopped by the terminal event {names[run.terminal]} at t = {time:.6g}."
    return "The integration reached the end of the time span."
