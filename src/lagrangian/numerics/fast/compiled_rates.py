"""The right-hand side of one system as a C function, for the C loop compiled once per machine.

The state equations (:mod:`lagrangian.numerics.state_equations`) are a linear system

    matrix(t, x, p) z = vector(t, x, p),     z = [q_ddot_S; q_dot_F],   x = [q; q_dot_S],

and :func:`lagrangian.numerics.fast.c_loop.native_equations` compiles its entries into one C
function (SymEngine's LLVM backend, milliseconds) of the input vector and output vector

    in  = [t, x, p]                   (1 + len(x) + len(p) numbers)
    out = [matrix row by row, vector] (size^2 + size numbers).

The C loop solves it for z in place and assembles dx/dt = [q_dot; q_ddot_S].  Solving in the
loop rather than compiling the solved rates: for the 10-link pendulum the explicit rates
(SymEngine's LU solve, then LLVM) take 0.7 us a call against 1.2 us for matrix, vector and
the compiled solve, but nearly twice the compile time (0.09 s against 0.05 s), which is what
a new model costs, and an expression that grows as n^3 (``benchmarks/simulate.py``, (d)).
The same shape serves any linear system whose first unknowns are the accelerations, such as
the multiplier form [[M, -A^T], [A, 0]] [q_ddot; lambda] = [forcing; gamma]
(:mod:`lagrangian.numerics.fast.c_constrained`).  Parameters are numbers in ``in``, so a new
mass needs no new compilation.  numba compiles the variational marches only
(:func:`numba_available`, :func:`require_numba`).
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass

from lagrangian.errors import Fix, Problem, Setting, SimulationError
from lagrangian.numerics.fast.native import NativeFunction

INSTALL_HINT = "pip install lagrangian[fast]"


def numba_available() -> bool:
    """Whether numba can be imported (without importing it)."""
    return importlib.util.find_spec("numba") is not None


def require_numba(feature: str = "the compiled variational marches") -> None:
    """Raise SimulationError, with the install command, when numba is not installed."""
    if not numba_available():
        fix = f"{INSTALL_HINT}, or use " + Fix("{} (the default)", (Setting("backend", "numpy"),))
        problem = Problem("backend", f"{feature} need numba, which is not installed", fix)
        raise SimulationError("", [problem])


@dataclass(frozen=True)
class FastEquations:
    """The compiled linear system of one system's state equations, and what its arrays mean.

    Attributes
    ----------
    coordinates, parameters, state_names:
        Names in the order of q, p and the state x = [q; q_dot_S].
    second, first:
        Indices of the second-order coordinates S and the first-order ones F.
    size:
        The number of unknowns z (and rows of the matrix); z begins with q_ddot_S, q_dot_F.
    function:
        out = [matrix row by row, vector] of in = [t, x, p] (module docstring).
    """

    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    state_names: tuple[str, ...]
    second: tuple[int, ...]
    first: tuple[int, ...]
    size: int
    function: NativeFunction
