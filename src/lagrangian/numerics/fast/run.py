"""Drive the compiled loops: one integration, or a batch of them.

Every member of a batch is integrated on its own, with its own adaptive steps, by the same
compiled loop as a single run, so member i of a batch is the run of member i alone.  The
compiled batch loop takes chunks of members (one call from Python per chunk: a call costs
about 0.1 ms, as much as a short integration); it releases the GIL, so ``workers`` threads
run chunks at once.  This module is imported only when numba is installed.
"""

from __future__ import annotations

import contextlib
import weakref
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
from numba import njit

from lagrangian.errors import SimulationError
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.loops import (
    STOP,
    batch_loop,
    compile_cached,
    contiguous,
    single_loop,
    system_arguments,
)
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.fast.tableaus import ADAPTIVE, adaptive_tableau

#: Members per call into the compiled batch loop (one progress update each).
CHUNK = 256


def never_stop(t, q, q_dot) -> float:
    """The stop condition of a run without one: never negative."""
    return 1.0


@cache
def never() -> Any:
    """``never_stop`` compiled (on first use: loading it starts numba up)."""
    return compile_cached(STOP, never_stop)


def compiled_loop(settings: Settings, batch: bool = False) -> tuple[Any, tuple[Any, ...]]:
    """The compiled loop of ``settings.method`` (of one member, or of a batch) and its
    ``config`` argument (tolerances and tableau, or the step)."""
    compiled = batch_loop if batch else single_loop
    if settings.method in ADAPTIVE:
        tolerances = (float(settings.rtol), float(settings.atol), float(settings.max_step))
        return compiled("adaptive"), (tolerances, adaptive_tableau(settings.method))
    if settings.method == "RK4" and settings.dt is not None:
        return compiled("rk4"), (float(settings.dt),)
    raise SimulationError(f"The numba backend has no method {settings.method!r}.")


@dataclass(frozen=True)
class FastRun:
    """One integration: output times and states, how it ended, the last and stop states."""

    t: np.ndarray
    x: np.ndarray
    status: int
    t_reached: float
    x_reached: np.ndarray
    t_stop: float
    x_stop: np.ndarray


def compile_stop(stop_when: Callable[..., Any] | None) -> Any:
    """``stop_when`` compiled by numba for one member (``never`` when None).

    Raises SimulationError when numba cannot compile it.
    """
    if stop_when is None:
        return never()
    from numba.core.errors import NumbaError

    function = getattr(stop_when, "py_func", stop_when)  # also a numba function's own
    with contextlib.suppress(TypeError):  # not weakly referable: compiled each time
        if function in _COMPILED_STOPS:
            return _COMPILED_STOPS[function]
    try:
        compiled = njit(STOP, cache=False, nogil=True, error_model="numpy")(function)
    except NumbaError as error:
        first = str(error).strip().splitlines()[0]
        raise SimulationError(
            f"stop_when: numba cannot compile {getattr(function, '__name__', function)!r} "
            f"({first}); with backend='numba' it must be a function of (t, q, q_dot) that "
            "numba compiles (NumPy and math on floats and 1-d arrays), returning a float."
        ) from error
    with contextlib.suppress(TypeError):
        _COMPILED_STOPS[function] = compiled
    return compiled


#: Each stop function compiled once per process (a sweep's blocks share one on a worker).
_COMPILED_STOPS: weakref.WeakKeyDictionary[Any, Any] = weakref.WeakKeyDictionary()


def integrate(
    fast: FastEquations,
    settings: Settings,
    x0: np.ndarray,
    p: np.ndarray,
    stop_when: Callable[..., Any] | None = None,
) -> FastRun:
    """Integrate one member; an empty ``settings.t_out`` records every step."""
    out = np.full((len(settings.t_out), len(x0)), np.nan)
    run = _caller(fast, settings, stop_when)
    times, states, rows, status, t_reached, x_reached, t_stop, x_stop = run(
        contiguous(x0, 1), contiguous(p, 1), out
    )
    return FastRun(
        times[:rows].copy(), states[:rows].copy(), int(status), t_reached, x_reached, t_stop, x_stop
    )


@dataclass(frozen=True)
class BatchRun:
    """A batch: output states (members, times, state), and per member how it ended, the
    time of its last state (end, stop or failure) and that state."""

    x: np.ndarray
    status: np.ndarray
    t_final: np.ndarray
    x_final: np.ndarray


def integrate_batch(
    fast: FastEquations,
    settings: Settings,
    X0: np.ndarray,
    P: np.ndarray,
    stop_when: Callable[..., Any] | None = None,
    progress: Callable[[int], None] | None = None,
    workers: int = 1,
) -> BatchRun:
    """Integrate every row of X0 with the parameters of the same row of P, each on its own.

    ``progress`` is called with the number of members done after each chunk of members;
    ``workers`` threads run chunks at once (the compiled loop releases the GIL).
    """
    X0, P = contiguous(X0, 2), contiguous(P, 2)
    k = len(X0)
    out = np.full((k, len(settings.t_out), X0.shape[1]), np.nan)
    ends = (np.zeros(k, dtype=np.int64), np.zeros(k), np.zeros_like(X0))
    loop, last = compiled_loop(settings, batch=True)
    stop, watch = compile_stop(stop_when), stop_when is not None  # compiled here, or refused
    function, equations = system_arguments(fast)
    span = (float(settings.span[0]), float(settings.span[1]))
    t_out = contiguous(settings.t_out, 1)

    def chunk(first: int) -> int:
        end = min(first + CHUNK, k)
        loop(function, equations, stop, watch, X0, P, span, t_out, out, last, first, end, ends)
        return end - first

    done = 0
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        for count in pool.map(chunk, range(0, k, CHUNK)):
            done += count
            if progress is not None:
                progress(done)
    return BatchRun(out, *ends)


def _caller(
    fast: FastEquations, settings: Settings, stop_when: Callable[..., Any] | None
) -> Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[Any, ...]]:
    """run(x0, p, out): one call of the compiled loop, every other argument prepared once
    (C-contiguous float arrays x0, p; output rows go into ``out``, a view is fine)."""
    loop, last = compiled_loop(settings)
    stop, watch = compile_stop(stop_when), stop_when is not None  # compiled here, or refused
    function, equations = system_arguments(fast)
    span = (float(settings.span[0]), float(settings.span[1]))
    t_out = contiguous(settings.t_out, 1)

    def run(x0: np.ndarray, p: np.ndarray, out: np.ndarray) -> tuple[Any, ...]:
        return tuple(loop(function, equations, stop, watch, x0, p, span, t_out, out, last))

    return run
