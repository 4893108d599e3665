"""The Butcher tableaus of the explicit Runge–Kutta methods the compiled and vectorized loops
run, taken from SciPy (and the classical RK4) so that every loop takes SciPy's steps.

An explicit Runge–Kutta step with s stages (Hairer, Nørsett & Wanner, Solving ODEs I, II.1):

    K_i = f(t + c_i h, x + h sum_{j<i} a_ij K_j),    x_new = x + h sum_i b_i K_i,

with the error estimated from K (and K_s = f(t + h, x_new)) by the weights E (RK45) or E5 and
E3 (DOP853, Hairer's 8(5,3) estimate).  Every tableau has the fields of :class:`Tableau`, so
one loop serves every method: P is RK45's dense-output matrix; A_extra, C_extra, D are
DOP853's three extra stages and its interpolation weights; RK4 (``fixed``) has no error
estimate and interpolates by the cubic Hermite polynomial of x and dx/dt at both ends of a
step; the arrays a method does not use are small zero arrays.

>>> tableau = tableau_of("DOP853")
>>> tableau.A.shape, tableau.dop853, tableau.error_order
((12, 12), True, 7)
>>> tableau_of("RK4").B.tolist()
[0.16666666666666666, 0.3333333333333333, 0.3333333333333333, 0.16666666666666666]
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any, NamedTuple

import numpy as np
from scipy.integrate import DOP853, RK45


class Tableau(NamedTuple):
    """One explicit Runge–Kutta method as the loops read it (module docstring)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    E: np.ndarray
    E3: np.ndarray
    P: np.ndarray
    A_extra: np.ndarray
    C_extra: np.ndarray
    D: np.ndarray
    dop853: bool
    error_order: int
    fixed: bool = False


_UNUSED = np.zeros((1, 1))


def _dop853() -> Tableau:
    return Tableau(
        _array(DOP853.A),
        _array(DOP853.B),
        _array(DOP853.C),
        _array(DOP853.E5),
        _array(DOP853.E3),
        _UNUSED,
        _array(DOP853.A_EXTRA),
        _array(DOP853.C_EXTRA),
        _array(DOP853.D),
        True,
        DOP853.error_estimator_order,
    )


def _rk45() -> Tableau:
    stages = RK45.n_stages
    square = np.zeros((stages, stages))
    square[:, : RK45.A.shape[1]] = RK45.A
    return Tableau(
        square,
        _array(RK45.B),
        _array(RK45.C),
        _array(RK45.E),
        np.zeros(stages + 1),
        _array(RK45.P),
        _UNUSED,
        np.zeros(1),
        _UNUSED,
        False,
        RK45.error_estimator_order,
    )


def _rk4() -> Tableau:
    """The classical RK4: c = (0, 1/2, 1/2, 1), b = (1/6, 1/3, 1/3, 1/6) (Hairer, Nørsett &
    Wanner, Solving ODEs I, II.1, Table 1.2, left)."""
    A = np.zeros((4, 4))
    A[1, 0], A[2, 1], A[3, 2] = 0.5, 0.5, 1.0
    B = np.array([1 / 6, 1 / 3, 1 / 3, 1 / 6])
    C = np.array([0.0, 0.5, 0.5, 1.0])
    unused = np.zeros(5)
    return Tableau(A, B, C, unused, unused, _UNUSED, _UNUSED, np.zeros(1), _UNUSED, False, 4, True)


_BUILDERS = {"RK45": _rk45, "DOP853": _dop853, "RK4": _rk4}


@cache
def tableau_of(method: str) -> Tableau:
    """The tableau of ``method`` ("RK45", "DOP853" or "RK4"); KeyError for any other name
    (which methods run where is :mod:`lagrangian.simulation.methods`' to say)."""
    return _BUILDERS[method]()


def _array(values: Any) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=float)


def fixed_steps(t0: float, t1: float, dt: float) -> int:
    """How many steps a fixed-step method takes over [t0, t1]: ``dt`` shortened so that a
    whole number of steps ends exactly at t1 (a step within 1e-9 of a whole number of
    ``dt`` is not split)."""
    return max(1, math.ceil(abs(t1 - t0) / dt - 1e-9))
