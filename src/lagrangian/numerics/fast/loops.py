"""The compiled loops, typed once for every system: the right-hand side is a function value.

Numba would otherwise specialize (and recompile, and inline at every call site) each loop for
each generated right-hand side.  Declared with explicit signatures in which ``rates`` and the
stop condition are first-class function types,

    rates(t, x, p, matrix, vector, dx) -> bool          RATES
    stop(t, q, q_dot) -> float                           STOP

the loops compile once (several seconds) and are the same for every system, so they are kept
in numba's on-disk cache; a new system only compiles its own ``rates``, which is never cached.
Numba checks a cached loop against the time stamp of the loop's own file only: after editing
the helpers it calls (``dense.py``), delete the cache (``__pycache__/*.nbi``, ``*.nbc``).
This module is imported only when numba is installed.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
from numba import njit, types

from lagrangian.numerics.fast.adaptive import integrate_adaptive
from lagrangian.numerics.fast.fixed import integrate_rk4
from lagrangian.numerics.fast.outcome import FINISHED, STOPPED

_f = types.float64
_vector = types.Array(_f, 1, "C")
_matrix = types.Array(_f, 2, "C")
_any_vector = types.Array(_f, 1, "A")

#: rates(t, x, p, matrix, vector, dx) -> ok, the signature of every generated right-hand side.
RATES = types.boolean(_f, _vector, _vector, _matrix, _vector, _vector)
#: stop(t, q, q_dot) -> g (the member stops where g turns negative).
STOP = _f(_f, _any_vector, _any_vector)

#: A, B, C, E, E3, P, A_extra, C_extra, D, then is_dop853 and the error order.
_TABLEAU_ARRAYS = (_matrix, _vector, _vector, _vector, _vector, _matrix, _matrix, _vector, _matrix)
_TABLEAU = types.Tuple((*_TABLEAU_ARRAYS, types.boolean, types.int64))
_CONFIG = {
    "adaptive": types.Tuple((types.UniTuple(_f, 3), _TABLEAU)),
    "rk4": types.UniTuple(_f, 1),
}
_LOOPS = {"adaptive": integrate_adaptive, "rk4": integrate_rk4}
_RESULT = types.Tuple((_vector, _matrix, types.int64, types.int64, _f, _vector, _f, _vector))


def _arguments(kind: str) -> tuple[Any, ...]:
    functions = (types.FunctionType(RATES), types.FunctionType(STOP))
    run = (types.boolean, types.int64, types.int64, _vector, _vector, types.UniTuple(_f, 2))
    return (*functions, *run, _vector, _matrix, _CONFIG[kind])


@cache
def single_loop(kind: str) -> Any:
    """The compiled loop of ``kind`` ("adaptive" or "rk4"), see
    :func:`lagrangian.numerics.fast.adaptive.integrate_adaptive`."""
    signature = _RESULT(*_arguments(kind))
    return njit(signature, cache=True, nogil=True, error_model="numpy")(_LOOPS[kind].py_func)


def adaptive_members(
    rates, stop, watch, n, size, X0, P, span, t_out, out, config, first, last, ends
):
    """Members first..last-1 of a batch, each by ``integrate_adaptive`` (see ``batch_loop``)."""
    for i in range(first, last):
        result = integrate_adaptive(
            rates, stop, watch, n, size, X0[i], P[i], span, t_out, out[i], config
        )
        keep(result, i, ends)


def rk4_members(rates, stop, watch, n, size, X0, P, span, t_out, out, config, first, last, ends):
    """Members first..last-1 of a batch, each by ``integrate_rk4`` (see ``batch_loop``)."""
    for i in range(first, last):
        result = integrate_rk4(
            rates, stop, watch, n, size, X0[i], P[i], span, t_out, out[i], config
        )
        keep(result, i, ends)


@njit(cache=False, nogil=True)
def keep(result, i, ends):
    """Member i's status, final time and final state (the end, its stop or its last step)."""
    status, t_final, x_final = ends
    ended = result[3] == STOPPED or result[3] == FINISHED
    status[i] = result[3]
    t_final[i] = result[6] if ended else result[4]
    final = result[7] if ended else result[5]
    for j in range(final.size):
        x_final[i, j] = final[j]


_MEMBERS = {"adaptive": adaptive_members, "rk4": rk4_members}


@cache
def batch_loop(kind: str) -> Any:
    """The compiled loop over members first..last-1 of a batch: every member integrated on
    its own by the same loop as a single run, with one call from Python per chunk.

    Arguments: as the single loop's, with X0, P (one row per member) and out (members,
    times, state) instead of one member's, then first, last and ``ends`` = (status, t_final,
    x_final), the arrays it fills.
    """
    arguments = list(_arguments(kind))
    arguments[5:7] = [_matrix, _matrix]  # X0, P
    arguments[9] = types.Array(_f, 3, "C")  # out
    ends = types.Tuple((types.Array(types.int64, 1, "C"), _vector, _matrix))
    signature = types.void(*arguments, types.int64, types.int64, ends)
    return njit(signature, cache=True, nogil=True, error_model="numpy")(_MEMBERS[kind])


def contiguous(values: Any, ndim: int) -> np.ndarray:
    """A C-contiguous float array of ``ndim`` dimensions (what the signatures ask for)."""
    array = np.ascontiguousarray(values, dtype=float)
    if array.ndim != ndim:
        raise ValueError(f"expected {ndim} dimensions, got shape {array.shape}")
    return array
