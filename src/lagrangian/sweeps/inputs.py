"""A sweep's simulation inputs checked on the client, before a cluster starts or a store is
made: what the workers' integrator would refuse (method, tolerances, samples, time span,
missing values, backend; for a constrained system also a first member off its constraints)
is refused here, every problem at once, with the output times it would use.

>>> import lagrangian as lg
>>> checked_times(lg.examples.simple_pendulum(), {"theta": [0.1]}, {}, 2.0, {"samples": 3})
array([0., 1., 2.])
>>> checked_member_times(lg.examples.cylinder_on_incline(), {}, {}, 2.0, {"samples": 2})
array([0., 2.])
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from lagrangian.errors import SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.simulation.batch.run import StopCondition, prepared_batch
from lagrangian.simulation.batch.stop import stop_event
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare


def checked_times(
    system: System,
    initial: Mapping[str, Any],
    parameters: Mapping[str, Any],
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    backend: str = "numpy",
) -> np.ndarray:
    """The output times shared by every member; SimulationInputError on bad input (the
    checks of :func:`lagrangian.simulate_batch`, without integrating)."""
    *_, batch = prepared_batch(
        system, initial, parameters, t_span, stepping, backend, "sweep", ends_only=True
    )
    return np.asarray(batch.t_out, dtype=float)


def checked_member_times(
    system: System,
    initial: Mapping[str, float],
    parameters: Mapping[str, float],
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    backend: str = "numpy",
    stop_when: StopCondition | None = None,
    project_initial: bool = False,
) -> np.ndarray:
    """The output times of members run one by one with :func:`lagrangian.simulate` (the
    ends of the time span without ``samples`` or ``t_eval``, as a batch); its checks of one
    member (``initial`` and ``parameters``: numbers) without integrating, the start on the
    constraints included.  SimulationInputError on bad input."""
    try:
        setup = prepare(
            system,
            initial,
            t_span,
            stepping,
            parameters=parameters,
            events=(stop_event(stop_when),) if stop_when is not None else (),
            backend=backend,
            project_initial=project_initial,
            driver="sweep",  # its fixes name the stop condition stop_when, not events
            ends_only=True,
        )
        motion, _ = plan(setup)
        motion.start(setup.inputs, project_initial)
    except SimulationInputError as error:
        raise_if_problems(list(error.problems), "Cannot sweep", SimulationInputError)
        raise
    t_out = setup.inputs.t_out
    return np.asarray(setup.inputs.t_span if t_out is None else t_out, dtype=float)
