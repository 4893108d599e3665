"""simulate_unilateral: the motion under unilateral constraints g(q, t) >= 0 (issue 4 item 5).

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

The pieces are concatenated: t, q, q_dot, energy, the multipliers of every constraint
(NaN while a unilateral one is inactive) and the residuals of the active constraints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np

from lagrangian.constraints import constrained_equations
from lagrangian.constraints.multipliers import multiplier_symbols
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.model.constraints import Constraint, Holonomic, Unilateral, label, statement
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.constrained import CompiledConstrained, compile_constrained
from lagrangian.simulation.constrained_run import checked_initial, multipliers_along
from lagrangian.simulation.constrained_start import INITIAL_TOLERANCE
from lagrangian.simulation.events import EventFunction, EventWatch
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.run import solver_starter, state_by_name, trajectory_of
from lagrangian.simulation.stepping import integrate
from lagrangian.simulation.trajectory import Event, Trajectory

#: How far below zero an inactive constraint's g may go before it counts as a re-contact.
RECONTACT_TOLERANCE = 1e-8


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


def simulate_unilateral(
    system: System,
    eom: EquationsOfMotion,
    compiled: CompiledEquations,
    inputs: Inputs,
    *,
    events: Sequence[EventFunction],
    progress: Callable[[float], None] | None,
    alpha: float,
    beta: float,
    project_initial: bool,
) -> Trajectory:
    """The motion of ``system`` with its unilateral constraints (see the module docstring)."""
    constraints = tuple(system.constraints)
    one_sided = [i for i, c in enumerate(constraints) if isinstance(c, Unilateral)]
    forms = _ActiveSets(eom, constraints)
    alone = {i: forms.compiled((i,)) for i in one_sided}
    n, p, t0 = len(compiled.coordinates), inputs.p, inputs.t_span[0]
    q0, qd0 = inputs.x0[:n], inputs.x0[n:]
    active = {i for i in range(len(constraints)) if i not in alone}
    active |= {i for i in one_sided if _touching(i, constraints[i], alone[i], q0, qd0, t0, p)}

    def tag(i: int) -> str:
        return constraints[i].name or str(i)

    order = sorted(active)
    current = checked_initial(
        system.replace(constraints=[_bilateral(constraints[i]) for i in order]),
        forms.compiled(tuple(order)),
        inputs,
        project_initial,
    )
    t1 = inputs.t_span[1]
    names = tuple(s.name for s in multiplier_symbols(len(constraints)))
    pieces: list[Trajectory] = []
    found: list[Event] = []
    counts = np.zeros(len(events), dtype=int)
    status, message = "success", ""
    while True:
        order = sorted(active)
        numeric = forms.compiled(tuple(order))
        t_start, x = current.t_span[0], current.x0
        lam = numeric.accelerations(x[:n], x[n:], t_start, p, alpha, beta)[1]
        pulling = [(lam[k], i) for k, i in enumerate(order) if i in alone and lam[k] < 0]
        if pulling:  # released at once, before integrating this piece
            i = min(pulling)[1]
            active.discard(i)
            found.append(
                Event(f"release {tag(i)}", t_start, state_by_name(compiled, t_start, x, p))
            )
            continue
        watched = [
            _release(f"release {tag(i)}", i, k, numeric, p, alpha, beta)
            for k, i in enumerate(order)
            if i in alone
        ] + [_contact(f"contact {tag(i)}", i, alone[i], p) for i in one_sided if i not in active]
        watch = EventWatch([*events, *watched], _unpack(n))
        watch.counts[: len(events)] = counts

        def field(t: float, x: np.ndarray, numeric: CompiledConstrained = numeric) -> np.ndarray:
            q_ddot, _ = numeric.accelerations(x[:n], x[n:], t, p, alpha, beta)
            return np.concatenate((x[n:], q_ddot))

        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            run = integrate(
                solver_starter(field, current), t_start, x, current.t_out, watch, progress
            )
        counts = watch.counts[: len(events)].copy()
        piece = trajectory_of(compiled, current, run, watch)
        multipliers, residual = multipliers_along(numeric, piece, p, alpha, beta)
        full = np.full((len(piece.t), len(constraints)), np.nan)
        full[:, order] = multipliers
        pieces.append(
            dataclasses.replace(
                piece,
                multipliers=full,
                multiplier_names=names,
                constraint_residual=residual,
                events=(),
            )
        )
        found.extend(piece.events)
        message = piece.message
        if run.failure is not None:
            status = "failed"
            break
        if run.terminal is None or run.terminal < len(events):
            break
        event = watched[run.terminal - len(events)]
        t_event, x_event = run.events[-1][1], run.events[-1][2]
        if not event.release:
            status = "failed"
            message = (
                f"The unilateral constraint {label(event.index, constraints[event.index])}, "
                f"{statement(constraints[event.index])}, is violated again at t = "
                f"{t_event:.6g}: impacts are not modelled, so the integration stops there."
            )
            break
        active.discard(event.index)
        if t_event >= t1:
            break
        t_out = current.t_out
        current = dataclasses.replace(
            current,
            x0=np.array(x_event, dtype=float),
            t_span=(t_event, t1),
            t_out=None if t_out is None else t_out[t_out >= t_event],
        )
    return _joined(pieces, found, status, message)


class _ActiveSets:
    """The compiled multiplier form of each set of active constraints, compiled once per set
    (a run that releases and keeps constraints meets the same sets again)."""

    def __init__(self, eom: EquationsOfMotion, constraints: Sequence[Constraint]) -> None:
        self.eom, self.constraints = eom, tuple(constraints)
        self._compiled: dict[tuple[int, ...], CompiledConstrained] = {}

    def compiled(self, active: tuple[int, ...]) -> CompiledConstrained:
        """The multiplier form with the constraints ``active`` (indices, in order)."""
        if active not in self._compiled:
            chosen = [self.constraints[i] for i in active]
            self._compiled[active] = compile_constrained(constrained_equations(self.eom, chosen))
        return self._compiled[active]


def _bilateral(constraint: Constraint) -> Constraint:
    """An active unilateral constraint as the holonomic one it acts like."""
    if isinstance(constraint, Unilateral):
        return Holonomic(constraint.expression, name=constraint.name)
    return constraint


def _unpack(n: int) -> Callable[[float, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    return lambda t, x: (x[:n], x[n:])


def _touching(
    index: int,
    constraint: Constraint,
    numeric: CompiledConstrained,
    q: np.ndarray,
    qd: np.ndarray,
    t: float,
    p: np.ndarray,
) -> bool:
    """Whether a unilateral constraint starts active; raise when it is violated or hit."""
    h, c = numeric.residuals(q, qd, t, p)
    g, g_dot = float(h[0]), float(c[0])
    where = f"{label(index, constraint)}, {statement(constraint)}"
    if g < -INITIAL_TOLERANCE:
        raise SimulationError(
            f"The initial state violates the unilateral constraint {where}: g = {g:.3g} < 0."
        )
    if g > INITIAL_TOLERANCE or g_dot > INITIAL_TOLERANCE:
        return False
    if g_dot < -INITIAL_TOLERANCE:
        raise SimulationError(
            f"The initial state moves into the unilateral constraint {where} (dg/dt = "
            f"{g_dot:.3g} < 0 at g = 0): impacts are not modelled."
        )
    return True


def _release(
    name: str,
    index: int,
    k: int,
    numeric: CompiledConstrained,
    p: np.ndarray,
    alpha: float,
    beta: float,
) -> _Watched:
    def multiplier(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(numeric.accelerations(q, q_dot, t, p, alpha, beta)[1][k])

    return _Watched(name, index, True, multiplier)


def _contact(name: str, index: int, numeric: CompiledConstrained, p: np.ndarray) -> _Watched:
    def gap(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(numeric.residuals(q, q_dot, t, p)[0][0]) + RECONTACT_TOLERANCE

    return _Watched(name, index, False, gap)


def _joined(pieces: list[Trajectory], found: list[Event], status: str, message: str) -> Trajectory:
    """The pieces end to end (a row repeated at a junction is kept once)."""
    keep = [pieces[0]]
    for piece in pieces[1:]:
        later = piece.t > keep[-1].t[-1] if len(keep[-1].t) else np.ones(len(piece.t), bool)
        keep.append(_rows(piece, later))

    def stack(name: str) -> np.ndarray:
        return np.concatenate([getattr(piece, name) for piece in keep])

    first = keep[0]
    return dataclasses.replace(
        first,
        t=stack("t"),
        q=stack("q"),
        q_dot=stack("q_dot"),
        energy=stack("energy"),
        energy_function=None if first.energy_function is None else stack("energy_function"),
        events=tuple(found),
        status=status,
        message=message,
        multipliers=stack("multipliers"),
        constraint_residual=stack("constraint_residual"),
    )


def _rows(piece: Trajectory, mask: np.ndarray) -> Trajectory:
    def pick(value: np.ndarray | None) -> np.ndarray | None:
        return None if value is None else value[mask]

    return dataclasses.replace(
        piece,
        t=piece.t[mask],
        q=piece.q[mask],
        q_dot=piece.q_dot[mask],
        energy=piece.energy[mask],
        energy_function=pick(piece.energy_function),
        multipliers=pick(piece.multipliers),
        constraint_residual=pick(piece.constraint_residual),
    )
