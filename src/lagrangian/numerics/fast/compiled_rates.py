"""The right-hand side of one system as a C function, for the loops compiled once per machine.

The state equations (:mod:`lagrangian.numerics.state_equations`) are a linear system

    matrix(t, x, p) z = vector(t, x, p),     z = [q_ddot_S; q_dot_F],   x = [q; q_dot_S],

and ``fast_equations(eom)`` compiles its entries into one C function (:mod:`~lagrangian.
numerics.fast.native`: SymEngine's LLVM backend in milliseconds, numba only where SymEngine
cannot) of the input vector and output vector

    in  = [t, x, p]                   (1 + len(x) + len(p) numbers)
    out = [matrix row by row, vector] (size^2 + size numbers).

The compiled loops solve it for z in place (:mod:`~lagrangian.numerics.fast.linear`) and
assemble dx/dt = [q_dot; q_ddot_S] (:mod:`~lagrangian.numerics.fast.rates`).  Solving in the
loop rather than compiling the solved rates: for the 10-link pendulum the explicit rates
(SymEngine's LU solve, then LLVM) take 0.7 us a call against 1.2 us for matrix, vector and
the compiled solve, but nearly twice the compile time (0.09 s against 0.05 s), which is what
a new model costs, and an expression that grows as n^3 (``benchmarks/simulate.py``, (d)).
The same shape serves any linear system whose first unknowns are the accelerations, such as
the multiplier form [[M, -A^T], [A, 0]] [q_ddot; lambda] = [forcing; gamma]
(:func:`linear_equations`).  Parameters are numbers in ``in``, so a new mass needs no
new compilation.

>>> import lagrangian as lg
>>> fast = fast_equations(lg.derive(lg.examples.simple_pendulum()))  # doctest: +SKIP
>>> fast.state_names, fast.function.compiler  # doctest: +SKIP
(('theta', 'theta_dot'), 'llvm')
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.fast.native import NativeFunction, native_function
from lagrangian.numerics.state_equations import state_equations
from lagrangian.symbolic.caches import IdentityCache

INSTALL_HINT = "pip install lagrangian[fast]"

_CACHE: IdentityCache[EquationsOfMotion, FastEquations] = IdentityCache()


def numba_available() -> bool:
    """Whether numba can be imported (without importing it)."""
    return importlib.util.find_spec("numba") is not None


def require_numba(feature: str = "backend='numba'") -> None:
    """Raise SimulationError, with the install command, when numba is not installed."""
    if not numba_available():
        raise SimulationError(
            f"{feature} needs numba, which is not installed: {INSTALL_HINT} "
            "(or use backend='numpy', the default)."
        )


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


def fast_equations(eom: EquationsOfMotion) -> FastEquations:
    """The compiled state equations of ``eom``, built once per EquationsOfMotion object.

    Raises SimulationError when numba is missing or an expression has no numeric form.
    """
    require_numba()
    return _CACHE.get(eom, _build)


def _build(eom: EquationsOfMotion) -> FastEquations:
    equations = state_equations(eom)
    return linear_equations(
        eom.time,
        eom.coordinates,
        [eom.velocities[j] for j in equations.second],
        tuple(eom.parameters),
        (equations.matrix, equations.vector),
        equations.first,
    )


def linear_equations(
    time: sp.Symbol,
    coordinates: Sequence[sp.Symbol],
    velocities: Sequence[sp.Symbol],
    parameters: Sequence[sp.Symbol],
    system: tuple[sp.MatrixBase, sp.MatrixBase],
    first: Sequence[int] = (),
) -> FastEquations:
    """``matrix z = vector`` (``system``) compiled as a function of [t, q, ``velocities``, p].

    ``velocities`` are those of the second-order coordinates (every coordinate not in
    ``first``), in order; z must begin with their accelerations, then the velocities of the
    ``first``-order coordinates; any further unknowns (multipliers) are solved for and not
    integrated.  Raises SimulationError when an expression has no numeric form.
    """
    matrix, vector = system
    n = len(coordinates)
    second = tuple(j for j in range(n) if j not in set(first))
    square = matrix.shape == (len(vector), len(vector))
    if len(velocities) != len(second) or not square or len(vector) < n:
        raise ValueError("the velocities, the matrix and the vector do not fit together")
    symbols = [time, *coordinates, *velocities, *parameters]
    return FastEquations(
        coordinates=tuple(s.name for s in coordinates),
        parameters=tuple(s.name for s in parameters),
        state_names=(*(s.name for s in coordinates), *(s.name for s in velocities)),
        second=second,
        first=tuple(first),
        size=len(vector),
        function=native_function(symbols, [*matrix, *vector]),
    )
