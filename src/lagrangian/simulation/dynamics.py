"""The dynamics objects of the free and the constrained motion (the shape of
:class:`lagrangian.simulation.integrators.protocol.Dynamics`), and the one check of an initial state
against the constraints.

* :class:`FreeDynamics`: M(q, t) q_ddot = forcing(q, q_dot, t), x = [q; q_dot] (first-order
  coordinates keep only q, :mod:`lagrangian.numerics.state_equations`).
* :class:`MultiplierDynamics`: the multiplier form of :mod:`lagrangian.numerics.constrained`,

      [ M  -A^T ] [ q_ddot ]   [ forcing                      ]
      [ A    0  ] [ lambda ] = [ gamma - 2 alpha c - beta^2 h ],

  with Baumgarte's stabilization (alpha, beta) or a projection onto the constraints after
  every step (coordinate projection; explicit Runge–Kutta methods), which holds the
  residuals at the projection's tolerance for any length of run.

Every integrator that holds constraints starts the same way (:func:`start_on_constraints`):
an initial state within ``INITIAL_TOLERANCE`` of the constraints is taken as given, one
farther off is moved onto them when asked (:func:`lagrangian.constraints.project_state`),
refused otherwise.

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.compile import compile_equations
>>> compiled = compile_equations(lg.derive(lg.examples.simple_pendulum()))
>>> FreeDynamics(compiled, np.array([1.0, 9.81, 1.0])).field(0.0, np.array([np.pi / 2, 0.0]))
array([ 0.  , -9.81])
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Callable, Sequence
from typing import Generic, Protocol, TypeVar

import numpy as np

from lagrangian.constraints import project_state
from lagrangian.errors import Fix, Problem, Setting, SimulationError, SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.constrained import CompiledConstrained
from lagrangian.simulation.inputs import Inputs

#: Largest constraint residual of an initial state accepted as is.
INITIAL_TOLERANCE = 1e-9


class WithoutConstraints:
    """The constraint members of a Dynamics that has no constraints: no residual, no
    projection, no multiplier rows, and any initial state is a start."""

    def residual(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return 0.0

    def projection(self) -> None:
        return None

    def constraint_rows(self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray) -> None:
        return None

    def start(self, inputs: Inputs, project_initial: bool) -> Inputs:
        return inputs


@dataclasses.dataclass(frozen=True)
class FreeDynamics(WithoutConstraints):
    """dx/dt = [q_dot; q_ddot] from the compiled state equations, at the parameters p."""

    compiled: CompiledEquations
    p: np.ndarray
    multiplier_names: tuple[str, ...] = ()

    def field(self, t: float, x: np.ndarray) -> np.ndarray:
        return self.compiled.rhs(t, x, self.p)

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[: len(self.compiled.coordinates)], self.compiled.velocities(t, x, self.p)


class ConstraintForm(Protocol):
    """A compiled formulation with constraints: its coordinates, and the residuals (h, c) =
    (position residuals, 0 for velocity rows; A q_dot + b) at a state."""

    @property
    def coordinates(self) -> tuple[str, ...]: ...

    def residuals(
        self, q: np.ndarray, qd: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]: ...


F = TypeVar("F", bound=ConstraintForm)


@dataclasses.dataclass(frozen=True)
class ConstrainedMotion(Generic[F]):
    """What every formulation with constraints shares: the state x = [q; q_dot], the largest
    residual of the compiled ``form`` at the parameters p, and the start checked against the
    constraints of ``system`` (:func:`start_on_constraints`)."""

    system: System
    form: F
    p: np.ndarray

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = len(self.form.coordinates)
        return x[:n], x[n:]

    def residual(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        h, c = self.form.residuals(q, q_dot, t, self.p)
        return float(np.max(np.abs(np.concatenate((h, c))), initial=0.0))

    def start(self, inputs: Inputs, project_initial: bool) -> Inputs:
        coordinates = self.form.coordinates
        return start_on_constraints(
            self.residual, self.system, coordinates, inputs, project_initial
        )


@dataclasses.dataclass(frozen=True)
class MultiplierDynamics(ConstrainedMotion[CompiledConstrained]):
    """The multiplier form (module docstring) of the constraints of ``system`` at the
    parameters p: Baumgarte's ``gains`` (alpha, beta), and ``project_steps`` to move every
    step back onto the constraints."""

    gains: tuple[float, float] = (0.0, 0.0)
    project_steps: bool = False

    @property
    def multiplier_names(self) -> tuple[str, ...]:
        return self.form.multipliers

    def field(self, t: float, x: np.ndarray) -> np.ndarray:
        n = len(self.form.coordinates)
        q_ddot, _ = self.form.accelerations(x[:n], x[n:], t, self.p, *self.gains)
        return np.concatenate((x[n:], q_ddot))

    def multipliers(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> np.ndarray:
        """lambda at one state (raises SimulationError where the matrix is singular)."""
        return self.form.accelerations(q, q_dot, t, self.p, *self.gains)[1]

    def projection(self) -> Callable[[float, np.ndarray], np.ndarray] | None:
        if not self.project_steps:
            return None
        n, numeric, p = len(self.form.coordinates), self.form, self.p

        def project(t: float, x: np.ndarray) -> np.ndarray:
            return np.concatenate(numeric.project(x[:n], x[n:], t, p))

        return project

    def constraint_rows(
        self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The multipliers and the largest constraint residual at every output row (NaN
        multipliers where the matrix is singular)."""
        multipliers = np.full((len(t), len(self.multiplier_names)), np.nan)
        residual = np.full(len(t), np.nan)
        for i, (time, qi, vi) in enumerate(zip(t, q, q_dot)):
            residual[i] = self.residual(float(time), qi, vi)
            with contextlib.suppress(SimulationError):
                multipliers[i] = self.multipliers(float(time), qi, vi)
        return multipliers, residual


def start_on_constraints(
    residual_at: Callable[[float, np.ndarray, np.ndarray], float],
    system: System,
    coordinates: Sequence[str],
    inputs: Inputs,
    project_initial: bool,
) -> Inputs:
    """``inputs`` when the largest constraint residual of its initial state (``residual_at``
    of t, q, q_dot) is within ``INITIAL_TOLERANCE``; else, with ``project_initial``, the inputs
    with that state projected onto the constraints of ``system``; else SimulationInputError
    saying how to fix it.  ``coordinates`` name the first half of x0 = [q; q_dot]."""
    n, x0, t0 = len(coordinates), inputs.x0, inputs.t_span[0]
    residual = residual_at(t0, x0[:n], x0[n:])
    if residual <= INITIAL_TOLERANCE:  # False for NaN: a state where h is not defined
        return inputs
    if not project_initial:
        problem = Problem(
            "initial",
            f"the initial state violates the constraints: the largest residual is "
            f"{residual:.3g} (> {INITIAL_TOLERANCE:g})",
            Fix("move it onto them: pass {}", (Setting("project_initial", True),)),
        )
        raise SimulationInputError("Cannot simulate (1 problem):", [problem])
    state: dict[str, float] = {**inputs.parameters, "t": t0}
    state.update(zip(coordinates, x0[:n].tolist()))
    state.update((name + "_dot", float(v)) for name, v in zip(coordinates, x0[n:]))
    projected = {symbol.name: value for symbol, value in project_state(system, state).items()}
    names = [*coordinates, *(f"{name}_dot" for name in coordinates)]
    return dataclasses.replace(inputs, x0=np.array([projected[k] for k in names], dtype=float))
