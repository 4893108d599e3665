"""The simulate layer: integrate the equations of motion into a Trajectory (see DESIGN.md).

>>> import lagrangian as lg
>>> from lagrangian.simulate import simulate
>>> trajectory = simulate(lg.examples.double_pendulum(), t_span=2.0, method="DOP853")
>>> trajectory.q.shape[1], trajectory.status
(2, 'success')
"""

from lagrangian.simulate.action import action, action_variation, stationary_path
from lagrangian.simulate.batch import simulate_batch
from lagrangian.simulate.batch_result import Batch
from lagrangian.simulate.events import EventFunction
from lagrangian.simulate.run import simulate
from lagrangian.simulate.trajectory import Event, Trajectory

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
