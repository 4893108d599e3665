"""The compiled fast path: each model's functions compiled in milliseconds, driven by loops
compiled once per machine.

The explicit Runge–Kutta methods (RK45 and DOP853 step for step as SciPy takes them, and the
classical RK4) run in one C loop (:mod:`~lagrangian.numerics.fast.c_loop`, ``c_loop.c``),
compiled once per machine by the system's C compiler into a cached shared library
(:mod:`~lagrangian.numerics.fast.c_build`).  It drives the right-hand side compiled by
SymEngine's LLVM backend (:mod:`~lagrangian.numerics.fast.native`) through its C function
pointer: a new model costs its LLVM compilation only, and parameters are numbers in the
function's input, so changing a mass needs no new compilation.  The multiplier form of a
constrained system runs in the same loop (:mod:`~lagrangian.numerics.fast.c_constrained`).
Without a C compiler, callers use SciPy's solvers instead.

numba compiles what nothing else compiles: the variational marches (the midpoint rule and
the Gauss–Legendre collocation, :mod:`~lagrangian.numerics.fast.discrete_loops`), where it
is installed (``pip install lagrangian[fast]``).
"""

from lagrangian.numerics.fast.compiled_rates import (
    INSTALL_HINT,
    FastEquations,
    numba_available,
    require_numba,
)

__all__ = ["INSTALL_HINT", "FastEquations", "numba_available", "require_numba"]
