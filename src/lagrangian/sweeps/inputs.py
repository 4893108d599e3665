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

from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import compile_equations
from lagrangian.simulation.batch_inputs import checked_batch
from lagrangian.simulation.options import check_keywords
from lagrangian.simulation.setup import collect, describe_system, options_for


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
    check_keywords(stepping, "sweep")
    eom, system, fallbacks = describe_system(system)
    compiled = compile_equations(eom)
    problems: list[Problem] = []
    chosen = options_for(
        system, compiled, stepping, fallbacks, backend=backend, driver="simulate_batch"
    )
    collect(problems, chosen)
    given = {"initial": initial, "parameters": parameters, "t_span": t_span, **stepping}
    batch, found = checked_batch(compiled, given, fallbacks)
    raise_if_problems(problems + found, "Cannot sweep", SimulationInputError)
    return np.asarray(batch.t_out, dtype=float)
