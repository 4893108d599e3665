"""simulate(..., backend="numba"): the whole integration in one compiled call.

The numba backend (:mod:`lagrangian.numerics.fast`) runs SciPy's RK45 and DOP853, step for
step, and the fixed-step RK4, with the right-hand side and the loop compiled, so no Python
runs per step; it returns what the NumPy backend returns.  What it does not do is refused up
front, naming the feature: events (use :func:`lagrangian.simulation.batch.simulate_batch` with
``stop_when`` for a stop condition), constraints, the variational integrator, and the implicit
or other SciPy methods.  A progress callback is called once, at the end.

>>> check_backend("numpy", "RK45", None, ())
>>> check_backend("cuda", "RK45", None, ())
Traceback (most recent call last):
...
lagrangian.errors.SimulationError: Cannot simulate (1 problem):
  - backend: unknown backend 'cuda' — backends: 'numpy' (the default), 'numba'
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationError, raise_if_problems
from lagrangian.model import System
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.stepping import Integration

#: The backends of simulate and simulate_batch.
BACKENDS = ("numpy", "numba")
#: The methods of the numba backend.
COMPILED_METHODS = ("RK45", "DOP853", "RK4")


def check_backend(backend: str, method: Any, system: System | None, events: Sequence[Any]) -> None:
    """Refuse an unknown backend, and with numba every feature it does not support."""
    problems: list[Problem] = []
    if backend not in BACKENDS:
        problems.append(
            Problem(
                "backend",
                f"unknown backend {backend!r}",
                "backends: 'numpy' (the default), 'numba'",
            )
        )
    elif backend == "numba":
        fix = "use backend='numpy' (the default)"
        if method is not None and method not in COMPILED_METHODS:
            problems.append(
                Problem(
                    "method",
                    f"the numba backend has no method {method!r}",
                    f"methods: {COMPILED_METHODS}, or {fix}",
                )
            )
        if events:
            problems.append(
                Problem(
                    "events",
                    "the numba backend does not locate events",
                    f"{fix}, or simulate_batch(..., stop_when=...)",
                )
            )
        if system is not None and system.constraints:
            problems.append(
                Problem(
                    "constraints", "the numba backend does not integrate constrained systems", fix
                )
            )
    raise_if_problems(problems, "Cannot simulate", SimulationError)
    if backend == "numba":
        from lagrangian.numerics.fast import require_numba

        require_numba()


def integrate_compiled(
    eom: EquationsOfMotion, inputs: Inputs, progress: Callable[[float], None] | None = None
) -> Integration:
    """Integrate with the numba backend; the result as
    :func:`lagrangian.simulation.stepping.integrate` gives it (rows up to a failure, the
    failure)."""
    from lagrangian.numerics.fast import fast_equations
    from lagrangian.numerics.fast.outcome import describe, failed
    from lagrangian.numerics.fast.run import Settings, integrate

    check_backend("numba", inputs.method, None, ())
    fast = fast_equations(eom)
    t_out = inputs.t_out if inputs.t_out is not None else np.zeros(0)
    settings = Settings(
        inputs.method, inputs.t_span, t_out, inputs.rtol, inputs.atol, inputs.max_step, inputs.dt
    )
    run = integrate(fast, settings, inputs.x0, inputs.p)
    if progress is not None:
        progress(run.t_reached)
    failure = describe(run.status) if failed(run.status) else None
    return Integration(
        t=run.t,
        x=run.x,
        events=(),
        failure=failure,
        t_reached=float(run.t_reached),
        x_reached=np.asarray(run.x_reached, dtype=float),
        terminal=None,
    )
