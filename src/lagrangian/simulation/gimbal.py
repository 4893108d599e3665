"""Gimbal lock of Euler angles during a simulation: stop with an error that names the body,
instead of integrating through a singular mass matrix.

Three Euler angles (a, b, c) no longer determine their rates from the angular velocity where
the first and third rotation axes line up: s = sin(b) = 0 for a proper Euler sequence such as
ZXZ, s = cos(b) = 0 for a Tait–Bryan one such as ZYX (``Orientation.gimbal_lock``).  There
omega = J(a, b, c) (a_dot, b_dot, c_dot) has a singular J, the mass matrix is singular, and the
rates of a and c blow up.  For every 3-D body given by Euler angles the simulation watches the
terminal event

    g = sigma s(q, t) - epsilon,    sigma = the sign of s at the start,  epsilon = 1e-6,

which falls through zero both when the motion comes within epsilon of the lock and when one
step crosses it.  A start at the lock is refused before integrating.  Integrators that take no
events (``method="variational"``, ``backend="numba"``) are checked along their output instead.

>>> import lagrangian as lg
>>> try:
...     lg.simulate(lg.examples.heavy_symmetric_top(), {"theta": 0.0}, 1.0)
... except lg.SimulationError as error:
...     print(str(error)[:60])
body 'top': Euler angles ZXZ at gimbal lock (theta = 0) at t
"""

from __future__ import annotations

import dataclasses

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.trajectory import Trajectory

#: |s| below this counts as at gimbal lock.
TOLERANCE = 1e-6
_ADVICE = (
    "use other angles (a sequence whose lock this motion avoids), a quaternion, or an axis and "
    "angle for its orientation"
)


@dataclasses.dataclass(frozen=True)
class Lock:
    """Where one body's Euler angles lock: ``expression`` s(q, t) vanishes there; ``angle`` is
    the middle angle and ``values`` evaluates (s, angle) at (q, t, p)."""

    body: str
    sequence: str
    angle: sp.Expr
    expression: sp.Expr
    values: NumericFunction

    @property
    def event_name(self) -> str:
        return f"gimbal_lock_{self.body}"

    def message(self, angle: float, time: float) -> str:
        return (
            f"body {self.body!r}: Euler angles {self.sequence} at gimbal lock "
            f"({self.angle} = {angle:.6g}) at t = {time:.6g}; {_ADVICE}."
        )


class LockEvent:
    """The terminal event g = sigma s - epsilon of one lock (sigma fixed at the first call,
    which is the start of the run)."""

    terminal = True
    direction = -1.0

    def __init__(self, lock: Lock, p: np.ndarray) -> None:
        self.lock, self.p, self.sign = lock, p, 0.0
        self.__name__ = lock.event_name

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        s = float(self.lock.values(q, t, self.p)[0])
        if self.sign == 0.0:
            self.sign = 1.0 if s >= 0 else -1.0
        return self.sign * s - TOLERANCE


@dataclasses.dataclass(frozen=True)
class GimbalGuard:
    """The locks of one simulation: ``events`` to add to the run (empty for integrators that
    take none) and :meth:`finish` to turn a stop at a lock into a failure."""

    locks: tuple[Lock, ...]
    p: np.ndarray
    events: tuple[LockEvent, ...]

    def finish(self, trajectory: Trajectory) -> Trajectory:
        """``trajectory``, failed at the first lock it reached (its rows up to there)."""
        found = self._stopped(trajectory) or self._reached(trajectory)
        if found is None:
            return trajectory
        lock, row = found
        q = trajectory.q[row]
        angle = float(lock.values(q, float(trajectory.t[row]), self.p)[1])
        message = lock.message(angle, float(trajectory.t[row]))
        return dataclasses.replace(
            _head(trajectory, row + 1), status="failed", message=message, message_template=None
        )

    def _stopped(self, trajectory: Trajectory) -> tuple[Lock, int] | None:
        """The lock whose terminal event ended the run (its state is the last row)."""
        if not (self.events and trajectory.success and trajectory.events):
            return None
        name = trajectory.events[-1].name
        stopped = trajectory.message.startswith("Stopped by the terminal event")
        lock = next((k for k in self.locks if k.event_name == name), None)
        return (lock, len(trajectory.t) - 1) if stopped and lock is not None else None

    def _reached(self, trajectory: Trajectory) -> tuple[Lock, int] | None:
        """Without events: the first output row at (or past) a lock."""
        if self.events or len(trajectory.t) == 0:
            return None
        first: tuple[Lock, int] | None = None
        for lock in self.locks:
            p = np.broadcast_to(self.p, (len(trajectory.t), len(self.p)))
            s = lock.values(trajectory.q, trajectory.t, p)[:, 0]
            rows = np.flatnonzero(np.sign(s[0]) * s < TOLERANCE)
            if len(rows) and (first is None or rows[0] < first[1]):
                first = (lock, int(rows[0]))
        return first


def gimbal_guard(
    eom: EquationsOfMotion, system: System, inputs: Inputs, takes_events: bool
) -> GimbalGuard:
    """The guard of one simulation from its checked ``inputs`` (watching events when the
    integrator ``takes_events``, else the output rows); SimulationInputError when the
    initial state is at a lock."""
    locks = _locks(eom, system)
    n, t0 = len(eom.coordinates), inputs.t_span[0]
    for lock in locks:
        with np.errstate(invalid="ignore"):
            s, angle = (float(v) for v in lock.values(inputs.x0[:n], t0, inputs.p))
        if abs(s) < TOLERANCE:
            raise SimulationInputError(
                f"body {lock.body!r}: Euler angles {lock.sequence} at gimbal lock "
                f"({lock.angle} = {angle:.6g}) at the start, t = {t0:.6g}: the mass matrix is "
                f"singular there, so the motion cannot start; {_ADVICE}, or start away from "
                "the lock."
            )
    events = tuple(LockEvent(lock, inputs.p) for lock in locks) if takes_events else ()
    return GimbalGuard(locks, inputs.p, events)


def _locks(eom: EquationsOfMotion, system: System) -> tuple[Lock, ...]:
    groups = (list(eom.coordinates), eom.time, list(eom.parameters))
    locks = []
    for body in system.rigid_bodies:
        orientation = body.orientation
        if orientation is None or orientation.gimbal_lock is None:
            continue
        angle, expression = orientation.angles[1], orientation.gimbal_lock
        values = NumericFunction(groups, [expression, angle], (2,))
        locks.append(Lock(body.name, orientation.sequence, angle, expression, values))
    return tuple(locks)


def _head(trajectory: Trajectory, rows: int) -> Trajectory:
    """The first ``rows`` rows of a trajectory."""

    def cut(values: np.ndarray | None) -> np.ndarray | None:
        return None if values is None else values[:rows]

    return dataclasses.replace(
        trajectory,
        t=trajectory.t[:rows],
        q=trajectory.q[:rows],
        q_dot=trajectory.q_dot[:rows],
        energy=trajectory.energy[:rows],
        energy_function=cut(trajectory.energy_function),
        multipliers=cut(trajectory.multipliers),
        constraint_residual=cut(trajectory.constraint_residual),
        conserved={name: values[:rows] for name, values in trajectory.conserved.items()},
    )
