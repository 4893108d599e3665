"""simulate(system, initial, t_span) -> Trajectory: integrate the equations of motion.

    M(q, t) q_ddot = forcing(q, q_dot, t),    x = [q; q_dot],    dx/dt = [q_dot; M^-1 forcing]

(first-order coordinates keep only q in the state, see :mod:`lagrangian.numerics.state_equations`),
integrated by any ``scipy.integrate.solve_ivp`` method, the fixed-step RK4 (RK45, DOP853 and
RK4 in the compiled C loop where it runs) or the variational integrator
(:mod:`lagrangian.simulation.variational.midpoint`).

One driver for every path (docs/architecture.md): :func:`~lagrangian.simulation.setup.prepare`
checks the call into a run setup, :func:`plan` picks the dynamics of the formulation (free,
multiplier form, active sets of unilateral constraints, discrete Lagrangian) and the
integrator from the method table, the integrator steps it, and
:func:`~lagrangian.simulation.outcome.conclude` builds the Trajectory and decides on failure.

>>> import lagrangian as lg
>>> trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.1}, 1.0, samples=3)
>>> trajectory.t
array([0. , 0.5, 1. ])
>>> trajectory.drift()["energy_relative"] < 1e-8
True
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from lagrangian.constraints import constrained_equations, multiplier_names
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Fix, Problem, Setting, SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.constrained import compile_constrained
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
from lagrangian.simulation.dynamics import FreeDynamics, MultiplierDynamics
from lagrangian.simulation.flight import FlightIntegrator
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.compiled import native_integrator
from lagrangian.simulation.integrators.events import EventFunction, EventWatch
from lagrangian.simulation.integrators.loop import FAILURES, SolverIntegrator
from lagrangian.simulation.integrators.piecewise import Hybrid, PiecewiseIntegrator
from lagrangian.simulation.integrators.protocol import Integrator, Motion
from lagrangian.simulation.options import StepKeywords, check_keywords
from lagrangian.simulation.outcome import conclude
from lagrangian.simulation.setup import RunSetup, prepare
from lagrangian.simulation.switching import SwitchedDynamics, has_switching
from lagrangian.simulation.trajectory import Trajectory
from lagrangian.simulation.transitions import with_transitions
from lagrangian.simulation.unilateral import UnilateralDynamics
from lagrangian.simulation.variational.midpoint import DiscreteDynamics, VariationalIntegrator

if TYPE_CHECKING:
    from typing_extensions import Unpack


def simulate(
    system_or_eom: System | EquationsOfMotion,
    initial: Mapping[Any, float] | None = None,
    t_span: float | tuple[float, float] | None = None,
    *,
    parameters: Mapping[Any, float] | None = None,
    events: Sequence[EventFunction] = (),
    raise_on_failure: bool = True,
    progress: Callable[[float], None] | None = None,
    baumgarte: tuple[float, float] | None = None,
    project_initial: bool = False,
    project_steps: bool = False,
    backend: str = "numpy",
    conserved: Mapping[str, Any] | None = None,
    **stepping: Unpack[StepKeywords],
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
        :mod:`lagrangian.simulation.variational.midpoint`, with applied forces, dissipation and
        holonomic constraints held exactly at every step; on a conservative system the energy
        error stays bounded instead of drifting), or ``gauss4``, ``gauss6`` (fixed step ``dt``:
        the symplectic Gauss–Legendre collocation of order 4 and 6, Lobatto IIIA–IIIB with
        holonomic constraints, :mod:`lagrangian.simulation.variational.collocation`; these three run
        compiled when numba is installed).  The names are those of
        :data:`lagrangian.simulation.methods.TABLE`.
    rtol, atol, max_step:
        Tolerances (default 1e-8, 1e-10) and largest step of the adaptive methods (refused
        with the others).
    dt:
        The step of RK4 and of the variational integrator (refused with the others).
    samples, t_eval:
        ``samples`` evenly spaced output times, or the output times ``t_eval``; neither: every
        step.  method, rtol, atol, samples and dt also fall back to ``System.simulation``.
    events:
        Functions g(t, q, q_dot) whose zeros are recorded (``terminal``, ``direction``
        attributes as in solve_ivp).
    raise_on_failure:
        False: a failed or interrupted (Ctrl-C) integration returns a Trajectory with status
        ``"failed"`` or ``"interrupted"``, the message, and every output computed before.
        True (default): a failure raises SimulationError, Ctrl-C raises
        :class:`~lagrangian.simulation.outcome.SimulationInterrupted` (a KeyboardInterrupt
        holding that Trajectory).
    progress:
        Called with the time reached after every accepted step (for a progress bar; the
        compiled variational loops call it at least every 1% of the run).
    baumgarte:
        With constraints: Baumgarte's (alpha, beta) stabilization of the constraint drift
        (default off); see :mod:`lagrangian.simulation.dynamics`.
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
        ``"numpy"`` (default): SciPy's solvers, where RK45, DOP853 and RK4 (free systems, and
        the multiplier form without ``project_steps``; events that are expressions of the
        state) run step for step in a C loop compiled once per machine when a C compiler is
        present (:mod:`lagrangian.simulation.integrators.compiled`).  ``"numba"`` is another
        name of the default for one release (the C loop replaced the numba loops); the run's
        message says so.

    A System with holonomic or velocity constraints is integrated in the multiplier form
    (``method="variational"``: holonomic ones only, in the discrete equations); its
    Trajectory also holds the multipliers lambda_j and the constraint residual.  An option
    that does not apply to the method or the system is refused by name.

    Raises
    ------
    SimulationInputError
        Bad input, every problem listed (a ValueError and a SimulationError).
    SimulationError
        A failed integration (with ``raise_on_failure``).
    """
    check_keywords(stepping, "simulate")
    setup = prepare(
        system_or_eom,
        initial,
        t_span,
        stepping,
        parameters=parameters,
        events=events,
        conserved=conserved,
        progress=progress,
        backend=backend,
        baumgarte=baumgarte,
        project_initial=project_initial,
        project_steps=project_steps,
    )
    motion, integrator = plan(setup)
    inputs = motion.start(setup.inputs, setup.options.project_initial)
    refuse_unphysical(motion, inputs, setup.compiled.state_names)
    watch = EventWatch(setup.events, motion.unpack) if setup.events else None
    run = integrator.run(motion, inputs, watch, progress)
    return conclude(setup, motion, run, raise_on_failure)


def refuse_unphysical(motion: Motion, inputs: Inputs, names: Sequence[str]) -> None:
    """Refuse an initial state where the equations of motion are not finite numbers (a
    velocity of 1e308 whose square overflows, a division by zero in the model): no step can
    start from it, and an adaptive solver would look for its first step size for ever.
    A formulation without a vector field (the discrete one) or a field that fails there
    (a singular mass matrix) is left to the integrator, which reports it."""
    field = getattr(motion, "field", None)
    t0, x0 = inputs.t_span[0], inputs.x0
    try:
        with np.errstate(all="ignore"):
            if field is None and isinstance(motion, SwitchedDynamics):
                field = motion.piece(motion.initial_mode(t0, x0)[0]).field
            if field is None:
                return
            rates = np.asarray(field(t0, x0), dtype=float)
    except FAILURES:
        return
    bad = [name for name, rate in zip(names, rates) if not np.isfinite(rate)]
    if not bad:
        return
    state = ", ".join(f"{name}={value:g}" for name, value in zip(names, x0))
    problem = Problem(
        "initial",
        f"at the initial state ({state}) the equations of motion give the rate of "
        f"{', '.join(bad)} as {rates[names.index(bad[0])]:g}, not a finite number: an "
        "overflow or a division by zero there",
        Fix(
            "start from a state of physical size where the forces are finite ({}), or check "
            "the model's expressions for a division by zero",
            (Setting("initial", entry=names[int(np.argmax(np.abs(x0)))]),),
        ),
    )
    raise SimulationInputError("Cannot simulate (1 problem):", [problem])


def plan(setup: RunSetup) -> tuple[Motion, Integrator[Any]]:
    """The dynamics of the system's formulation and the integrator of the method; the
    System's transitions (:mod:`lagrangian.simulation.transitions`) make it a hybrid motion
    of the piecewise loop."""
    motion, integrator = formulation(setup)
    if not setup.system.transitions:
        return motion, integrator
    if setup.options.spec.variational:
        raise SimulationInputError(
            f"transitions: method={setup.options.method!r} steps a fixed grid and locates no "
            "guard; use an adaptive method such as 'DOP853'"
        )
    # a hybrid formulation (unilateral constraints, switching) keeps its own guards
    inner = cast(Hybrid[Any], motion) if isinstance(integrator, PiecewiseIntegrator) else None
    hybrid = with_transitions(setup.eom, setup.inputs.p, motion, inner)
    return hybrid, PiecewiseIntegrator(SolverIntegrator())


def formulation(setup: RunSetup) -> tuple[Motion, Integrator[Any]]:
    """The dynamics of the system's formulation and the integrator of the method."""
    options, eom, p = setup.options, setup.eom, setup.inputs.p
    constraints = setup.system.constraints
    names = multiplier_names(len(constraints))
    if options.spec.variational:
        expressions = [c.expression for c in constraints]
        mechanics = compile_discrete_mechanics(eom, expressions)
        discrete = DiscreteDynamics(setup.system, mechanics, p, names)
        return discrete, VariationalIntegrator(options.method)
    if options.unilateral:
        dynamics = UnilateralDynamics(setup.system, eom, p, options.gains, names)
        # pieces in closed form where the contacts' motion is polynomial in t, else stepped
        return dynamics, PiecewiseIntegrator(FlightIntegrator(SolverIntegrator()))
    if constraints:
        equations = constrained_equations(eom, constraints)
        multipliers = MultiplierDynamics(
            setup.system, compile_constrained(equations), p, options.gains, options.project_steps
        )
        # RK45 and DOP853 of the multiplier form in the C loop where it can run, as below
        native = native_integrator(
            eom, options, setup.events, setup.inputs, multipliers.unpack, equations
        )
        return multipliers, native or SolverIntegrator()
    if has_switching(eom) and all(order == 2 for order in eom.coordinate_orders.values()):
        return SwitchedDynamics(eom, p), PiecewiseIntegrator(SolverIntegrator())
    # the methods of the C loop compiled once per machine where it can run (a C compiler,
    # equations and events LLVM compiles), else SciPy's solvers
    free = FreeDynamics(setup.compiled, p)
    native = native_integrator(eom, options, setup.events, setup.inputs, free.unpack)
    return free, native or SolverIntegrator()
