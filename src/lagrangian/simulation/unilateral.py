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
* Impact: when an inactive constraint's g becomes negative (below -RECONTACT_TOLERANCE,
  which absorbs the integration error right after a release, where g grows like
  (t - t_release)^3), the velocities jump by the impulsive Lagrange equations with Newton's
  law of restitution (:mod:`lagrangian.simulation.impacts`), every unilateral constraint
  touching there resolved together; an Event ``"impact <names>"`` and an
  :class:`~lagrangian.simulation.trajectory.Impact` are recorded.  The contacts that took an
  impulse and do not bounce stay active (plastic, e = 0); a bounce that would rise less than
  the contact tolerance ends the accumulation of ever smaller bounces (a ball with e < 1
  bounces infinitely often in finite time): the contact persists from there, an Event
  ``"rest <name>"``.  A constraint with no coefficient of restitution cannot take an impact:
  the run stops there with status "failed" and a message saying so.

The active set is the mode of a hybrid motion, a frozen set of constraint indices: the
piecewise loop (:mod:`lagrangian.simulation.integrators.piecewise`) integrates each piece with
the multiplier form of its active set (:class:`lagrangian.simulation.dynamics.MultiplierDynamics`)
and joins the pieces into one Integration: the states, the multipliers of every constraint
(NaN while a unilateral one is inactive) and the residuals of the active constraints.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable

import numpy as np
import sympy as sp

from lagrangian.constraints import constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.model.constraints import Constraint, Holonomic, Unilateral, label, statement
from lagrangian.numerics.constrained import CompiledConstrained, compile_constrained
from lagrangian.simulation.dynamics import INITIAL_TOLERANCE, MultiplierDynamics
from lagrangian.simulation.impacts import ImpactRecord, resolve
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.piecewise import Guard, Jump, Record
from lagrangian.simulation.integrators.protocol import Dynamics, Integration
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

    def piece(self, active: set[int] | frozenset[int]) -> MultiplierDynamics:
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

    def guards(self, mode: frozenset[int], piece: Dynamics) -> list[_Watched]:
        """The terminal events of a piece: each active unilateral multiplier turning to the
        pulling side (a release), each inactive one's g going below zero (a re-contact)."""
        assert isinstance(piece, MultiplierDynamics)
        order = sorted(mode)
        watched = [
            _release(f"release {self.tag(i)}", i, k, piece)
            for k, i in enumerate(order)
            if i in self.one_sided
        ]
        for i in self.one_sided:
            if i not in mode:
                watched.append(_contact(f"contact {self.tag(i)}", i, self.piece({i}), self.p))
        return watched

    def tag(self, i: int) -> str:
        return self.system.constraints[i].name or str(i)

    # -- the Hybrid protocol of the piecewise loop ----------------------------------------
    def initial_mode(self, t: float, x: np.ndarray) -> tuple[frozenset[int], list[Record]]:
        n = len(self.eom.coordinates)
        return frozenset(self.active_at(t, x[:n], x[n:])), []

    def settle(
        self, mode: frozenset[int], t: float, x: np.ndarray
    ) -> tuple[frozenset[int], list[Record]]:
        """Release, one after another, the active unilateral constraints whose multiplier
        pulls at (t, x) (the most negative first)."""
        released: list[Record] = []
        while (pulling := self.pulling(mode, t, x)) is not None:
            mode = mode - {pulling}
            released.append((f"release {self.tag(pulling)}", t, np.array(x, dtype=float)))
        return mode, released

    def pulling(self, mode: frozenset[int], t: float, x: np.ndarray) -> int | None:
        """The active unilateral constraint whose multiplier pulls at (t, x) (the most
        negative one), or None."""
        n = len(self.eom.coordinates)
        lam = self.piece(set(mode)).multipliers(t, x[:n], x[n:])
        pulling = [(lam[k], i) for k, i in enumerate(sorted(mode)) if i in self.one_sided]
        pulling = [pair for pair in pulling if pair[0] < 0]
        return min(pulling)[1] if pulling else None

    def transition(self, mode: frozenset[int], guard: Guard, t: float, x: np.ndarray) -> Jump:
        """A release drops the constraint; a contact is an impact where the constraint has a
        coefficient of restitution, and ends the run where it has none."""
        assert isinstance(guard, _Watched)
        if guard.release:
            return Jump(mode - {guard.index}, x, guard.__name__)
        if self.restitution(guard.index) is None:
            return Jump(mode, x, guard.__name__, _unmodelled(self.system, guard.index, t))
        return self.impact(mode, guard.index, t, x)

    def restitution(self, i: int) -> float | None:
        """The coefficient of restitution of constraint i at the run's parameters, or None."""
        return self.restitutions[i]

    @functools.cached_property
    def restitutions(self) -> tuple[float | None, ...]:
        """Every constraint's coefficient of restitution at the run's parameters (None for
        none), evaluated once per run; SimulationInputError for one outside [0, 1]."""
        values = {s: sp.Float(v) for s, v in zip(self.eom.parameters, self.p)}
        found: list[float | None] = []
        for i, constraint in enumerate(self.system.constraints):
            e = getattr(constraint, "restitution", None)
            value = None if e is None else float(e.xreplace(values))
            if value is not None and not 0.0 <= value <= 1.0:
                raise SimulationInputError(
                    f"the coefficient of restitution of {label(i, constraint)}, {e} = "
                    f"{value:g}, is not in [0, 1]: give parameters that make it one"
                )
            found.append(value)
        return tuple(found)

    def impact(self, mode: frozenset[int], index: int, t: float, x: np.ndarray) -> Jump:
        """The velocity jump of an impact on constraint ``index`` at (t, x), resolved with
        every unilateral constraint touching there (:func:`lagrangian.simulation.impacts.
        resolve`), and the mode after: the contacts that took an impulse and do not bounce
        stay active, the others are released."""
        n, m = len(self.eom.coordinates), len(self.system.constraints)
        q, v = x[:n], x[n:]
        every = self.piece(set(range(m)))
        parts = every.form.parts(q, v, t, self.p)
        touching = self.touching(mode, index, parts.h, parts.rates)
        missing = [i for i in touching if i not in mode and self.restitution(i) is None]
        if missing:
            return Jump(mode, x, f"contact {self.tag(missing[0])}",
                        _unmodelled(self.system, missing[0], t))  # fmt: skip
        bilateral = [i for i in range(m) if i not in self.one_sided]
        e = {i: 0.0 if i in mode else float(self.restitution(i) or 0.0) for i in touching}
        after, impulses = resolve(parts.mass, parts.jacobian, parts.rates, bilateral,
                                  touching, [e[i] for i in touching], v)  # fmt: skip
        rest = [i for i in touching if e[i] > 0 and impulses[i] > 0
                and self.bounce_height(mode, i, t, q, after) <= RECONTACT_TOLERANCE]  # fmt: skip
        if rest:  # a bounce lower than the contact tolerance: the contact persists (Zeno)
            e.update(dict.fromkeys(rest, 0.0))
            after, impulses = resolve(parts.mass, parts.jacobian, parts.rates, bilateral,
                                      touching, [e[i] for i in touching], v)  # fmt: skip
        rates = parts.jacobian @ after + parts.rates - parts.jacobian @ v
        scale = float(np.max(np.abs(parts.rates), initial=0.0)) + 1e-300
        staying = {i for i in touching if abs(rates[i]) <= 1e-9 * scale
                   and (impulses[i] > 0 or i in mode)}  # fmt: skip
        after_mode = frozenset(set(bilateral) | staying)
        state = np.concatenate((q, after))
        if staying - mode:  # onto the contacts that persist (the impact was met at g = -tol)
            state = np.concatenate(self.piece(after_mode).form.project(q, after, t, self.p))
        hit = tuple(i for i in touching if impulses[i] > 0)
        names = tuple(self.tag(i) for i in hit)
        record = ImpactRecord(t, names, tuple(float(impulses[i]) for i in hit), np.array(x),
                              state, tuple(self.tag(i) for i in rest))  # fmt: skip
        also = tuple(f"rest {self.tag(i)}" for i in rest)
        return Jump(after_mode, state, f"impact {', '.join(names)}", impact=record, also=also)

    def touching(
        self, mode: frozenset[int], index: int, h: np.ndarray, rates: np.ndarray
    ) -> list[int]:
        """The unilateral constraints an impact on ``index`` involves: it, those in contact,
        and every other one at g ~ 0 that is closing."""
        band = 2 * RECONTACT_TOLERANCE
        near = {i for i in self.one_sided if abs(h[i]) <= band and rates[i] < 0}
        return sorted({index} | (set(self.one_sided) & mode) | near)

    def bounce_height(
        self, mode: frozenset[int], i: int, t: float, q: np.ndarray, v: np.ndarray
    ) -> float:
        """How high constraint i rises after leaving with g_dot = a_i v + b_i > 0 under the
        motion of ``mode`` (i released): g_dot^2 / (2 |g_ddot|), infinite when g_ddot >= 0
        (it does not come back).  g_ddot = a_i q_ddot - gamma_i (A q_ddot = gamma is the
        constraints' second derivative held at zero)."""
        free = self.piece(set(mode) - {i})
        q_ddot = free.field(t, np.concatenate((q, v)))[len(q) :]
        parts = self.piece(set(range(len(self.system.constraints)))).form.parts(q, v, t, self.p)
        g_dot = float(parts.rates[i])
        g_ddot = float(parts.jacobian[i] @ q_ddot - parts.gamma[i])
        return np.inf if g_ddot >= 0 else g_dot**2 / (2 * -g_ddot)

    def completed(self, mode: frozenset[int], piece: Dynamics, run: Integration) -> Integration:
        """A piece with the multipliers of every constraint (NaN for the inactive ones) and
        the residual of the active ones."""
        assert isinstance(piece, MultiplierDynamics)
        n = len(self.eom.coordinates)
        multipliers, residual = piece.constraint_rows(run.t, run.x[:, :n], run.x[:, n:])
        full = np.full((len(run.t), len(self.multiplier_names)), np.nan)
        full[:, sorted(mode)] = multipliers
        return dataclasses.replace(run, multipliers=full, constraint_residual=residual)


def _unmodelled(system: System, index: int, t: float) -> str:
    """Why a run stops at a contact whose constraint has no coefficient of restitution."""
    constraint = system.constraints[index]
    return (
        f"the unilateral constraint {label(index, constraint)}, {statement(constraint)}, is "
        f"reached at t = {t:.6g}: an impact, and it has no coefficient of restitution, so the "
        "integration stops there (give it one, e.g. restitution: 1 for an elastic impact)"
    )


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
            f"{g_dot:.3g} < 0 at g = 0): an impact at the start; start just outside it "
            "(g > 0), where the impact is resolved by its coefficient of restitution."
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
