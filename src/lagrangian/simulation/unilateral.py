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
from typing import NamedTuple

import numpy as np
import sympy as sp

from lagrangian.constraints import constrained_equations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.model.constraints import Constraint, Holonomic, Unilateral, label, statement
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.constrained import CompiledConstrained, compile_constrained
from lagrangian.simulation.dynamics import (
    INITIAL_TOLERANCE,
    MultiplierDynamics,
    start_on_constraints,
)
from lagrangian.simulation.flight import Calendar, LoneImpacts, QuadraticGaps, quadratic_gaps
from lagrangian.simulation.impacts import ImpactRecord, resolve
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.piecewise import Guard, Jump, Record
from lagrangian.simulation.integrators.protocol import Dynamics, Integration
from lagrangian.symbolic.caches import IdentityCache

#: How far below zero an inactive constraint's g may go before it counts as a re-contact.
RECONTACT_TOLERANCE = 1e-8
#: Contacts the calendar finds within this time (relative to 1 + |t|) of an impact take
#: part in it (simultaneous impacts, as on a symmetric lattice).
SIMULTANEOUS = 1e-12

_FORMS: IdentityCache[EquationsOfMotion, dict[tuple[int, ...], CompiledConstrained]] = (
    IdentityCache()
)
_GAPS: IdentityCache[EquationsOfMotion, dict[bytes, QuadraticGaps | None]] = IdentityCache()
_MASSES: IdentityCache[EquationsOfMotion, dict[bytes, tuple[np.ndarray, np.ndarray]]] = (
    IdentityCache()
)
_RESTITUTIONS: IdentityCache[System, dict[bytes, tuple[float | None, ...]]] = IdentityCache()
_ACTIVE: IdentityCache[System, dict[tuple[int, ...], System]] = IdentityCache()


class _Watched:
    """An event function of this module: a multiplier (release) or a g (re-contact)."""

    terminal = True
    direction = -1.0

    def __init__(
        self, name: str, index: int, release: bool, function: Callable[..., float]
    ) -> None:
        self.__name__ = name
        self.index, self.release, self.function = index, release, function
        # an active contact's multiplier is constant where the acceleration is (a flight)
        self.constant_in_flight = release

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

    @functools.cached_property
    def one_sided(self) -> tuple[int, ...]:
        """The indices of the unilateral constraints."""
        return tuple(i for i, c in enumerate(self.system.constraints) if isinstance(c, Unilateral))

    @functools.cached_property
    def unilateral(self) -> frozenset[int]:
        """The indices of the unilateral constraints, as a set."""
        return frozenset(self.one_sided)

    @functools.cached_property
    def bilateral(self) -> frozenset[int]:
        """The indices of the holonomic and velocity constraints (always active)."""
        return frozenset(range(len(self.system.constraints))) - self.unilateral

    @functools.cached_property
    def gaps(self) -> QuadraticGaps | None:
        """The constraints as polynomial gaps (:mod:`lagrangian.simulation.flight`) when the
        motion between impacts can be polynomial in t: every constraint unilateral and of
        degree <= 2 in q alone, the mass matrix and the forces constant; else None.  Found
        once per equations and parameter values."""
        found = _GAPS.get(self.eom, lambda _: {})
        key = self.p.tobytes()
        if key not in found:
            found[key] = self._polynomial_gaps()
        return found[key]

    def _polynomial_gaps(self) -> QuadraticGaps | None:
        eom, constraints = self.eom, self.system.constraints
        if len(self.one_sided) != len(constraints) or not constraints:
            return None
        if any(order != 2 for order in eom.coordinate_orders.values()):
            return None
        state = {*eom.coordinates, *eom.velocities, eom.time}
        if (eom.mass_matrix.free_symbols | eom.forcing.free_symbols) & state:
            return None
        values = {s: sp.Float(v) for s, v in zip(eom.parameters, self.p)}
        expressions = [c.expression for c in constraints]
        return quadratic_gaps(expressions, range(len(constraints)), eom.coordinates, values)

    @functools.cached_property
    def calendar(self) -> Calendar:
        """The next contact time of every gap along the run's flights (gaps only)."""
        assert self.gaps is not None
        return Calendar(self.gaps)

    @functools.cached_property
    def constant_mass(self) -> tuple[np.ndarray, np.ndarray]:
        """M and M^-1 of a system whose mass matrix is constant (gaps only), found once per
        equations and parameter values."""
        found = _MASSES.get(self.eom, lambda _: {})
        key = self.p.tobytes()
        if key not in found:
            zero = np.zeros(len(self.eom.coordinates))
            # the equations' own M (compiled for the start's check), not the multiplier
            # form's: that one, of thousands of contacts, compiles for minutes
            mass = np.asarray(compile_equations(self.eom).mass_matrix(zero, 0.0, self.p))
            diagonal = np.count_nonzero(mass - np.diag(np.diagonal(mass))) == 0
            inverse = np.diag(1 / np.diagonal(mass)) if diagonal else np.linalg.inv(mass)
            found[key] = (mass, inverse)
        return found[key]

    @functools.cached_property
    def lone_impacts(self) -> LoneImpacts | None:
        """What a flight needs to resolve a lone contact's impact itself (gaps only): M^-1,
        every contact's restitution and name; None when a restitution is out of range (the
        impact that meets it says so)."""
        try:
            found = self.restitutions
        except SimulationInputError:
            return None
        restitution = np.array([np.nan if e is None else e for e in found], dtype=float)
        labels = tuple(self.tag(i) for i in range(len(found)))
        inverse = self.constant_mass[1]
        return LoneImpacts(inverse, restitution, labels, SIMULTANEOUS, RECONTACT_TOLERANCE)

    @functools.cached_property
    def contact_guards(self) -> dict[frozenset[int], _Contacts]:
        """The contact guard of each mode met in a run (with gaps), made once per mode."""
        return {}

    @functools.cached_property
    def accelerations(self) -> dict[frozenset[int], np.ndarray]:
        """The constant acceleration of each mode that moves in closed form, found once."""
        return {}

    def flies(self, mode: frozenset[int]) -> bool:
        """Whether ``mode`` moves with a constant acceleration: gaps, and no active contact
        but affine ones held without Baumgarte's terms (which depend on the state)."""
        if self.gaps is None:
            return False
        affine = self.gaps.affine
        return not mode or (self.gains == (0.0, 0.0) and all(affine[i] for i in mode))

    def flight_acceleration(
        self, mode: frozenset[int], piece: Dynamics, t: float, x: np.ndarray
    ) -> np.ndarray | None:
        """The constant acceleration of ``mode``, or None when it does not fly."""
        if not self.flies(mode):
            return None
        if mode not in self.accelerations:
            if mode:
                self.accelerations[mode] = piece.field(t, x)[len(x) // 2 :]
            else:  # no contact: M^-1 forcing, both constant
                zero = np.zeros(len(x) // 2)
                forcing = compile_equations(self.eom).forcing(zero, zero, 0.0, self.p)
                self.accelerations[mode] = self.constant_mass[1] @ np.asarray(forcing, float)
        return self.accelerations[mode]

    def piece(self, active: set[int] | frozenset[int]) -> MultiplierDynamics:
        """The multiplier form of the ``active`` constraints (the unilateral ones as the
        holonomic constraints they act like), compiled once per set and equations."""
        made = self.pieces.get(frozenset(active))
        if made is not None:
            return made
        order = tuple(sorted(active))
        forms = _FORMS.get(self.eom, lambda _: {})
        if order not in forms:
            chosen = [_bilateral(self.system.constraints[i]) for i in order]
            forms[order] = compile_constrained(constrained_equations(self.eom, chosen))
        made = MultiplierDynamics(self.system, forms[order], self.p, self.gains)
        self.pieces[frozenset(active)] = made
        return made

    @functools.cached_property
    def pieces(self) -> dict[frozenset[int], MultiplierDynamics]:
        """The multiplier form of each active set met in a run, made once per set."""
        return {}

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
        active = tuple(sorted(self.active_at(t0, inputs.x0[:n], inputs.x0[n:])))
        if self.gaps is not None:  # the residuals of the active gaps, without compiling
            coordinates = tuple(q.name for q in self.eom.coordinates)
            return start_on_constraints(self.gap_residual(active), self.with_active(active),
                                        coordinates, inputs, project_initial)  # fmt: skip
        piece = dataclasses.replace(self.piece(set(active)), system=self.with_active(active))
        return piece.start(inputs, project_initial)

    def gap_residual(
        self, active: tuple[int, ...]
    ) -> Callable[[float, np.ndarray, np.ndarray], float]:
        """The largest residual |g|, |g_dot| of the ``active`` gaps at (t, q, q_dot)."""
        rows = np.array(active, dtype=np.intp)

        def residual(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
            assert self.gaps is not None
            h, gradients = self.gaps.values_and_gradients(rows, q)
            c = gradients @ q_dot
            return float(np.max(np.abs(np.concatenate((h, c))), initial=0.0))

        return residual

    def with_active(self, active: tuple[int, ...]) -> System:
        """The System with the ``active`` constraints only, the unilateral ones as holonomic:
        made once per System and active set (validating a System of thousands of contacts
        costs more than a run of hundreds of impacts)."""
        made = _ACTIVE.get(self.system, lambda _: {})
        if active not in made:
            chosen = [_bilateral(self.system.constraints[i]) for i in active]
            made[active] = self.system.replace(constraints=chosen)
        return made[active]

    def active_at(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> set[int]:
        """The constraints active at a start: the bilateral ones, and each unilateral one
        touching (g ~ 0, dg/dt ~ 0); SimulationInputError when one is violated or hit."""
        constraints = self.system.constraints
        active = set(self.bilateral)
        if self.gaps is not None:  # every gap at once; only those within the band are looked at
            hs, _ = self.gaps.values_and_gradients(np.arange(len(constraints)), q, rows=False)
            near = np.flatnonzero(hs <= INITIAL_TOLERANCE)
            _, gradients = self.gaps.values_and_gradients(near, q)
            cs = gradients @ q_dot
            found = list(zip(near.tolist(), hs[near].tolist(), cs.tolist()))
        else:
            found = []
            for i in self.one_sided:
                h, c = self.piece({i}).form.residuals(q, q_dot, t, self.p)
                found.append((i, float(h[0]), float(c[0])))
        active.update(i for i, h, c in found if _touching(i, constraints[i], h, c))
        return active

    def guards(self, mode: frozenset[int], piece: Dynamics) -> list[_Watched | _Contacts]:
        """The terminal events of a piece: each active unilateral multiplier turning to the
        pulling side (a release), each inactive one's g going below zero (a re-contact; with
        gaps, one guard for all of them, found in closed form where the mode flies)."""
        assert isinstance(piece, MultiplierDynamics)
        order = sorted(mode)
        watched: list[_Watched | _Contacts] = [
            _release(f"release {self.tag(i)}", i, k, piece)
            for k, i in enumerate(order)
            if i in self.unilateral
        ]
        if self.gaps is not None:
            if mode not in self.contact_guards:
                self.contact_guards[mode] = _Contacts(self, mode)
            return [*watched, self.contact_guards[mode]]
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
        if not mode:
            return None
        lam = self.piece(set(mode)).multipliers(t, x[:n], x[n:])
        pulling = [(lam[k], i) for k, i in enumerate(sorted(mode)) if i in self.unilateral]
        pulling = [pair for pair in pulling if pair[0] < 0]
        return min(pulling)[1] if pulling else None

    def transition(self, mode: frozenset[int], guard: Guard, t: float, x: np.ndarray) -> Jump:
        """A release drops the constraint; a contact is an impact where the constraint has a
        coefficient of restitution, and ends the run where it has none."""
        if isinstance(guard, _Contacts):
            index = guard.reached(t, x)
        else:
            assert isinstance(guard, _Watched)
            if guard.release:
                return Jump(mode - {guard.index}, x, guard.__name__)
            index = guard.index
        if self.restitution(index) is None:
            return Jump(mode, x, f"contact {self.tag(index)}",
                        _unmodelled(self.system, index, t))  # fmt: skip
        return self.impact(mode, index, t, x)

    def restitution(self, i: int) -> float | None:
        """The coefficient of restitution of constraint i at the run's parameters, or None."""
        return self.restitutions[i]

    @functools.cached_property
    def restitutions(self) -> tuple[float | None, ...]:
        """Every constraint's coefficient of restitution at the run's parameters (None for
        none), evaluated once per System and parameter values; SimulationInputError for one
        outside [0, 1]."""
        found = _RESTITUTIONS.get(self.system, lambda _: {})
        key = self.p.tobytes()
        if key not in found:
            found[key] = self._restitutions()
        return found[key]

    def _restitutions(self) -> tuple[float | None, ...]:
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
        n = len(self.eom.coordinates)
        q, v = x[:n], x[n:]
        near = self.near(mode, index, t, q, v)
        at = {row: k for k, row in enumerate(near.rows)}
        touching = self.touching(mode, index, near)
        missing = [i for i in touching if i not in mode and self.restitution(i) is None]
        if missing:
            return Jump(mode, x, f"contact {self.tag(missing[0])}",
                        _unmodelled(self.system, missing[0], t))  # fmt: skip
        bilateral = [i for i in near.rows if i not in self.unilateral]
        e = {i: 0.0 if i in mode else float(self.restitution(i) or 0.0) for i in touching}

        def solved() -> tuple[np.ndarray, np.ndarray]:
            return resolve(near.mass, near.jacobian, near.rates, [at[i] for i in bilateral],
                           [at[i] for i in touching], [e[i] for i in touching], v,
                           near.inverse_mass)  # fmt: skip

        after, impulses = solved()
        rest = [i for i in touching if e[i] > 0 and impulses[at[i]] > 0
                and self.bounce_height(mode, i, t, q, after) <= RECONTACT_TOLERANCE]  # fmt: skip
        if rest:  # a bounce lower than the contact tolerance: the contact persists (Zeno)
            e.update(dict.fromkeys(rest, 0.0))
            after, impulses = solved()
        rates = near.jacobian @ (after - v) + near.rates
        scale = float(np.max(np.abs(near.rates), initial=0.0)) + 1e-300
        staying = {i for i in touching if abs(rates[at[i]]) <= 1e-9 * scale
                   and (impulses[at[i]] > 0 or i in mode)}  # fmt: skip
        after_mode = self.bilateral | staying
        state = np.concatenate((q, after))
        if staying - mode:  # onto the contacts that persist (the impact was met at g = -tol)
            state = np.concatenate(self.piece(after_mode).form.project(q, after, t, self.p))
        hit = tuple(i for i in touching if impulses[at[i]] > 0)
        names = tuple(self.tag(i) for i in hit)
        record = ImpactRecord(t, names, tuple(float(impulses[at[i]]) for i in hit), np.array(x),
                              state, tuple(self.tag(i) for i in rest))  # fmt: skip
        also = tuple(f"rest {self.tag(i)}" for i in rest)
        return Jump(after_mode, state, f"impact {', '.join(names)}", impact=record, also=also)

    def near(
        self, mode: frozenset[int], index: int, t: float, q: np.ndarray, v: np.ndarray
    ) -> _Near:
        """The constraints an impact on ``index`` may involve, with M, their Jacobian rows,
        rates and gaps: every constraint; with gaps, only ``index``, the active ones and those
        the calendar (or, after a stepped piece, the contact band) finds touching now."""
        if self.gaps is None:
            m = len(self.system.constraints)
            parts = self.piece(set(range(m))).form.parts(q, v, t, self.p)
            return _Near(list(range(m)), parts.mass, parts.jacobian, parts.rates, parts.h, None)
        calendar = self.calendar
        if calendar.hit[0] == t:
            soon = np.flatnonzero(calendar.times <= t + SIMULTANEOUS * (1 + abs(t)))
        else:
            every = np.arange(len(self.system.constraints))
            soon = np.flatnonzero(np.abs(self.gaps.values(every, q)) <= 2 * RECONTACT_TOLERANCE)
        rows = sorted({index, *mode, *soon.tolist()})
        h, jacobian = self.gaps.values_and_gradients(np.array(rows), q)
        mass, inverse = self.constant_mass
        return _Near(rows, mass, jacobian, jacobian @ v, h, inverse)

    def touching(self, mode: frozenset[int], index: int, near: _Near) -> list[int]:
        """The unilateral constraints an impact on ``index`` involves: it, those in contact,
        and every other one at g ~ 0 that is closing."""
        band = 2 * RECONTACT_TOLERANCE
        closing = {row for row, h, rate in zip(near.rows, near.h, near.rates)
                   if row in self.unilateral and abs(h) <= band and rate < 0}  # fmt: skip
        return sorted({index} | (self.unilateral & mode) | closing)

    def bounce_height(
        self, mode: frozenset[int], i: int, t: float, q: np.ndarray, v: np.ndarray
    ) -> float:
        """How high constraint i rises after leaving with g_dot = a_i v + b_i > 0 under the
        motion of ``mode`` (i released): g_dot^2 / (2 |g_ddot|), infinite when g_ddot >= 0
        (it does not come back).  g_ddot = a_i q_ddot - gamma_i (A q_ddot = gamma is the
        constraints' second derivative held at zero)."""
        released = frozenset(mode - {i})
        q_ddot = self.accelerations.get(released)  # a flight's, found once per mode
        if q_ddot is None:
            free = self.piece(released)
            x = np.concatenate((q, v))
            flying = self.flight_acceleration(released, free, t, x)
            q_ddot = flying if flying is not None else free.field(t, x)[len(q) :]
        if self.gaps is not None:  # g along q + v s + q_ddot s^2/2: g_dot = c1, g_ddot = 2 c2
            _, c1, c2, _, _ = self.gaps.along(np.array([i]), q, v, q_ddot)
            g_dot, g_ddot = float(c1[0]), float(2 * c2[0])
        else:
            m = len(self.system.constraints)
            parts = self.piece(set(range(m))).form.parts(q, v, t, self.p)
            g_dot = float(parts.rates[i])
            g_ddot = float(parts.jacobian[i] @ q_ddot - parts.gamma[i])
        return np.inf if g_ddot >= 0 else g_dot**2 / (2 * -g_ddot)

    def completed(self, mode: frozenset[int], piece: Dynamics, run: Integration) -> Integration:
        """A piece with the multipliers of every constraint (NaN for the inactive ones) and
        the residual of the active ones."""
        assert isinstance(piece, MultiplierDynamics)
        n = len(self.eom.coordinates)
        full = np.full((len(run.t), len(self.multiplier_names)), np.nan)
        if not mode:  # no constraint active: no multiplier, no residual
            residual = np.zeros(len(run.t))
            return dataclasses.replace(run, multipliers=full, constraint_residual=residual)
        multipliers, residual = piece.constraint_rows(run.t, run.x[:, :n], run.x[:, n:])
        full[:, sorted(mode)] = multipliers
        return dataclasses.replace(run, multipliers=full, constraint_residual=residual)


class _Near(NamedTuple):
    """The constraints an impact may involve (``rows``, indices in the System's list) with the
    mass matrix, their Jacobian rows, rates g_dot, gaps g, and M^-1 when it is constant."""

    rows: list[int]
    mass: np.ndarray
    jacobian: np.ndarray
    rates: np.ndarray
    h: np.ndarray
    inverse_mass: np.ndarray | None


class _Contacts:
    """The one contact guard of a mode of a system with gaps: the least gap of the inactive
    contacts (plus the contact tolerance), whose first zero is the first contact.  A
    :class:`~lagrangian.simulation.flight.FlightGuard`: where the mode flies the calendar finds
    that zero in closed form; else it is stepped like any event function."""

    terminal = True
    direction = -1.0
    __name__ = "contact"

    def __init__(self, dynamics: UnilateralDynamics, mode: frozenset[int]) -> None:
        assert dynamics.gaps is not None
        self.dynamics, self.mode, self.gaps = dynamics, mode, dynamics.gaps
        self.calendar = dynamics.calendar
        self.excluded = np.zeros(len(dynamics.system.constraints), dtype=bool)
        self.excluded[list(mode)] = True
        self.open = np.flatnonzero(~self.excluded)
        # without active contacts a flight resolves the lone impacts itself (flight.py)
        self.lone_impacts = None if mode else dynamics.lone_impacts

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        values = self.gaps.values(self.open, q)
        return float(np.min(values, initial=np.inf)) + RECONTACT_TOLERANCE

    def acceleration(self, piece: Dynamics, t: float, x: np.ndarray) -> np.ndarray | None:
        return self.dynamics.flight_acceleration(self.mode, piece, t, x)

    def reached(self, t: float, x: np.ndarray) -> int:
        """The constraint whose contact ends the piece at (t, x): the calendar's, else the
        least gap."""
        time, gap = self.calendar.hit
        if time == t and gap >= 0:
            return gap
        values = self.gaps.values(self.open, x[: len(x) // 2])
        return int(self.open[np.argmin(values)])


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
    """Whether a unilateral constraint starts active; raise when it is violated or hit.  A
    state just after an impact, within the contact band and leaving, starts inactive (the
    start of a return map on the impact's section)."""
    if -2 * RECONTACT_TOLERANCE <= g < -INITIAL_TOLERANCE and g_dot > INITIAL_TOLERANCE:
        return False
    if g < -INITIAL_TOLERANCE:
        raise SimulationInputError(
            f"The initial state violates the unilateral constraint "
            f"{label(index, constraint)}, {statement(constraint)}: g = {g:.3g} < 0."
        )
    if g > INITIAL_TOLERANCE or g_dot > INITIAL_TOLERANCE:
        return False
    if g_dot < -INITIAL_TOLERANCE:
        raise SimulationInputError(
            f"The initial state moves into the unilateral constraint "
            f"{label(index, constraint)}, {statement(constraint)} (dg/dt = {g_dot:.3g} < 0 at "
            "g = 0): an impact at the start; start just outside it (g > 0), where the impact "
            "is resolved by its coefficient of restitution."
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
