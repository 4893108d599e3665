"""limit_cycle: a periodic motion, as a fixed point of its return map on a section.

A walker's gait repeats from one heel strike to the next.  The *return map* P takes the state
just after a transition (the section) to the state just after the next one; a period-one
cycle is a fixed point x* = P(x*), found by Newton's method on P(x) - x with the Jacobian of P
by central differences.  Its eigenvalues are the cycle's Floquet multipliers: the cycle is
stable when every one lies inside the unit circle (a reset that fixes some coordinates in
terms of others gives zeros) (Garcia, Chatterjee, Ruina & Coleman, *J. Biomech. Eng.* 120,
1998, §"Stability"; Guckenheimer & Holmes, *Nonlinear Oscillations*, 1983, §1.5).

The section may also be a surface G(q, q_dot, t) = 0 of a smooth motion, crossed in a
direction (Poincaré's first-return map).  P is taken on the whole state, so a start moved
along its own orbit returns to the same point: one multiplier is 0.  A conservative system's
energy is kept by P: one multiplier is 1, the cycle is one of a family (one per energy), and
the others come in pairs m, 1/m (P is symplectic on the energy surface): the cycle is at
best neutrally stable, with every multiplier on the unit circle.

>>> import lagrangian as lg
>>> cycle = limit_cycle(lg.examples.simplest_walker(), section="heel_strike")
>>> round(cycle.state["theta"], 5), round(cycle.period, 3), cycle.stable
(0.20031, 3.882, True)
>>> swing = limit_cycle(lg.examples.simple_pendulum(), {"theta": 0.0, "theta_dot": 1.0},
...                     section="theta")
>>> round(swing.period, 9)          # 4 K(k) sqrt(l/g), k = sin(amplitude / 2)
2.019033949
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, NamedTuple, cast

import numpy as np

from lagrangian.errors import LagrangianError, SimulationError, SimulationInputError
from lagrangian.model import System, Unilateral
from lagrangian.simulation.crossings import Crossing, section_crossing
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.integrators.piecewise import (
    Guard,
    Jump,
    PiecewiseIntegrator,
    integrate_piecewise,
)
from lagrangian.simulation.integrators.protocol import Dynamics
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import RunSetup, prepare
from lagrangian.simulation.transitions import SingleMode

#: Newton's method stops when |P(x) - x| falls below this (relative to |x| + 1).
TOLERANCE = 1e-10
#: The most Newton iterations.
ITERATIONS = 20
#: Multipliers this close to the unit circle are taken as on it (central differences of
#: returns integrated to 1e-12 give the Jacobian to about 1e-8).
NEUTRAL = 1e-6
#: The integration of one return (DOP853, tight, so that the differences are meaningful).
RETURN_SETTINGS = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12}


class LimitCycle(NamedTuple):
    """A period-one cycle: the ``state`` on the section (just after the transition, by name;
    or where the motion crosses the section expression),
    its ``period``, the Floquet ``multipliers`` (eigenvalues of the linearized return map,
    largest first), whether it is ``stable`` (all inside the unit circle), and how Newton's
    method went (``iterations``, the final ``residual`` |P(x) - x|)."""

    section: str
    state: Mapping[str, float]
    period: float
    multipliers: tuple[complex, ...]
    stable: bool
    iterations: int
    residual: float

    def document(self) -> dict[str, Any]:
        """The cycle as JSON-ready data (a multiplier as [real, imaginary])."""
        return {
            "section": self.section,
            "state": dict(self.state),
            "period": self.period,
            "multipliers": [[m.real, m.imag] for m in self.multipliers],
            "moduli": [abs(m) for m in self.multipliers],
            "stable": self.stable,
            "iterations": self.iterations,
            "residual": self.residual,
        }

    def text(self) -> str:
        """The cycle for people, a few lines."""
        state = ", ".join(f"{name} = {value:.10g}" for name, value in self.state.items())
        multipliers = ", ".join(_complex(m) for m in self.multipliers)
        largest = max(abs(m) for m in self.multipliers)
        verdict = "stable" if self.stable else "unstable"
        if not self.stable and largest <= 1 + NEUTRAL:
            verdict = "neutrally stable (a multiplier on the unit circle)"
        return (
            f"Limit cycle through {self.section}: period {self.period:.10g}, {verdict} "
            f"(largest |multiplier| {largest:.4g})\n  on the section: {state}\n"
            f"  Floquet multipliers: {multipliers}"
        )


def limit_cycle(
    system: System,
    initial: Mapping[str, float] | None = None,
    *,
    section: str,
    direction: str = "rising",
    parameters: Mapping[str, float] | None = None,
    max_return_time: float = 100.0,
) -> LimitCycle:
    """The period-one cycle through ``section`` near the motion from ``initial`` (over
    ``System.initial``): first the motion is followed to the section, then Newton's method
    finds the fixed point of the return map (module docstring).

    ``section`` names a transition of the System, or a unilateral constraint with a
    coefficient of restitution (the state just after each impact on it), or is an expression
    of the state whose zero, crossed in ``direction`` (``rising``, ``falling`` or ``both``), is
    the section: ``"theta"`` for a pendulum's swings through the vertical.

    Raises SimulationInputError for a section that is none of these, and SimulationError
    when a return does not reach the section within ``max_return_time`` or Newton's method
    does not converge."""
    returns = _ReturnMap(system, dict(initial or {}), dict(parameters or {}), section,
                         direction, max_return_time)  # fmt: skip
    x, _ = returns(returns.start)  # onto the section
    iterations, residual = _newton(returns, x)
    if residual > TOLERANCE * (1 + float(np.max(np.abs(iterations[-1])))):
        raise SimulationError(
            f"no period-one cycle through {section!r} found from this start: Newton's method "
            f"left |P(x) - x| = {residual:.3g} after {ITERATIONS} iterations; start nearer one"
        )
    x = iterations[-1]
    _, period = returns(x)
    multipliers = np.linalg.eigvals(returns.jacobian(x))
    ordered = tuple(complex(m) for m in sorted(multipliers, key=abs, reverse=True))
    return LimitCycle(
        section,
        dict(zip(returns.names, x.tolist())),
        period,
        ordered,
        # a multiplier on the unit circle, to the differences' accuracy, is not inside it
        bool(np.all(np.abs(multipliers) < 1 - NEUTRAL)),
        len(iterations) - 1,
        residual,
    )


def _newton(returns: _ReturnMap, x: np.ndarray) -> tuple[list[np.ndarray], float]:
    """The iterates of Newton's method on P(x) - x = 0 from x, and the last |P(x) - x|:
    x <- x - (dP/dx - 1)^-1 (P(x) - x), until the residual is below the tolerance."""
    iterates = [x]
    for _ in range(ITERATIONS):
        image, _ = returns(x)
        residual = float(np.max(np.abs(image - x)))
        if residual <= TOLERANCE * (1 + float(np.max(np.abs(x)))):
            break
        step = np.linalg.lstsq(returns.jacobian(x) - np.eye(len(x)), image - x, rcond=None)[0]
        x = x - step
        iterates.append(x)
    return iterates, residual


def _complex(value: complex) -> str:
    if abs(value.imag) <= 1e-12 * max(abs(value), 1e-300):
        return f"{value.real:.6g}"
    return f"{value.real:.6g} {'+' if value.imag >= 0 else '-'} {abs(value.imag):.6g}i"


class _ReturnMap:
    """P(x): the state just after the next firing of the transition ``section``, or at the
    next crossing of the section expression, from x at t = 0."""

    def __init__(
        self,
        system: System,
        initial: dict[str, float],
        parameters: dict[str, float],
        section: str,
        direction: str,
        horizon: float,
    ) -> None:
        self.setup = prepare(system, initial, horizon, dict(RETURN_SETTINGS),
                             parameters=parameters)  # fmt: skip
        self.names = self.setup.compiled.state_names
        self.start = np.array(self.setup.inputs.x0, dtype=float)
        # the motion is a frozen value: planned once, stepped from every start
        motion, integrator = plan(self.setup)
        smooth = not isinstance(integrator, PiecewiseIntegrator)
        hybrid = SingleMode(cast(Dynamics, motion)) if smooth else motion
        crossing = _section(self.setup, section, direction)
        self.section = section if crossing is None else crossing.__name__
        self.stopping = _StopAt(hybrid, self.section, crossing)

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, float]:
        inputs = dataclasses.replace(self.setup.inputs, x0=np.array(x, dtype=float), t_out=None)
        # a start on the section expression is not its crossing: the next one is
        disarmed = self.section if self.stopping.crossing is not None else None
        run = integrate_piecewise(
            self.stopping, inputs, None, None, SolverIntegrator(), disarmed=disarmed
        )
        if run.stopped_by != self.section:
            reason = run.failure or f"no {self.section!r} within t = {inputs.t_span[1]:g}"
            raise SimulationError(f"the return to the section failed: {reason}")
        return np.array(run.x_reached, dtype=float), float(run.t_reached)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """dP/dx by central differences (steps of 1e-6 relative); one-sided where a step
        leaves the admissible states (into a unilateral constraint of the section)."""
        columns = []
        for i in range(len(x)):
            h = 1e-6 * (1 + abs(x[i]))
            plus, minus = x.copy(), x.copy()
            plus[i] += h
            minus[i] -= h
            images: list[np.ndarray | None] = []
            for side in (plus, minus):
                try:
                    images.append(self(side)[0])
                except SimulationInputError:  # a start inside a constraint
                    images.append(None)
            if images[0] is not None and images[1] is not None:
                columns.append((images[0] - images[1]) / (2 * h))
            elif images[0] is not None or images[1] is not None:
                centre = self(x)[0]
                columns.append((images[0] - centre) / h if images[0] is not None
                               else (centre - images[1]) / h)  # fmt: skip
            else:
                raise SimulationError("the return map has no admissible neighbour to differentiate")
        return np.column_stack(columns)


def _section(setup: RunSetup, section: str, direction: str) -> Crossing | None:
    """None for a transition's name; else the crossing of the section expression (its
    name unused by the transitions), or SimulationInputError saying it is neither."""
    names = [item.name for item in setup.system.transitions]
    if section in names or section in impact_names(setup.system):
        return None
    try:
        crossing = section_crossing(setup.eom, section, setup.inputs.p, direction,
                                    name=_unused("section", names), terminal=True)  # fmt: skip
    except LagrangianError as error:
        raise SimulationInputError(
            f"section: {section!r} is not a transition of the system (its transitions: "
            f"{', '.join(names) or 'none'}), a unilateral constraint with a coefficient of "
            f"restitution (those: {', '.join(impact_names(setup.system)) or 'none'}) nor an "
            f"expression of its state: {error}"
        ) from None
    return crossing


def _unused(name: str, taken: list[str]) -> str:
    while name in taken:
        name += "_"
    return name


@dataclasses.dataclass(frozen=True)
class _StopAt:
    """A hybrid motion whose run ends at the first firing of the transition ``section``, or
    with ``crossing`` (a guard added to every mode, named ``section``) at its first zero."""

    inner: Any
    section: str
    crossing: Crossing | None = None

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def guards(self, mode: Any, piece: Any) -> list[Guard]:
        own = [self.crossing] if self.crossing is not None else []
        return [*self.inner.guards(mode, piece), *own]

    def transition(self, mode: Any, guard: Guard, t: float, x: np.ndarray) -> Jump:
        if guard is self.crossing:
            return Jump(mode, np.array(x, dtype=float), self.section, stop=True)
        jump: Jump = self.inner.transition(mode, guard, t, x)
        if jump.label == self.section:
            return jump._replace(stop=True)
        if jump.impact is not None and self.section in jump.impact.constraints:
            return jump._replace(stop=True, label=self.section)  # an impact on the section
        return jump


def impact_names(system: System) -> list[str]:
    """The names of the unilateral constraints that take impacts (a section of a return
    map: the state just after an impact on it)."""
    return [c.name for c in system.constraints
            if isinstance(c, Unilateral) and c.name and c.restitution is not None]  # fmt: skip
