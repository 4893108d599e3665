"""The simulate layer: integrate the equations of motion into a Trajectory (see DESIGN.md).

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.double_pendulum(), t_span=2.0, method="DOP853")
>>> trajectory.q.shape[1], trajectory.status
(2, 'success')
"""

from lagrangian.simulation.action import action, action_variation, stationary_path
from lagrangian.simulation.batch import simulate_batch
from lagrangian.simulation.batch_result import Batch
from lagrangian.simulation.events import EventFunction
from lagrangian.simulation.run import simulate
from lagrangian.simulation.trajectory import Event, Trajectory

__all__ = [
    "Batch",
    "Event",
    "EventFunction",
    "Trajectory",
    "action",
    "action_variation",
    "simulate",
    "simulate_batch",
    "stationary_path",
]
