"""Between steps, compiled: dense output, output rows at the requested times, the stop time.

A step from t_old to t_old + h leaves an interpolant of the state x(t_old + s h), 0 <= s <= 1,
kept as rows of an array F, of one of three kinds:

    RK45 (kind 0):     x = x_old + h sum_k F_k s^(k+1)              (F = K^T P, SciPy's P)
    DOP853 (kind 1):   x = x_old + F_0 + (1-s)(F_1 + s(F_2 + ...))   (SciPy's nested form, read
                                                                      from the last row back)
    Hermite (kind 2):  the cubic through x and f at both ends, F = [x_old, x, f_old, f]

The stop condition g(t, q, q_dot) ends a run where it turns negative; that time is found on
the interpolant by the Illinois method (regula falsi, halving the value kept at a stale end),
to 4 ulp of t.  :func:`start_run` and :func:`end_step` are what every integration loop does
before its first step and after each step; the loops differ only in how they step.  This
module is imported only when numba is installed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lagrangian.numerics.fast.outcome import FINISHED, SINGULAR, STOPPED
from lagrangian.numerics.fast.rates import bind, coordinate_count, state_rates

RK45_DENSE, DOP853_DENSE, HERMITE_DENSE = 0, 1, 2
ULP = 2.220446049250313e-16


@njit(cache=False, nogil=True, error_model="numpy")
def dense_value(t, t_old, h, y_old, F, kind, out) -> None:
    """The interpolated state at t (see the module docstring for the three kinds)."""
    s = (t - t_old) / h
    n = out.size
    if kind == HERMITE_DENSE:
        h00, h10 = (1 + 2 * s) * (1 - s) ** 2, s * (1 - s) ** 2
        h01, h11 = s**2 * (3 - 2 * s), s**2 * (s - 1)
        for i in range(n):
            out[i] = h00 * F[0, i] + h10 * h * F[2, i] + h01 * F[1, i] + h11 * h * F[3, i]
        return
    if kind == RK45_DENSE:
        for i in range(n):
            total, power = 0.0, 1.0
            for k in range(F.shape[0]):
                power *= s
                total += F[k, i] * power
            out[i] = h * total + y_old[i]
        return
    rows = F.shape[0]
    for i in range(n):
        value = 0.0
        for r in range(rows):
            value += F[rows - 1 - r, i]
            value *= s if r % 2 == 0 else 1 - s
        out[i] = value + y_old[i]


@njit(cache=False, nogil=True, error_model="numpy")
def condition(system, stop, t, y, n, f) -> float:
    """g(t, q, q_dot) at state y; q_dot from the rates (first-order coordinates included)."""
    if not state_rates(system, t, y, f):
        return np.nan
    return stop(t, y[:n], f[:n])


@njit(cache=False, nogil=True, error_model="numpy")
def locate_stop(system, stop, interval, y_old, F, kind, n):
    """The time in (t_old, t_new] where g turns negative, ``interval`` = (t_old, g_old,
    t_new, g_new, h), g_old >= 0 > g_new (or g_new not a number)."""
    a, ga, b, gb, h = interval
    if not gb < 0:
        gb = -1.0
    y, f = np.empty(y_old.size), np.empty(y_old.size)
    t_old, side = a, 0
    for _ in range(200):
        if b - a <= 4 * ULP * max(abs(a), abs(b)):
            break
        c = b - gb * (b - a) / (gb - ga)
        if not a < c < b:
            c = 0.5 * (a + b)
        dense_value(c, t_old, h, y_old, F, kind, y)
        gc = condition(system, stop, c, y, n, f)
        if gc >= 0:
            a, ga = c, gc
            if side == 1:
                gb *= 0.5
            side = 1
        else:  # negative, or not a number: the stop lies before c
            b, gb = c, (gc if gc < 0 else -1.0)
            if side == -1:
                ga *= 0.5
            side = -1
    return b


@njit(cache=False, nogil=True, error_model="numpy")
def grow(times, states, rows):
    """Twice the room for every-step output, keeping the first ``rows`` rows."""
    if rows < times.size:
        return times, states
    bigger_t = np.empty(2 * times.size)
    bigger_x = np.empty((2 * times.size, states.shape[1]))
    for row in range(rows):
        bigger_t[row] = times[row]
        put(bigger_x[row], states[row])
    return bigger_t, bigger_x


@njit(cache=False, nogil=True, error_model="numpy")
def sample(t_out, out, first, t_end, t_old, h, y_old, F, kind) -> int:
    """Fill the output rows from ``first`` whose times are <= t_end; the next row to fill."""
    row = first
    while row < t_out.size and t_out[row] <= t_end:
        dense_value(t_out[row], t_old, h, y_old, F, kind, out[row])
        row += 1
    return row


@njit(cache=False, nogil=True, error_model="numpy")
def finite(values) -> bool:
    """Whether every entry is a finite number."""
    for i in range(values.size):  # noqa: SIM110  (numba compiles no generator in all())
        if not math.isfinite(values[i]):
            return False
    return True


@njit(cache=False, nogil=True, error_model="numpy")
def put(target, values) -> None:
    """target[:] = values, as a loop (numba compiles slice assignment slowly)."""
    for i in range(values.size):
        target[i] = values[i]


@njit(cache=False, nogil=True, error_model="numpy")
def start_output(t0, x0, t_out, out):
    """(times, states, rows) of a run's output before its first step: every step (``t_out``
    empty: growable arrays holding t0, x0) or the requested times up to t0, filled with x0."""
    nx = x0.size
    every = t_out.size == 0
    times, states = (np.empty(64), np.empty((64, nx))) if every else (t_out, out)
    rows = 0
    if every:
        times[0], rows = t0, 1
        put(states[0], x0)
    else:
        while rows < t_out.size and t_out[rows] <= t0:
            put(out[rows], x0)
            rows += 1
    return times, states, rows


@njit(cache=False, nogil=True, error_model="numpy")
def start_run(function, equations, stop, watch, t0, x0, p, t_out, out, f):
    """Before the first step from (t0, x0): the right-hand side bound to the parameters p
    (:func:`lagrangian.numerics.fast.rates.bind`), two scratch states ``work``, the output
    so far (:func:`start_output`), f(t0, x0) written into ``f`` and g(t0) (1 when not
    ``watch``ed).  Returns (system, work, times, states, rows, status, g): status SINGULAR
    when the rates fail at the start, STOPPED when g(t0) < 0 already, else FINISHED (go on)."""
    nx = x0.size
    n = coordinate_count(equations)
    system = bind(function, equations, p, nx)
    work = (np.empty(nx), np.empty(nx))
    times, states, rows = start_output(t0, x0, t_out, out)
    if not state_rates(system, t0, x0, f):
        return system, work, times, states, rows, SINGULAR, 1.0
    g = stop(t0, x0[:n], f[:n]) if watch else 1.0
    return system, work, times, states, rows, (FINISHED if g >= 0 else STOPPED), g


@njit(cache=False, nogil=True, error_model="numpy")
def end_step(system, stop, interval, x_old, x, F, kind, n, t_out, output):
    """After a step over ``interval`` = (t_old, g_old, t, g_new, h) whose interpolant is F
    (from ``x_old``, ending at ``x``): where g turned negative, the stop time and state on the
    interpolant; then the output up to there, ``output`` = (times, states, rows), every step
    (``t_out`` empty) or at the requested times.  Returns (times, states, rows, stopped,
    t_end, x_end): the end of the step, or the stop."""
    t_old, _, t, g_new, h = interval
    times, states, rows = output
    t_end, x_end, stopped = t, x, not g_new >= 0
    if stopped:
        t_end = locate_stop(system, stop, interval, x_old, F, kind, n)
        x_end = np.empty(x.size)
        dense_value(t_end, t_old, h, x_old, F, kind, x_end)
    if t_out.size == 0:
        times, states = grow(times, states, rows)
        times[rows] = t_end
        put(states[rows], x_end)
        rows += 1
    else:
        rows = sample(t_out, states, rows, t_end, t_old, h, x_old, F, kind)
    return times, states, rows, stopped, t_end, x_end
