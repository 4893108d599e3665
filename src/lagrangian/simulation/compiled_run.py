"""simulate(..., backend="numba"): the whole integration in one compiled call.

The numba backend (:mod:`lagrangian.numerics.fast`) runs SciPy's RK45 and DOP853, step for
step, and the fixed-step RK4, with the right-hand side and the loop compiled, so no Python
runs per step; it returns what the NumPy backend returns.  What it does not do is refused up
front by :class:`lagrangian.simulation.options.Options`, naming the feature: events (use
:func:`lagrangian.simulation.batch.simulate_batch` with ``stop_when`` for a stop condition),
constraints, the variational integrator, and the implicit or other SciPy methods.  A progress
callback is called once, at the end.
"""

from __future__ import annotations

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.numerics.fast.settings import Settings
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integration import Integration, Progress


def integrate_compiled(
    eom: EquationsOfMotion, inputs: Inputs, progress: Progress | None = None
) -> Integration:
    """Integrate with the numba backend; the result as
    :func:`lagrangian.simulation.stepping.integrate` gives it (rows up to a failure, the
    failure).  Needs ``pip install lagrangian[fast]`` (SimulationError naming it)."""
    from lagrangian.numerics.fast import fast_equations, require_numba
    from lagrangian.numerics.fast.outcome import describe, failed
    from lagrangian.numerics.fast.run import integrate

    require_numba()
    fast = fast_equations(eom)
    t_out = inputs.t_out if inputs.t_out is not None else np.zeros(0)
    run = integrate(fast, loop_settings(inputs, t_out), inputs.x0, inputs.p)
    if progress is not None:
        progress(run.t_reached)
    return Integration(
        t=run.t,
        x=run.x,
        t_reached=float(run.t_reached),
        x_reached=np.asarray(run.x_reached, dtype=float),
        failure=describe(run.status) if failed(run.status) else None,
    )


def loop_settings(inputs: Inputs, t_out: np.ndarray) -> Settings:
    """The settings of the hand-written loops (numba's and the NumPy batch's) from checked
    inputs, with the output times ``t_out`` (empty: every step)."""
    return Settings(
        inputs.method,
        inputs.t_span,
        t_out,
        inputs.rtol,
        inputs.atol,
        inputs.max_step,
        inputs.dt,
        inputs.max_steps,
    )
