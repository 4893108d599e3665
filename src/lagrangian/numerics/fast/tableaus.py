"""The Butcher tableaus of the compiled integrators, taken from SciPy so both agree.

An explicit Runge–Kutta step with s stages (Hairer, Nørsett & Wanner, Solving ODEs I, II.1):

    K_i = f(t + c_i h, x + h sum_{j<i} a_ij K_j),    x_new = x + h sum_i b_i K_i,

with the error estimated from K (and K_s = f(t + h, x_new)) by the weights E (RK45) or E5 and
E3 (DOP853, Hairer's 8(5,3) estimate).  Every tableau is packed into one tuple of the same
types, so one compiled integration loop serves both methods:

    (A, B, C, E, E3, P, A_extra, C_extra, D, is_dop853, error_order)

P is RK45's dense-output matrix; A_extra, C_extra, D are DOP853's three extra stages and its
interpolation weights; the arrays a method does not use are small zero arrays.

>>> tableau = adaptive_tableau("DOP853")
>>> tableau[0].shape, tableau[-2], tableau[-1]
((12, 12), True, 7)
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
from scipy.integrate import DOP853, RK45

#: The adaptive methods of the compiled backend.
ADAPTIVE = ("RK45", "DOP853")


@cache
def adaptive_tableau(method: str) -> tuple[Any, ...]:
    """The packed tableau of ``method`` ("RK45" or "DOP853"), see the module docstring."""
    unused = np.zeros((1, 1))
    if method == "DOP853":
        return (
            _array(DOP853.A),
            _array(DOP853.B),
            _array(DOP853.C),
            _array(DOP853.E5),
            _array(DOP853.E3),
            unused,
            _array(DOP853.A_EXTRA),
            _array(DOP853.C_EXTRA),
            _array(DOP853.D),
            True,
            DOP853.error_estimator_order,
        )
    stages = RK45.n_stages
    square = np.zeros((stages, stages))
    square[:, : RK45.A.shape[1]] = RK45.A
    return (
        square,
        _array(RK45.B),
        _array(RK45.C),
        _array(RK45.E),
        np.zeros(stages + 1),
        _array(RK45.P),
        unused,
        np.zeros(1),
        unused,
        False,
        RK45.error_estimator_order,
    )


def _array(values: Any) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=float)
