"""A sweep's simulation inputs checked on the client, before a cluster starts or a store is
made: what ``simulate_batch`` would refuse (method, tolerances, samples, time span, missing
values, backend) is refused here, every problem at once, with the output times it would use.

>>> import lagrangian as lg
>>> checked_times(lg.examples.simple_pendulum(), {"theta": [0.1]}, {}, 2.0, {"samples": 3})
array([0., 1., 2.])
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from lagrangian.model import System
from lagrangian.simulation.batch import prepared_batch


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
    *_, batch = prepared_batch(system, initial, parameters, t_span, stepping, backend, "sweep")
    return np.asarray(batch.t_out, dtype=float)
