"""The classical fixed-step RK4 compiled by numba, as :mod:`lagrangian.simulation.integrators.rk4`
does it.

    k1 = f(t, x),            k2 = f(t + h/2, x + h/2 k1),
    k3 = f(t + h/2, x + h/2 k2),  k4 = f(t + h, x + h k3),
    x(t + h) = x + h/6 (k1 + 2 k2 + 2 k3 + k4)                  global error O(h^4)

h is ``dt`` shortened so that a whole number of steps ends exactly at t1 (step i ends at
t0 + i h); output between steps is the cubic Hermite interpolant of x and f at both ends, and
the stop condition is located on it (:mod:`lagrangian.numerics.fast.dense`).  This module is
imported only when numba is installed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lagrangian.numerics.fast.dense import HERMITE_DENSE, end_step, finite, put, start_run
from lagrangian.numerics.fast.outcome import FINISHED, NOT_FINITE, SINGULAR, STOPPED
from lagrangian.numerics.fast.rates import coordinate_count, state_rates


@njit(cache=False, nogil=True, error_model="numpy")
def rk4_step(system, t, x, h, k, x_new, work) -> bool:
    """x_new = x(t + h) from k[0] = f(t, x); k[1..3] receive the other stages."""
    stage = work[0]
    for s, c in ((1, h / 2), (2, h / 2), (3, h)):
        for i in range(x.size):
            stage[i] = x[i] + c * k[s - 1, i]
        if not state_rates(system, t + c, stage, k[s]):
            return False
    for i in range(x.size):
        x_new[i] = x[i] + h / 6 * (k[0, i] + 2 * k[1, i] + 2 * k[2, i] + k[3, i])
    return True


@njit(cache=False, nogil=True, error_model="numpy")
def integrate_rk4(function, equations, stop, watch, x0, p, span, t_out, out, config):
    """RK4 from (t0, x0) over ``span`` = (t0, t1); arguments and result as
    :func:`lagrangian.numerics.fast.adaptive.integrate_adaptive` (``config`` = (dt,))."""
    dt = config[0]
    t0, t1 = span
    nx = x0.size
    steps = max(1, math.ceil(abs(t1 - t0) / dt - 1e-9))
    h = (t1 - t0) / steps
    k, F = np.empty((4, nx)), np.empty((4, nx))
    t, x, x_new = t0, x0.copy(), np.empty(nx)
    n = coordinate_count(equations)
    system, work, times, states, rows, status, g_old = start_run(
        function, equations, stop, watch, t, x, p, t_out, out, k[0]
    )
    if status != FINISHED:
        return times, states, rows, status, t, x, t, x.copy()
    t_stop, x_stop = t1, x
    for taken in range(1, steps + 1):
        if not rk4_step(system, t, x, h, k, x_new, work):
            status = SINGULAR
            break
        if not finite(x_new):
            status = NOT_FINITE
            break
        t_new = t1 if taken == steps else t0 + taken * h
        put(F[0], x)
        put(F[1], x_new)
        put(F[2], k[0])
        if not state_rates(system, t_new, x_new, k[0]):
            status = SINGULAR
            break
        put(F[3], k[0])
        t_old, t = t, t_new
        put(x, x_new)
        g_new = stop(t, x[:n], k[0][:n]) if watch else 1.0
        # the Hermite interpolant reads both ends from F: x stands in for x_old
        interval, output = (t_old, g_old, t, g_new, t - t_old), (times, states, rows)
        times, states, rows, stopped, t_end, x_end = end_step(
            system, stop, interval, x, x, F, HERMITE_DENSE, n, t_out, output
        )
        g_old = g_new
        if stopped:
            status, t_stop, x_stop = STOPPED, t_end, x_end
            break
    if status == FINISHED:
        x_stop = x.copy()
    return times, states, rows, status, t, x, t_stop, x_stop
