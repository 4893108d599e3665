"""The compiled fast path: each model's right-hand side compiled in milliseconds, driven by
integration loops compiled once per machine.

``fast_equations(eom)`` compiles the entries of the state equations' linear system into one C
function ``f(out, in, user_data)`` with SymEngine's LLVM backend
(:mod:`~lagrangian.numerics.fast.native`; numba compiles generated Python source only where
SymEngine cannot).  The loops of :mod:`~lagrangian.numerics.fast.adaptive` (SciPy's RK45 and
DOP853, step for step) and :mod:`~lagrangian.numerics.fast.fixed` (RK4) take that function as a
value, solve the linear system in place (:mod:`~lagrangian.numerics.fast.rates`) and run a whole
integration, or a whole batch of them, without a Python call per step.  Being the same for
every system, the loops are compiled by numba once (several seconds) and kept in its on-disk
cache, see :mod:`~lagrangian.numerics.fast.loops`; a new model costs its LLVM compilation only.
Parameters are numbers in the function's input, so changing a mass needs no new compilation.
The multiplier form of a constrained system runs on the same loops
(:mod:`~lagrangian.numerics.fast.constrained`).  This path needs numba
(``pip install lagrangian[fast]``).

The default ``simulate`` of a system without constraints or events needs no numba: the same
RK45/DOP853 loop written in C (:mod:`~lagrangian.numerics.fast.c_loop`, ``c_loop.c``) is
compiled once per machine by the system's C compiler into a cached shared library
(:mod:`~lagrangian.numerics.fast.c_build`) and drives the LLVM right-hand side through its C
function pointer; without a compiler the run falls back to SciPy's solvers.

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
