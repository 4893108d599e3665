"""dx/dt inside the compiled loops: call the system's C function, solve, assemble.

A system reaches the loops as the C function ``void f(double *out, const double *in, void
*user_data)`` of :mod:`lagrangian.numerics.fast.compiled_rates`, a first-class function value
(so the loops are the same machine code for every system), and ``equations`` = (user_data,
second, first, size).  :func:`bind` gives one run its buffers, with the parameters written
once:

    in  = [t, x, p],    out = [matrix; vector]  (an array of size + 1 rows of size numbers)

and :func:`state_rates` evaluates, for the state x = [q; q_dot_S] (n coordinates),

    matrix z = vector  ->  z = [q_ddot_S; q_dot_F; ...]   (Gaussian elimination, in place)
    dx/dt = [q_dot; q_ddot_S],   q_dot_S from x, q_dot_F and q_ddot_S from z.

This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lagrangian.numerics.fast.linear import solve_linear


@njit(cache=False, nogil=True, error_model="numpy")
def bind(function, equations, p, nx):
    """(f, user_data, second, first, in, out) for a run of a state of nx numbers with the
    parameters ``p``: the buffers of :func:`state_rates`, ``in`` holding p already."""
    user_data, second, first, size = equations
    inputs = np.empty(1 + nx + p.size)
    for i in range(p.size):
        inputs[1 + nx + i] = p[i]
    outputs = np.empty((size + 1, size))
    return function, user_data, second, first, inputs, outputs


@njit(cache=False, nogil=True, error_model="numpy")
def coordinate_count(equations) -> int:
    """n, the number of coordinates: the second-order ones and the first-order ones."""
    return equations[1].size + equations[2].size


@njit(cache=False, nogil=True, error_model="numpy")
def state_rates(system, t, x, dx) -> bool:
    """dx/dt at (t, x) into ``dx`` (module docstring); False when the matrix is singular."""
    function, user_data, second, first, inputs, outputs = system
    inputs[0] = t
    for i in range(x.size):
        inputs[1 + i] = x[i]
    function(outputs.ctypes, inputs.ctypes, user_data)
    size = outputs.shape[1]
    z = outputs[size]
    if not solve_linear(outputs[:size], z):
        return False
    s = second.size
    n = s + first.size
    for k in range(s):
        dx[second[k]] = x[n + k]
        dx[n + k] = z[k]
    for k in range(first.size):
        dx[first[k]] = z[s + k]
    return True
