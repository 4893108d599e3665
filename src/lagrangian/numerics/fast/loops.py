"""The compiled loops, typed once for every system: the right-hand side is a function value.

Every system's right-hand side is a C function of one signature (:mod:`~lagrangian.numerics.
fast.compiled_rates`), passed to the loops as a first-class function value, with its
``user_data`` pointer and the layout of its state:

    f(out, in, user_data)                              C_FUNCTION
    equations = (user_data, second, first, size)       EQUATIONS
    stop(t, q, q_dot) -> float                         STOP

so each loop is compiled once per machine (several seconds) with an explicit signature and
kept in numba's on-disk cache; a new system costs only its own C function (milliseconds with
SymEngine's LLVM backend).  The cache is ``__pycache__`` beside these files, or, where the
package folder is read-only (an installed package), numba's user-wide cache folder, or
``NUMBA_CACHE_DIR`` when set; where no folder is writable at all, the loops are compiled in
every process instead.  Numba checks a cached loop against the time stamp of the loop's own
file only: after editing the helpers it calls (``dense.py``, ``rates.py``), delete the cache
(``__pycache__/*.nbi``, ``*.nbc``).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import pickle
import warnings
from functools import cache
from typing import Any

import numba.experimental.function_type  # noqa: F401  (numba types a WrapperAddressProtocol)
import numpy as np
from numba import njit, types
from numba.core.errors import NumbaExperimentalFeatureWarning

from lagrangian.numerics.fast.adaptive import integrate_adaptive
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.fixed import integrate_rk4
from lagrangian.numerics.fast.outcome import FINISHED, STOPPED

_f = types.float64
_vector = types.Array(_f, 1, "C")
_matrix = types.Array(_f, 2, "C")
_any_vector = types.Array(_f, 1, "A")
_indices = types.Array(types.int64, 1, "C")

#: void f(double *out, const double *in, void *user_data): every system's right-hand side.
C_FUNCTION = types.void(types.CPointer(_f), types.CPointer(_f), types.intp)
#: (user_data, second, first, size), see :mod:`lagrangian.numerics.fast.rates`.
EQUATIONS = types.Tuple((types.intp, _indices, _indices, types.int64))
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


class CFunction(types.WrapperAddressProtocol):
    """A C function of signature C_FUNCTION at ``address``, as numba passes it to the loops."""

    def __init__(self, address: int) -> None:
        self.address = address

    def __wrapper_address__(self) -> int:
        return self.address

    def signature(self) -> Any:
        return C_FUNCTION


def system_arguments(fast: FastEquations) -> tuple[Any, Any]:
    """The first two arguments of the loops for ``fast``: the C function and EQUATIONS.
    ``fast`` owns the machine code: keep it alive while the loops run."""
    function = fast.function
    equations = (
        function.user_data,
        np.array(fast.second, dtype=np.int64),
        np.array(fast.first, dtype=np.int64),
        fast.size,
    )
    return CFunction(function.address), equations


def _arguments(kind: str) -> tuple[Any, ...]:
    system = (types.FunctionType(C_FUNCTION), EQUATIONS, types.FunctionType(STOP))
    run = (types.boolean, _vector, _vector, types.UniTuple(_f, 2))
    return (*system, *run, _vector, _matrix, _CONFIG[kind])


#: What numba raises reading a cache file that is cut short or garbled.
CORRUPT_CACHE = (pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError)


def compile_cached(signature: Any, function: Any) -> Any:
    """``function`` compiled by numba for ``signature``, from the on-disk cache when there
    is one; compiled in this process when no cache folder is writable; compiled again and
    cached anew when the cache is corrupt."""
    options: dict[str, Any] = {"nogil": True, "error_model": "numpy"}
    with warnings.catch_warnings():
        # first-class function values are what makes one loop serve every system
        warnings.simplefilter("ignore", NumbaExperimentalFeatureWarning)
        try:
            return njit(signature, cache=True, **options)(function)
        except RuntimeError as error:  # numba: "cannot cache function ...: no locator"
            if "cannot cache" not in str(error):
                raise
            return njit(signature, cache=False, **options)(function)
        except CORRUPT_CACHE:  # a cache file cut short (a full disk, a killed process)
            njit(cache=True, **options)(function)._cache.flush()  # forget it, then rebuild
            return njit(signature, cache=True, **options)(function)


@cache
def single_loop(kind: str) -> Any:
    """The compiled loop of ``kind`` ("adaptive" or "rk4"), see
    :func:`lagrangian.numerics.fast.adaptive.integrate_adaptive`."""
    return compile_cached(_RESULT(*_arguments(kind)), _LOOPS[kind].py_func)


def adaptive_members(f, equations, stop, watch, X0, P, span, t_out, out, config, first, last, ends):
    """Members first..last-1 of a batch, each by ``integrate_adaptive`` (see ``batch_loop``)."""
    for i in range(first, last):
        member = (X0[i], P[i], span, t_out, out[i], config)
        keep(integrate_adaptive(f, equations, stop, watch, *member), i, ends)


def rk4_members(f, equations, stop, watch, X0, P, span, t_out, out, config, first, last, ends):
    """Members first..last-1 of a batch, each by ``integrate_rk4`` (see ``batch_loop``)."""
    for i in range(first, last):
        member = (X0[i], P[i], span, t_out, out[i], config)
        keep(integrate_rk4(f, equations, stop, watch, *member), i, ends)


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
    arguments[4:6] = [_matrix, _matrix]  # X0, P
    arguments[8] = types.Array(_f, 3, "C")  # out
    ends = types.Tuple((types.Array(types.int64, 1, "C"), _vector, _matrix))
    signature = types.void(*arguments, types.int64, types.int64, ends)
    return compile_cached(signature, _MEMBERS[kind])


def contiguous(values: Any, ndim: int) -> np.ndarray:
    """A C-contiguous float array of ``ndim`` dimensions (what the signatures ask for)."""
    array = np.ascontiguousarray(values, dtype=float)
    if array.ndim != ndim:
        raise ValueError(f"expected {ndim} dimensions, got shape {array.shape}")
    return array
