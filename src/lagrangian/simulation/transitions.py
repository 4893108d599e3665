"""A motion with the hybrid transitions of its System (:mod:`lagrangian.model.transitions`):
the piecewise loop's guards and resets.

Each transition is a guard of every piece: a terminal event G(t, q, q_dot) = 0 in its direction.
Where it fires and its condition ``when`` holds, the state jumps to the reset's values (taken at
the state just before) and an event named after the transition is recorded (a Trajectory
impact-like record with the velocities before and after); where the condition does not hold the
crossing is passed by, nothing recorded.  Either way the guard is disarmed for the first step of
the next piece, which starts on its zero.  The transitions wrap any other hybrid motion
(unilateral constraints, switching surfaces) or a smooth one (:class:`SingleMode`).

>>> import lagrangian as lg
>>> ball = lg.loads('''
... coordinates: [y]
... parameters: {g: 9.81}
... kinetic: y_dot**2/2
... potential: g*y
... transitions: [{name: bounce, guard: y, direction: falling, reset: {y_dot: -y_dot/2}}]
... initial: {y: 1.0, y_dot: 0.0}
... ''')
>>> run = lg.simulate(ball, t_span=1.0, samples=11, method="DOP853", rtol=1e-10, atol=1e-12)
>>> [event.name for event in run.events], round(run.events[0].t, 6)   # t1 = sqrt(2 / g)
(['bounce', 'bounce'], 0.451524)
>>> round(run.impacts[1].t - run.impacts[0].t, 6)                       # t1 (half the speed)
0.451524
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model.transitions import Transition
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulation.crossings import Crossing
from lagrangian.simulation.impacts import ImpactRecord
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.piecewise import Guard, Hybrid, Jump, Record
from lagrangian.simulation.integrators.protocol import Dynamics, Integration
from lagrangian.symbolic.caches import IdentityCache


@dataclasses.dataclass(frozen=True)
class SingleMode:
    """A smooth Dynamics as a hybrid motion of one mode, with no guards of its own."""

    dynamics: Dynamics

    def initial_mode(self, t: float, x: np.ndarray) -> tuple[None, list[Record]]:
        return None, []

    def settle(self, mode: None, t: float, x: np.ndarray) -> tuple[None, list[Record]]:
        return None, []

    def piece(self, mode: None) -> Dynamics:
        return self.dynamics

    def guards(self, mode: None, piece: Dynamics) -> list[Guard]:
        return []

    def transition(self, mode: None, guard: Guard, t: float, x: np.ndarray) -> Jump:
        raise AssertionError("a smooth motion has no guards")  # pragma: no cover

    def completed(self, mode: None, piece: Dynamics, run: Integration) -> Integration:
        return run


class _Guard(Crossing):
    """The guard of the transition number ``index`` (terminal, in its direction)."""

    def __init__(
        self, transition: Transition, index: int, guard: NumericFunction, p: np.ndarray
    ) -> None:
        super().__init__(transition.name, guard, p, transition.direction)
        self.index = index


@dataclasses.dataclass(frozen=True)
class WithTransitions:
    """The ``transitions`` of ``eom``'s System over the hybrid motion ``inner``, at the
    parameters p (module docstring)."""

    inner: Hybrid[Any]
    eom: EquationsOfMotion
    p: np.ndarray
    motion: Any  # the Motion of the formulation (multiplier names, rows, the start)
    #: The times the transitions fired in the run under way (the state of one run).
    fired: list[float] = dataclasses.field(default_factory=list, compare=False, repr=False)

    @property
    def multiplier_names(self) -> tuple[str, ...]:
        names: tuple[str, ...] = self.motion.multiplier_names
        return names

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        pair: tuple[np.ndarray, np.ndarray] = self.motion.unpack(t, x)
        return pair

    def residual(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(self.motion.residual(t, q, q_dot))

    def constraint_rows(self, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray) -> Any:
        return self.motion.constraint_rows(t, q, q_dot)

    def start(self, inputs: Inputs, project_initial: bool) -> Inputs:
        started: Inputs = self.motion.start(inputs, project_initial)
        return started

    # -- the Hybrid protocol ------------------------------------------------------------
    def initial_mode(self, t: float, x: np.ndarray) -> tuple[Any, list[Record]]:
        self.fired.clear()  # a new run
        return self.inner.initial_mode(t, x)

    def settle(self, mode: Any, t: float, x: np.ndarray) -> tuple[Any, list[Record]]:
        return self.inner.settle(mode, t, x)

    def piece(self, mode: Any) -> Dynamics:
        return self.inner.piece(mode)

    def guards(self, mode: Any, piece: Dynamics) -> list[Guard]:
        return [*self.inner.guards(mode, piece), *self.crossings()]

    def crossings(self) -> list[_Guard]:
        """The guards of the transitions, compiled once per equations."""
        compiled = compiled_transitions(self.eom)
        return [
            _Guard(item, i, compiled[i][0], self.p)
            for i, item in enumerate(self.eom.system.transitions)
        ]

    def transition(self, mode: Any, guard: Guard, t: float, x: np.ndarray) -> Jump:
        if not isinstance(guard, _Guard):
            return self.inner.transition(mode, guard, t, x)
        _, when, reset, targets = compiled_transitions(self.eom)[guard.index]
        n = len(self.eom.coordinates)
        q, q_dot = x[:n], x[n:]
        if when is not None and not when(q, q_dot, t, self.p):
            return Jump(mode, x, "", disarm=True)  # passed by (a swing leg scuffing)
        after = np.array(x, dtype=float)
        after[list(targets)] = np.asarray(reset(q, q_dot, t, self.p), dtype=float)
        record = ImpactRecord(t, (guard.__name__,), (), np.array(x, dtype=float), after)
        self.fired.append(t)
        if accumulating(self.fired):  # ever faster firings: stop at their accumulation
            names = ", ".join(dict.fromkeys(i.name for i in self.eom.system.transitions))
            label = f"rest ({names} fire ever faster: a Zeno accumulation)"
            return Jump(mode, after, label, impact=record, disarm=True, stop=True)
        return Jump(mode, after, guard.__name__, impact=record, disarm=True)

    def completed(self, mode: Any, piece: Dynamics, run: Integration) -> Integration:
        return self.inner.completed(mode, piece, run)


#: Firings closer than this (relative to 1 + |t|), each interval shorter than the one before,
#: are the accumulation of a Zeno motion (a rimless wheel rocking to rest between two spokes).
ZENO_INTERVAL = 1e-8


def accumulating(fired: list[float]) -> bool:
    """Whether the last firings come ever faster (or all at one instant: two guards whose
    resets land on each other's zero at rest) and the last interval is below ZENO_INTERVAL:
    the geometric accumulation t_inf = t_k + d_k r / (1 - r) is reached to that precision,
    and stepping on would take ever smaller steps without end.

    >>> accumulating([0.0, 0.5, 0.75, 0.875])
    False
    >>> accumulating([1.0, 1 + 4e-9, 1 + 6e-9, 1 + 7e-9])
    True
    >>> accumulating([1.0, 1.0, 1.0, 1.0])
    True
    """
    if len(fired) < 4:
        return False
    intervals = np.diff(fired[-4:])
    shrinking = bool(np.all(np.diff(intervals) <= 0))
    return shrinking and bool(intervals[-1] < ZENO_INTERVAL * (1 + abs(fired[-1])))


class _Condition:
    """``when`` of a transition at one state: its comparison of lhs - rhs with 0."""

    def __init__(self, function: NumericFunction, relation: Any) -> None:
        self.function, self.relation = function, relation

    def __call__(self, q: np.ndarray, q_dot: np.ndarray, t: float, p: np.ndarray) -> bool:
        value = float(self.function(q, q_dot, t, p))
        return bool(self.relation(value, 0.0))


#: Per transition: the guard, the condition (or None), the reset and the state indices it sets.
Compiled = tuple[NumericFunction, "_Condition | None", NumericFunction, tuple[int, ...]]


def compiled_transitions(eom: EquationsOfMotion) -> tuple[Compiled, ...]:
    """The numeric functions of the System's transitions (compiled once per equations)."""
    return _COMPILED.get(eom, lambda e: tuple(_compile(e, item) for item in e.system.transitions))


_COMPILED: IdentityCache[EquationsOfMotion, tuple[Compiled, ...]] = IdentityCache()


def _compile(eom: EquationsOfMotion, item: Transition) -> Compiled:
    if any(order != 2 for order in eom.coordinate_orders.values()):
        raise SimulationInputError(
            f"transition {item.name!r}: transitions are applied to systems whose every "
            "coordinate has inertia (a second-order state); this one has first-order ones"
        )
    q, qd, t, p = list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)
    groups = (q, qd, t, p)
    state = [*q, *qd]
    targets = tuple(state.index(key) for key, _ in item.reset)
    reset = NumericFunction(groups, [value for _, value in item.reset], (len(targets),))
    guard = NumericFunction(groups, [item.guard], ())
    when = None
    if item.when is not None:
        difference = NumericFunction(groups, [item.when.lhs - item.when.rhs], ())
        when = _Condition(difference, _RELATIONS[item.when.rel_op])
    return guard, when, reset, targets


_RELATIONS = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
}


def with_transitions(
    eom: EquationsOfMotion, p: np.ndarray, motion: Any, inner: Hybrid[Any] | None
) -> WithTransitions:
    """The motion ``motion`` (a Dynamics, or the hybrid ``inner``) with the System's
    transitions."""
    return WithTransitions(inner if inner is not None else SingleMode(motion), eom, p, motion)
