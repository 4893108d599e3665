"""Adaptive Runge–Kutta integration compiled by numba: SciPy's RK45 and DOP853, step for step.

The loop is ``scipy.integrate.solve_ivp``'s (``scipy/integrate/_ivp/rk.py``), written out so
that the same steps are taken: the initial step of Hairer, Nørsett & Wanner (Solving ODEs I,
II.4), and after a trial step h with error norm err (RMS over the state of the error estimate
divided by atol + rtol max(|x|, |x_new|)),

    accept when err < 1:  h <- h min(10, 0.9 err^(-1/(k+1)))   (at most h after a rejection)
    reject otherwise:     h <- h max(0.2, 0.9 err^(-1/(k+1))),

k the order of the error estimator (4 for RK45, 7 for DOP853).  Output at the requested times
comes from each step's dense output, as in solve_ivp; an optional stop condition g(t, q, q_dot)
ends the run where g turns negative, its time located on the dense output by the Illinois
method (regula falsi that halves the stale end's value).

The helpers are compiled by numba when the loop is (:mod:`lagrangian.numerics.fast.loops`
compiles ``integrate_adaptive`` once for every system); this module is imported only when
numba is installed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lagrangian.numerics.fast.dense import (
    DOP853_DENSE,
    RK45_DENSE,
    end_step,
    finite,
    put,
    start_run,
)
from lagrangian.numerics.fast.outcome import (
    FINISHED,
    NOT_FINITE,
    SINGULAR,
    STEP_TOO_SMALL,
    STOPPED,
)
from lagrangian.numerics.fast.rates import coordinate_count, state_rates

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0


@njit(cache=False, nogil=True, error_model="numpy")
def scaled_rms(values, y, rtol, atol) -> float:
    """sqrt(mean((values / (atol + rtol |y|))^2)), SciPy's norm for the initial step."""
    total = 0.0
    for i in range(values.size):
        total += (values[i] / (atol + abs(y[i]) * rtol)) ** 2
    return math.sqrt(total / values.size)


@njit(cache=False, nogil=True, error_model="numpy")
def initial_step(system, t0, y0, f0, t_bound, max_step, order, rtol, atol, work) -> float:
    """SciPy's select_initial_step: h from the sizes of x, f and the change of f over h0;
    -1 when the right-hand side fails."""
    y1, f1 = work
    interval = abs(t_bound - t0)
    d0, d1 = scaled_rms(y0, y0, rtol, atol), scaled_rms(f0, y0, rtol, atol)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(y0.size):
        y1[i] = y0[i] + h0 * f0[i]
    if not state_rates(system, t0 + h0, y1, f1):
        return -1.0
    for i in range(y0.size):
        f1[i] -= f0[i]
    d2 = scaled_rms(f1, y0, rtol, atol) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100 * h0, h1, interval, max_step)


@njit(cache=False, nogil=True, error_model="numpy")
def stage_state(K, a, s, y, h, out) -> None:
    """out = y + (sum_{j<s} a_j K_j) h, in solve_ivp's order of operations."""
    for i in range(y.size):
        total = 0.0
        for j in range(s):
            total += K[j, i] * a[j]
        out[i] = y[i] + total * h


@njit(cache=False, nogil=True, error_model="numpy")
def rk_step(system, t, y, h, tableau, K, y_new, work) -> bool:
    """One trial step: stages K_0..K_{s-1}, y_new, and K_s = f(t + h, y_new)."""
    A, B, C = tableau[0], tableau[1], tableau[2]
    stage = work[0]
    stages = B.size
    for s in range(1, stages):
        stage_state(K, A[s], s, y, h, stage)
        if not state_rates(system, t + C[s] * h, stage, K[s]):
            return False
    for i in range(y.size):
        total = 0.0
        for j in range(stages):
            total += K[j, i] * B[j]
        y_new[i] = y[i] + h * total
    return state_rates(system, t + h, y_new, K[stages])


@njit(cache=False, nogil=True, error_model="numpy")
def error_norm(K, h, y, y_new, rtol, atol, tableau) -> float:
    """RK45: rms(h K^T E / scale); DOP853: Hairer's estimate from E5 and E3; the scale is
    atol + rtol max(|y|, |y_new|)."""
    E, E3, dop853 = tableau[3], tableau[4], tableau[9]
    n = y.size
    scale = np.empty(n)
    for i in range(n):
        scale[i] = atol + max(abs(y[i]), abs(y_new[i])) * rtol
    if not dop853:
        total = 0.0
        for i in range(n):
            e = 0.0
            for j in range(E.size):
                e += K[j, i] * E[j]
            total += (e * h / scale[i]) ** 2
        return math.sqrt(total / n)
    e5_squared, e3_squared = 0.0, 0.0
    for i in range(n):
        e5, e3 = 0.0, 0.0
        for j in range(E.size):
            e5 += K[j, i] * E[j]
            e3 += K[j, i] * E3[j]
        e5_squared += (e5 / scale[i]) ** 2
        e3_squared += (e3 / scale[i]) ** 2
    if e5_squared == 0.0 and e3_squared == 0.0:
        return 0.0
    return abs(h) * e5_squared / math.sqrt((e5_squared + 0.01 * e3_squared) * n)


@njit(cache=False, nogil=True, error_model="numpy")
def dense_coefficients(system, t_old, y_old, y, f, h, tableau, K, F, work) -> bool:
    """The interpolant of the last step: RK45's Q = K^T P, or DOP853's F (3 extra stages)."""
    P, A_extra, C_extra, D, dop853 = tableau[5], tableau[6], tableau[7], tableau[8], tableau[9]
    stage = work[0]
    n = y.size
    if not dop853:
        for k in range(P.shape[1]):
            for i in range(n):
                total = 0.0
                for j in range(P.shape[0]):
                    total += K[j, i] * P[j, k]
                F[k, i] = total
        return True
    first = K.shape[0] - A_extra.shape[0]
    for e in range(A_extra.shape[0]):
        s = first + e
        stage_state(K, A_extra[e], s, y_old, h, stage)
        if not state_rates(system, t_old + C_extra[e] * h, stage, K[s]):
            return False
    for i in range(n):
        delta = y[i] - y_old[i]
        F[0, i] = delta
        F[1, i] = h * K[0, i] - delta
        F[2, i] = 2 * delta - h * (f[i] + K[0, i])
        for r in range(D.shape[0]):
            total = 0.0
            for j in range(D.shape[1]):
                total += D[r, j] * K[j, i]
            F[3 + r, i] = h * total
    return True


@njit(cache=False, nogil=True, error_model="numpy")
def spacing(t) -> float:
    """nextafter(t, inf) - t for t >= 0: one ulp (2^(e-53) for t = m 2^e, 1/2 <= m < 1)."""
    if t == 0.0:
        return 5e-324
    return math.ldexp(1.0, math.frexp(t)[1] - 53)


@njit(cache=False, nogil=True, error_model="numpy")
def adaptive_step(system, t, y, f, h_abs, t1, tolerances, tableau, K, y_new, work):
    """One accepted step of SciPy's RungeKutta._step_impl from (t, y) with f = f(t, y).

    Returns (status, t_new, h, next h_abs); K holds the stages, y_new the new state.
    """
    rtol, atol, max_step = tolerances
    exponent = -1.0 / (tableau[10] + 1)
    min_step = 10 * spacing(t)
    h_abs = min(h_abs, max_step) if h_abs > min_step else min_step
    rejected = False
    while True:
        if h_abs < min_step:
            return STEP_TOO_SMALL, t, 0.0, h_abs
        t_new = min(t + h_abs, t1)
        h = t_new - t
        h_abs = abs(h)
        put(K[0], f)
        if not rk_step(system, t, y, h, tableau, K, y_new, work):
            return SINGULAR, t, h, h_abs
        err = error_norm(K, h, y, y_new, rtol, atol, tableau)
        if err < 1:
            factor = MAX_FACTOR if err == 0 else min(MAX_FACTOR, SAFETY * err**exponent)
            if rejected:
                factor = min(1.0, factor)
            return FINISHED, t_new, h, h_abs * factor
        factor = SAFETY * err**exponent
        h_abs *= factor if factor > MIN_FACTOR else MIN_FACTOR  # NaN error: shrink by 0.2
        rejected = True


@njit(cache=False, nogil=True, error_model="numpy")
def integrate_adaptive(function, equations, stop, watch, x0, p, span, t_out, out, config):
    """Integrate from (t0, x0) over ``span`` = (t0, t1), output at ``t_out`` into ``out``.

    ``function``, ``equations``: the system's right-hand side (:mod:`lagrangian.numerics.
    fast.rates`), with the parameters ``p``.  ``config`` = ((rtol, atol, max_step), tableau of
    :mod:`lagrangian.numerics.fast.tableaus`).  ``out`` rows after a stop or a failure are
    left as given (NaN).  With an empty ``t_out`` every step is recorded instead, in arrays
    grown as needed.  ``watch``: whether to check the stop condition ``stop(t, q, q_dot)``
    (n coordinates).  Returns (times, states, rows, status, t_reached, x_reached, t_stop,
    x_stop).
    """
    tolerances, tableau = config
    t0, t1 = span
    nx = x0.size
    kind = DOP853_DENSE if tableau[9] else RK45_DENSE
    K = np.empty((tableau[1].size + 1 + tableau[7].size * tableau[9], nx))
    F = np.empty((7 if tableau[9] else tableau[5].shape[1], nx))
    t, y, f = t0, x0.copy(), np.empty(nx)
    y_old, y_new = np.empty(nx), np.empty(nx)
    n = coordinate_count(equations)
    system, work, times, states, rows, status, g_old = start_run(
        function, equations, stop, watch, t, y, p, t_out, out, f
    )
    if status != FINISHED:
        return times, states, rows, status, t, y, t, y.copy()
    rtol, atol, max_step = tolerances
    h_abs = initial_step(system, t, y, f, t1, max_step, tableau[10], rtol, atol, work)
    if h_abs < 0:
        return times, states, rows, SINGULAR, t, y, t, y
    t_stop, x_stop = t1, y
    while t < t1:
        status, t_new, h, h_abs = adaptive_step(
            system, t, y, f, h_abs, t1, tolerances, tableau, K, y_new, work
        )
        if status != FINISHED:
            break
        if not finite(y_new):
            status = NOT_FINITE
            break
        t_old = t
        put(y_old, y)
        put(y, y_new)
        put(f, K[tableau[1].size])
        t = t_new
        g_new = stop(t, y[:n], f[:n]) if watch else 1.0
        # the interpolant is needed for output at given times and to locate a stop
        needed = t_out.size > 0 or not g_new >= 0
        if needed and not dense_coefficients(system, t_old, y_old, y, f, h, tableau, K, F, work):
            status = SINGULAR
            break
        interval, output = (t_old, g_old, t, g_new, h), (times, states, rows)
        times, states, rows, stopped, t_end, x_end = end_step(
            system, stop, interval, y_old, y, F, kind, n, t_out, output
        )
        g_old = g_new
        if stopped:
            status, t_stop, x_stop = STOPPED, t_end, x_end
            break
    if status == FINISHED:
        x_stop = y.copy()
    return times, states, rows, status, t, y, t_stop, x_stop
