"""The piecewise loop: one run whose equations change at events (hybrid motion).

Some motions are smooth only piece by piece: a right-hand side with sign or Heaviside of the
state switches or slides at its switching surfaces (:mod:`lagrangian.simulation.switching`),
a unilateral constraint is active or released (:mod:`lagrangian.simulation.unilateral`).  Each
is a *hybrid system*: a set of **modes**, a smooth Dynamics per mode, **guards** (terminal
event functions, positive inside the mode) and a **transition** at a guard's zero that gives
the next mode and the state it starts from (the same state, or one reset by an impulse).  The
loop is written once, here, for all of them (Goebel, Sanfelice & Teel, *Hybrid Dynamical
Systems*, 2012, ch. 2; Filippov's sliding and Moreau's active sets are such systems):

    mode, start events = settle(initial_mode(t0, x0))
    repeat: integrate piece(mode) from (t, x) until a guard's zero, the end, a failure or a
            terminal event of the caller; at a guard: jump = transition(mode, guard, t, x);
            mode, x = settle(jump.mode, t, jump.state)

The run has one :class:`~lagrangian.simulation.integrators.budget.Budget`, handed to every
piece: its steps and wall time add up over the pieces (a motion switching without end stops
at the run's ``max_steps`` or ``max_wall_time``, never a fresh budget per piece).
The mode is a value (a frozen tuple or set): a hybrid Dynamics never changes.  The caller's
events are watched across every piece (their terminal counts carried over); the pieces are
joined into one :class:`~lagrangian.simulation.integrators.protocol.Integration` whose rows
are the output times asked for (not the rows of the transitions), whose events are the
caller's events and one event per transition, in the order of time.

>>> import numpy as np
>>> first = Integration(t=np.array([0.0, 1.0]), x=np.array([[0.0], [1.0]]), t_reached=1.0,
...                     x_reached=np.array([1.0]))
>>> second = Integration(t=np.array([1.0, 2.0]), x=np.array([[1.0], [0.5]]), t_reached=2.0,
...                      x_reached=np.array([0.5]))
>>> joined([first, second]).t
array([0., 1., 2.])
"""

from __future__ import annotations

import dataclasses
from collections.abc import Hashable, Sequence
from typing import Any, NamedTuple, Protocol, TypeVar

import numpy as np

from lagrangian.simulation.impacts import ImpactRecord
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.events import EventFunction, EventWatch
from lagrangian.simulation.integrators.protocol import Dynamics, Integration, Progress

Mode = TypeVar("Mode", bound=Hashable)
#: An event as the Integration records it: (name, time, state).
Record = tuple[str, float, np.ndarray]


class Guard(EventFunction, Protocol):
    """A terminal event function of a mode, positive inside it; its ``__name__`` is unique
    among the guards of the mode and is the name of the transition it starts."""

    __name__: str


class Jump(NamedTuple):
    """What a transition decided: the next ``mode`` and the ``state`` it starts from, the
    ``label`` of the event recorded at the transition ("" for none: a crossing passed by)
    and the ``also`` events at the same time, the ``impact`` when the velocities jump, or a
    ``failure`` that ends the run there (the mode and state are then those before it).
    ``disarm``: the guard is not watched during the first step of the next piece, which
    starts on its zero (a guard without the offset of a contact's tolerance).  ``stop``: the
    run ends with this transition, as at a terminal event named ``label`` (a return map
    stops on its section)."""

    mode: Any
    state: np.ndarray
    label: str
    failure: str | None = None
    impact: ImpactRecord | None = None
    also: tuple[str, ...] = ()
    disarm: bool = False
    stop: bool = False


class Hybrid(Protocol[Mode]):
    """A motion whose equations change at events (module docstring)."""

    def initial_mode(self, t: float, x: np.ndarray) -> tuple[Mode, list[Record]]:
        """The mode at the start, and the events of deciding it."""
        ...

    def settle(self, mode: Mode, t: float, x: np.ndarray) -> tuple[Mode, list[Record]]:
        """The mode a piece starting at (t, x) in ``mode`` really starts in (a constraint
        whose force would pull is released at once), and the events of that decision."""
        ...

    def piece(self, mode: Mode) -> Dynamics:
        """The smooth Dynamics of a mode."""
        ...

    def guards(self, mode: Mode, piece: Dynamics) -> Sequence[Guard]:
        """The terminal event functions that end a piece in ``mode``."""
        ...

    def transition(self, mode: Mode, guard: Guard, t: float, x: np.ndarray) -> Jump:
        """What happens at the zero of ``guard``, reached at (t, x) in ``mode``."""
        ...

    def completed(self, mode: Mode, piece: Dynamics, run: Integration) -> Integration:
        """A piece's Integration with what the hybrid adds to its rows (the multipliers of
        every constraint, NaN for the released ones)."""
        ...


class PieceIntegrator(Protocol):
    """What steps one piece of a hybrid motion: an Integrator that spends the run's
    ``budget`` (SciPy's solvers through the Python loop, or a flight in closed form)."""

    def run(
        self,
        dynamics: Any,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
        budget: Budget | None = None,
    ) -> Integration: ...


@dataclasses.dataclass(frozen=True)
class PiecewiseIntegrator:
    """The :class:`~lagrangian.simulation.integrators.protocol.Integrator` of every hybrid
    motion: its pieces stepped by ``inner`` (module docstring)."""

    inner: PieceIntegrator

    def run(
        self,
        dynamics: Hybrid[Any],
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        return integrate_piecewise(dynamics, inputs, watch, progress, self.inner)


def integrate_piecewise(
    hybrid: Hybrid[Any],
    inputs: Inputs,
    watch: EventWatch | None,
    progress: Progress | None,
    inner: PieceIntegrator,
    disarmed: str | None = None,
) -> Integration:
    """Integrate ``hybrid`` piece by piece with ``inner`` (module docstring) from the checked
    ``inputs``, watching the caller's events throughout.  ``disarmed`` names a guard not
    watched during the first step: the run starts on its zero (a return map on its section)."""
    own: Sequence[EventFunction] = watch.functions if watch is not None else ()
    counts = np.zeros(len(own), dtype=int)
    t0, t1 = inputs.t_span
    mode, entered = _settled(hybrid, *hybrid.initial_mode(t0, inputs.x0), t0, inputs.x0)
    pieces: list[Integration] = []
    current = inputs
    budget = Budget.of(inputs)  # the whole run's, spent by every piece
    while True:
        piece = hybrid.piece(mode)
        guards = list(hybrid.guards(mode, piece))
        piece_watch = EventWatch([*own, *guards], piece.unpack)
        piece_watch.counts[: len(own)] = counts
        piece_watch.disarmed = {
            len(own) + k for k, g in enumerate(guards) if g.__name__ == disarmed
        }
        run = inner.run(piece, current, piece_watch, progress, budget)
        counts = piece_watch.counts[: len(own)].copy()
        guard = next((g for g in guards if g.__name__ == run.stopped_by), None)
        mine = {g.__name__ for g in guards}
        stop = run.events[-1] if guard is not None else None
        theirs = (*entered, *(e for e in run.events if e[0] not in mine))
        run = hybrid.completed(mode, piece, run)
        if run.status != "success" or stop is None:
            pieces.append(_on_output_times(run, current, events=theirs))
            break
        spent = budget.used_up()
        if spent is not None:  # the guard ended the piece on the budget's last step
            _, t_stop, x_stop = stop
            ended = _on_output_times(run, current, events=theirs, failure=spent,
                                     t_reached=t_stop, x_reached=x_stop)  # fmt: skip
            pieces.append(ended)
            break
        _, t_jump, x_jump = stop
        jump = hybrid.transition(mode, guard, t_jump, x_jump)  # type: ignore[arg-type]
        if jump.failure is not None:  # the run ends at the guard, with its event
            failed = _failed_at(dataclasses.replace(run, events=theirs), stop, jump)
            pieces.append(_on_output_times(failed, current))
            break
        impacts = (*run.impacts, jump.impact) if jump.impact is not None else run.impacts
        pieces.append(_on_output_times(run, current, events=theirs, stopped_by=None,
                                       impacts=impacts))  # fmt: skip
        state = np.array(jump.state, dtype=float)
        names = [name for name in (jump.label, *jump.also) if name]
        records: list[Record] = [(name, t_jump, state) for name in names]
        disarmed = stop[0] if jump.disarm else None
        mode, entered = _settled(hybrid, jump.mode, records, t_jump, jump.state)
        if t_jump >= t1 or jump.stop:  # its events end the run
            stopped = jump.label if jump.stop else None
            pieces[-1] = dataclasses.replace(
                pieces[-1],
                events=(*pieces[-1].events, *entered),
                stopped_by=stopped,
                t_reached=t_jump,
                x_reached=state,
            )
            break
        current = continued_from(current, t_jump, jump.state)
    return joined(pieces)


def _settled(
    hybrid: Hybrid[Any], mode: Any, events: list[Record], t: float, x: np.ndarray
) -> tuple[Any, list[Record]]:
    """The mode a piece really starts in, and the events of the transition and the decision."""
    settled, decided = hybrid.settle(mode, t, x)
    return settled, [*events, *decided]


def _failed_at(run: Integration, stop: Record, jump: Jump) -> Integration:
    """A piece whose guard ends the run as a failure at the guard's zero (its event kept)."""
    _, t, x = stop
    event: Record = (jump.label, t, np.array(x, dtype=float))
    return dataclasses.replace(
        run,
        failure=jump.failure,
        stopped_by=None,
        t_reached=t,
        x_reached=x,
        events=(*run.events, event),
    )


def _on_output_times(run: Integration, inputs: Inputs, **changes: Any) -> Integration:
    """A piece with, when output times are given, only their rows (not the row of the
    transition that ends it): the joined run has exactly the rows asked for; ``changes``
    replace fields of the piece besides."""
    t_out = inputs.t_out
    if t_out is None or len(run.t) == 0:
        return dataclasses.replace(run, **changes) if changes else run
    # the rows at output times (sorted): where each row's time is one of them
    at = np.minimum(np.searchsorted(t_out, run.t), len(t_out) - 1)
    keep = t_out[at] == run.t
    if keep.all():
        return dataclasses.replace(run, **changes) if changes else run
    return dataclasses.replace(
        run,
        t=run.t[keep],
        x=run.x[keep],
        multipliers=_rows(run.multipliers, keep),
        constraint_residual=_rows(run.constraint_residual, keep),
        **changes,
    )


def continued_from(inputs: Inputs, t: float, x: np.ndarray) -> Inputs:
    """The inputs of the next piece, from the state x at t."""
    t_out = inputs.t_out
    return dataclasses.replace(
        inputs,
        x0=np.array(x, dtype=float),
        t_span=(t, inputs.t_span[1]),
        t_out=None if t_out is None else t_out[t_out >= t],
    )


def joined(pieces: list[Integration]) -> Integration:
    """The pieces end to end (a row repeated at a junction is kept once); the last piece
    says how the run ended.  Multipliers and residuals are joined when every piece has them."""
    keep = [pieces[0]]
    for piece in pieces[1:]:
        last = keep[-1].t[-1] if len(keep[-1].t) else -np.inf
        later = piece.t > last
        if later.all():  # no row repeated at the junction
            keep.append(piece)
            continue
        keep.append(
            dataclasses.replace(
                piece,
                t=piece.t[later],
                x=piece.x[later],
                multipliers=_rows(piece.multipliers, later),
                constraint_residual=_rows(piece.constraint_residual, later),
            )
        )
    return dataclasses.replace(
        pieces[-1],
        t=np.concatenate([p.t for p in keep]),
        x=np.concatenate([p.x for p in keep]),
        events=tuple(event for p in pieces for event in p.events),
        impacts=tuple(impact for p in pieces for impact in p.impacts),
        multipliers=_joined_rows([p.multipliers for p in keep]),
        constraint_residual=_joined_rows([p.constraint_residual for p in keep]),
    )


def _rows(values: np.ndarray | None, mask: np.ndarray) -> np.ndarray | None:
    return None if values is None else values[mask]


def _joined_rows(parts: list[np.ndarray | None]) -> np.ndarray | None:
    if any(part is None for part in parts):
        return None
    return np.concatenate(parts)  # type: ignore[arg-type]
