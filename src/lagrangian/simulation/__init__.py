"""The simulation layer: integrate the equations of motion into a Trajectory
(docs/architecture.md).

The names below load on first use (PEP 562), so that reading a :class:`Trajectory` — as the
render layer does — does not import SciPy's integrators.

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.double_pendulum(), t_span=2.0, method="DOP853")
>>> trajectory.q.shape[1], trajectory.status
(2, 'success')
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lagrangian.lazy_names import lazy_attribute

if TYPE_CHECKING:
    from lagrangian.simulation.batch.result import Batch
    from lagrangian.simulation.batch.run import simulate_batch
    from lagrangian.simulation.integrators.events import EventFunction
    from lagrangian.simulation.outcome import SimulationInterrupted
    from lagrangian.simulation.run import simulate
    from lagrangian.simulation.trajectory import Event, Trajectory
    from lagrangian.simulation.variational.action import action, action_variation, stationary_path

#: Public name -> the module defining it, imported when the name is first used.
_HOMES = {
    "Batch": "lagrangian.simulation.batch.result",
    "Event": "lagrangian.simulation.trajectory",
    "EventFunction": "lagrangian.simulation.integrators.events",
    "SimulationInterrupted": "lagrangian.simulation.outcome",
    "Trajectory": "lagrangian.simulation.trajectory",
    "action": "lagrangian.simulation.variational.action",
    "action_variation": "lagrangian.simulation.variational.action",
    "simulate": "lagrangian.simulation.run",
    "simulate_batch": "lagrangian.simulation.batch.run",
    "stationary_path": "lagrangian.simulation.variational.action",
}


def __getattr__(name: str) -> Any:
    return lazy_attribute(globals(), _HOMES, __name__, name)


__all__ = [
    "Batch",
    "Event",
    "EventFunction",
    "SimulationInterrupted",
    "Trajectory",
    "action",
    "action_variation",
    "simulate",
    "simulate_batch",
    "stationary_path",
]
