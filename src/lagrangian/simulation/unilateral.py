"""The motion under unilateral constraints g(q, t) >= 0: the active-set driver.

Active set strategy.  At the start a unilateral constraint is active (treated as a holonomic
one, g = 0) when g and dg/dt are ~0 (|.| <= INITIAL_TOLERANCE), inactive when g > 0 or when
g ~ 0 and dg/dt > 0 (leaving); g < 0, or g ~ 0 with dg/dt < 0 (an impact), is refused.  The
holonomic and velocity constraints are always active.  The motion is integrated with the
active constraints in the multiplier form of :mod:`lagrangian.numerics.constrained`.

Sign: the force of constraint j is +lambda_j dg_j/dq (:mod:`lagrangian.constraints.
multipliers`), which points to increasing g when lambda_j > 0: an active unilateral
constraint pushes while lambda_j >= 0.  (A particle resting on top of a sphere, g = x^2 + y^2
- R^2: lambda = m (g y - v^2) / (2 R^2) > 0, the force lambda (2x, 2y) points outwards.)

* Release: when an active unilateral constraint's multiplier crosses zero to the pulling
  side (lambda_j < 0) the integration stops at that zero, the constraint is dropped from the
  active set, an Event ``"release <name or index>"`` is recorded with the time and state, and
  the integration goes on from that state.  A multiplier already negative at the start of a
  piece releases its constraint there.
* Re-contact is not modelled: when an inactive constraint's g becomes negative (below
  -RECONTACT_TOLERANCE, which absorbs the integration error right after a release, where g
  grows like (t - t_release)^3) the run stops with status "failed" and a message saying that
  impacts are not modelled.

Each piece is integrated by the solver integrator with the multiplier form of its active set
(:class:`lagrangian.simulation.dynamics.MultiplierDynamics`); the pieces are joined into one
Integration: the states, the multipliers of every constraint (NaN while a unilateral one is
inactive) and the residuals of the active constraints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np

from lagrangian.constraints import constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.model.constraints import Constraint, Holonomic, Unilateral, label, statement
from lagrangian.numerics.constrained import CompiledConstrained, compile_constrained
from lagrangian.simulation.dynamics import INITIAL_TOLERANCE, MultiplierDynamics
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.events import EventFunction, EventWatch
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.integrators.piecewise import continued_from, joined
from lagrangian.simulation.integrators.protocol import Integration, Progress
from lagrangian.symbolic.caches import IdentityCache

#: How far below zero an inactive constraint's g may go before it counts as a re-contact.
RECONTACT_TOLERANCE = 1e-8

_FORMS: IdentityCache[EquationsOfMotion, dict[tuple[int, ...], CompiledConstrained]] = (
    IdentityCache()
)


class _Watched:
    """An event function of this module: a multiplier (release) or a g (re-contact)."""

    terminal = True
    direction = -1.0

    def __init__(
        self, name: str, index: int, release: bool, function: Callable[..., float]
    ) -> None:
        self.__name__ = name
        self.index, self.release, self.function = index, release, function

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return self.function(t, q, q_dot)


@dataclasses.dataclass(frozen=True)
class UnilateralDynamics:
    """The constraints of ``system`` with active sets (module docstring), at the parameters
    p with Baumgarte's ``gains``; ``multiplier_names`` name one multiplier per constraint."""

    system: System
    eom: EquationsOfMotion
    p: np.ndarray
    gains: tuple[float, float]
    multiplier_names: tuple[str, ...]

    @property
    def one_sided(self) -> tuple[int, ...]:
        """The indices of the unilateral constraints."""
        return tuple(i for i, c in enumerate(self.system.constraints) if isinstance(c, Unilateral))

    def piece(self, active: set[int]) -> MultiplierDynamics:
        """The multiplier form of the ``active`` constraints (the unilateral ones as the
        holonomic constraints they act like), compiled once per set and equations."""
        order = tuple(sorted(active))
        forms = _FORMS.get(self.eom, lambda _: {})
        if order not in forms:
            chosen = [_bilateral(self.system.constraints[i]) for i in order]
            forms[order] = compile_constrained(constrained_equations(self.eom, chosen))
        return MultiplierDynamics(self.system, forms[order], self.p, self.gains)

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = len(self.eom.coordinates)
        return x[:n], x[n:]

    def residual(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return self.piece(self.active_at(t, q, q_dot)).residual(t, q, q_dot)

    def constraint_rows(self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray) -> None:
        return None  # the active-set driver gives them, piece by piece

    def start(self, inputs: Inputs, project_initial: bool) -> Inputs:
        """The start checked against the constraints active there (a projection keeps the
        touching unilateral ones at g = 0, as the holonomic ones they act like)."""
        n, t0 = len(self.eom.coordinates), inputs.t_span[0]
        active = sorted(self.active_at(t0, inputs.x0[:n], inputs.x0[n:]))
        chosen = [_bilateral(self.system.constraints[i]) for i in active]
        piece = dataclasses.replace(
            self.piece(set(active)), system=self.system.replace(constraints=chosen)
        )
        return piece.start(inputs, project_initial)

    def active_at(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> set[int]:
        """The constraints active at a start: the bilateral ones, and each unilateral one
        touching (g ~ 0, dg/dt ~ 0); SimulationInputError when one is violated or hit."""
        constraints = self.system.constraints
        active = {i for i in range(len(constraints)) if i not in self.one_sided}
        for i in self.one_sided:
            h, c = self.piece({i}).form.residuals(q, q_dot, t, self.p)
            if _touching(i, constraints[i], float(h[0]), float(c[0])):
                active.add(i)
        return active

    def watchers(self, active: set[int], piece: MultiplierDynamics) -> list[_Watched]:
        """The terminal events of a piece: each active unilateral multiplier turning to the
        pulling side (a release), each inactive one's g going below zero (a re-contact)."""
        order = sorted(active)
        watched = [
            _release(f"release {self.tag(i)}", i, k, piece)
            for k, i in enumerate(order)
            if i in self.one_sided
        ]
        for i in self.one_sided:
            if i not in active:
                watched.append(_contact(f"contact {self.tag(i)}", i, self.piece({i}), self.p))
        return watched

    def tag(self, i: int) -> str:
        return self.system.constraints[i].name or str(i)


@dataclasses.dataclass(frozen=True)
class ActiveSetIntegrator:
    """Integrates piece by piece, each with the active constraints' multiplier form, until
    the end, a failure, a re-contact or the caller's terminal event (module docstring)."""

    inner: SolverIntegrator = SolverIntegrator()

    def run(
        self,
        dynamics: UnilateralDynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        own: Sequence[EventFunction] = watch.functions if watch is not None else ()
        counts = np.zeros(len(own), dtype=int)
        n, t1 = len(dynamics.eom.coordinates), inputs.t_span[1]
        active = dynamics.active_at(inputs.t_span[0], inputs.x0[:n], inputs.x0[n:])
        pieces: list[Integration] = []
        released: list[tuple[str, float, np.ndarray]] = []
        current = inputs
        while True:
            piece = dynamics.piece(active)
            pulling = _pulling(dynamics, piece, active, current)
            if pulling is not None:  # released at once, before integrating this piece
                active.discard(pulling)
                released.append((f"release {dynamics.tag(pulling)}", *_start(current)))
                continue
            watched = dynamics.watchers(active, piece)
            piece_watch = EventWatch([*own, *watched], piece.unpack)
            piece_watch.counts[: len(own)] = counts
            run = self.inner.run(piece, current, piece_watch, progress)
            counts = piece_watch.counts[: len(own)].copy()
            pieces.append(_with_multipliers(run, piece, sorted(active), dynamics, released))
            released = []
            event = next((w for w in watched if w.__name__ == run.stopped_by), None)
            if run.status != "success" or event is None:
                break
            _, t_event, x_event = run.events[-1]
            if not event.release:
                pieces[-1] = _recontact(pieces[-1], dynamics, event.index, t_event, x_event)
                break
            active.discard(event.index)
            if t_event >= t1:
                break
            current = continued_from(current, t_event, x_event)
        return joined(pieces)


def _pulling(
    dynamics: UnilateralDynamics, piece: MultiplierDynamics, active: set[int], inputs: Inputs
) -> int | None:
    """The active unilateral constraint whose multiplier pulls at the start of a piece (the
    most negative one), or None."""
    t, x = _start(inputs)
    n = len(dynamics.eom.coordinates)
    lam = piece.multipliers(t, x[:n], x[n:])
    pulling = [(lam[k], i) for k, i in enumerate(sorted(active)) if i in dynamics.one_sided]
    pulling = [pair for pair in pulling if pair[0] < 0]
    return min(pulling)[1] if pulling else None


def _start(inputs: Inputs) -> tuple[float, np.ndarray]:
    return inputs.t_span[0], inputs.x0


def _with_multipliers(
    run: Integration,
    piece: MultiplierDynamics,
    order: list[int],
    dynamics: UnilateralDynamics,
    released: list[tuple[str, float, np.ndarray]],
) -> Integration:
    """A piece with the multipliers of every constraint (NaN for the inactive ones) and the
    residual of the active ones, after the releases at its start."""
    n = len(dynamics.eom.coordinates)
    multipliers, residual = piece.constraint_rows(run.t, run.x[:, :n], run.x[:, n:])
    full = np.full((len(run.t), len(dynamics.multiplier_names)), np.nan)
    full[:, order] = multipliers
    return dataclasses.replace(
        run,
        multipliers=full,
        constraint_residual=residual,
        events=(*released, *run.events),
    )


def _recontact(
    run: Integration, dynamics: UnilateralDynamics, index: int, t: float, x: np.ndarray
) -> Integration:
    """A piece ended by an inactive constraint's g going below zero: a failure."""
    constraint = dynamics.system.constraints[index]
    failure = (
        f"the unilateral constraint {label(index, constraint)}, {statement(constraint)}, is "
        f"violated again at t = {t:.6g}: impacts are not modelled, so the integration stops "
        "there"
    )
    return dataclasses.replace(run, failure=failure, stopped_by=None, t_reached=t, x_reached=x)


def _bilateral(constraint: Constraint) -> Constraint:
    """An active unilateral constraint as the holonomic one it acts like."""
    if isinstance(constraint, Unilateral):
        return Holonomic(constraint.expression, name=constraint.name)
    return constraint


def _touching(index: int, constraint: Constraint, g: float, g_dot: float) -> bool:
    """Whether a unilateral constraint starts active; raise when it is violated or hit."""
    where = f"{label(index, constraint)}, {statement(constraint)}"
    if g < -INITIAL_TOLERANCE:
        raise SimulationInputError(
            f"The initial state violates the unilateral constraint {where}: g = {g:.3g} < 0."
        )
    if g > INITIAL_TOLERANCE or g_dot > INITIAL_TOLERANCE:
        return False
    if g_dot < -INITIAL_TOLERANCE:
        raise SimulationInputError(
            f"The initial state moves into the unilateral constraint {where} (dg/dt = "
            f"{g_dot:.3g} < 0 at g = 0): impacts are not modelled."
        )
    return True


def _release(name: str, index: int, k: int, piece: MultiplierDynamics) -> _Watched:
    def multiplier(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(piece.multipliers(t, q, q_dot)[k])

    return _Watched(name, index, True, multiplier)


def _contact(name: str, index: int, alone: MultiplierDynamics, p: np.ndarray) -> _Watched:
    def gap(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(alone.form.residuals(q, q_dot, t, p)[0][0]) + RECONTACT_TOLERANCE

    return _Watched(name, index, False, gap)
