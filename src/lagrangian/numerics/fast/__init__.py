"""The compiled fast path: the right-hand side and the integration loops compiled by numba.

``fast_equations(eom)`` turns the state equations into Python source
(:mod:`lagrangian.numerics.fast.source`) and compiles it with ``numba.njit``; the loops of
:mod:`~lagrangian.numerics.fast.adaptive` (SciPy's RK45 and DOP853, step for step) and
:mod:`~lagrangian.numerics.fast.fixed` (RK4) then run a whole integration, or a whole batch of
them, without a Python call per step.  NumPy/SciPy stays the default and the reference; this
path is optional (``pip install lagrangian[fast]``).

The right-hand side is compiled once per EquationsOfMotion object and process, never cached on
disk: it is generated source run through ``exec``, which numba cannot cache (about 0.5 s for a
double pendulum, 1.5 s for ten links).  The loops take it as a function value, so they are the
same for every system: compiled once (several seconds) and kept in numba's on-disk cache
(``__pycache__`` beside them, or ``NUMBA_CACHE_DIR``), see :mod:`~lagrangian.numerics.fast.loops`.
Parameters are an array ``p``, so changing a mass needs no new compilation.

The right-hand side lives in :mod:`~lagrangian.numerics.fast.compiled_rates`, the drivers in
:mod:`~lagrangian.numerics.fast.run` (imported only when numba is installed).

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.fast.run import Settings, integrate  # doctest: +SKIP
>>> fast = fast_equations(lg.derive(lg.examples.simple_pendulum()))  # doctest: +SKIP
>>> settings = Settings("DOP853", (0.0, 1.0), np.linspace(0, 1, 3))  # doctest: +SKIP
>>> x0, p = np.array([0.1, 0.0]), np.array([1.0, 9.81, 1.0])
>>> run = integrate(fast, settings, x0, p)  # doctest: +SKIP
"""

from lagrangian.numerics.fast.compiled_rates import (
    INSTALL_HINT,
    FastEquations,
    fast_equations,
    numba_available,
    require_numba,
)

__all__ = ["INSTALL_HINT", "FastEquations", "fast_equations", "numba_available", "require_numba"]
