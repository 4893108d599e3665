"""The compiled marches of the variational integrators, typed once for every system, and the
driver that runs one in chunks.

As the integration loops of :mod:`lagrangian.numerics.fast.loops`, each march takes the
system's C functions (:mod:`lagrangian.numerics.fast.discrete`) as function values, so it is
compiled once per machine with an explicit signature and kept in numba's on-disk cache
(:func:`lagrangian.numerics.fast.loops.compile_cached`).  Numba checks a cached march against
the time stamp of its own file only: after editing the helpers it calls (``newton.py``,
``discrete_nodes.py``, ``../stage_newton.py``, ``../stage_prediction.py``), delete the caches
beside them (``__pycache__/*.nbi``, ``*.nbc``).

:func:`run_march` calls a march over chunks of :data:`CHUNK` steps, or, when it reports
progress, of at most a hundredth of the run (a progress bar moves, a Ctrl-C raised by it
stops the run where it was asked to); it stops at Ctrl-C between two chunks (the state lives
in arrays, so the nodes computed before are kept).  The nodes are made as the march reaches
them (:mod:`lagrangian.numerics.fast.discrete_nodes`): the memory of a run is that of its
output rows, whatever its number of steps.  This module is imported only when numba
is installed.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import cache
from typing import Any

import llvmlite.binding as llvm
import numpy as np
from numba import types
from numba.core import config as numba_config
from numba.core.compiler_lock import global_compiler_lock

from lagrangian.numerics.fast.collocation import march_collocation
from lagrangian.numerics.fast.discrete import NativeMechanics
from lagrangian.numerics.fast.loops import C_FUNCTION, CFunction, compile_cached
from lagrangian.numerics.fast.midpoint import march_midpoint
from lagrangian.numerics.fast.newton import RUNNING

#: Steps per call into a compiled march (one progress report, one chance to stop, each).
CHUNK = 65536

_f = types.float64
_vector = types.Array(_f, 1, "C")
_matrix = types.Array(_f, 2, "C")
_integers = types.Array(types.int64, 1, "C")
#: The midpoint terms, the Legendre map and the constraints (separate arguments: numba warns
#: of a tuple of function values).
_FUNCTIONS = (types.FunctionType(C_FUNCTION),) * 3
_DATA = types.UniTuple(types.intp, 3)
#: (span, extra, wanted, every) of :mod:`lagrangian.numerics.fast.discrete_nodes`.
_SCHEDULE = types.Tuple((_vector, _vector, _vector, types.boolean))
#: (q, v, momentum, lambda, h, A, dh/dt, history) of the midpoint march.
_MIDPOINT_STATE = types.Tuple((*[_vector] * 5, _matrix, _vector, _matrix))
#: (a, a_hat, b, c, lobatto) of a collocation method.
_TABLEAU = types.Tuple((_matrix, _matrix, _vector, _vector, types.boolean))
#: (q, v, momentum, h, A, dh/dt, V, Lambda, [previous step], the prediction errors' history
#: and its counters) of the collocation march.
_COLLOCATION_STATE = types.Tuple(
    (*[_vector] * 4, _matrix, _vector, _matrix, _matrix, _vector, _matrix, _integers)
)
#: (q, v, residual, multipliers, node, t) by output row, of every march.
_OUT = types.Tuple((_matrix, _matrix, _vector, _matrix, _integers, _vector))
#: steps, cursor, clock
_PLACE = (types.int64, _integers, _vector)

_SIGNATURES = {
    "midpoint": types.int64(
        *_FUNCTIONS,
        _DATA,
        _vector,
        _SCHEDULE,
        types.boolean,
        _MIDPOINT_STATE,
        *_PLACE,
        _OUT,
        _matrix,
    ),
    "collocation": types.int64(
        *_FUNCTIONS,
        _DATA,
        _vector,
        _SCHEDULE,
        types.boolean,
        _TABLEAU,
        _COLLOCATION_STATE,
        *_PLACE,
        _OUT,
    ),
}
_MARCHES = {"midpoint": march_midpoint, "collocation": march_collocation}


@cache
def discrete_march(kind: str) -> Any:
    """The compiled march of ``kind`` (``"midpoint"`` or ``"collocation"``), its loops left
    scalar (:func:`scalar_loops`)."""
    with scalar_loops():
        return compile_cached(_SIGNATURES[kind], _MARCHES[kind])


@contextmanager
def scalar_loops() -> Iterator[None]:
    """Compile without LLVM's loop vectorizer (numba's ``LOOP_VECTORIZE``, read when a
    library is optimized) and without its loop unrolling, under numba's compiler lock so
    that nothing else compiles meanwhile.

    The marches' loops run over a handful of entries (a coordinate, a stage):
    - vectorized, each was preceded by run-time checks that its arrays do not overlap,
      pairwise over the arrays it touches, and the checks took longer than the loops (a
      gauss6 step of a double pendulum a quarter faster without them);
    - unrolled, each loop of unknown length became eight copies of its body with a loop for
      the rest and the tests between them, most of the work for two to six entries (gauss6
      1.2x, gauss4 1.3x faster without; the same numbers to the last digit)."""
    # numba sets its configuration at run time: mypy does not see the attribute
    with global_compiler_lock:
        vectorize = numba_config.LOOP_VECTORIZE  # type: ignore[attr-defined]
        numba_config.LOOP_VECTORIZE = False  # type: ignore[attr-defined]
        # numba has no setting for unrolling: its pass builders (LLVM's new pass manager,
        # numba >= 0.61) take their tuning options from llvmlite, made without it here
        tuning = getattr(llvm, "create_pipeline_tuning_options", None)
        if tuning is not None:
            llvm.create_pipeline_tuning_options = _without_unrolling(tuning)
        try:
            yield
        finally:
            numba_config.LOOP_VECTORIZE = vectorize  # type: ignore[attr-defined]
            if tuning is not None:
                llvm.create_pipeline_tuning_options = tuning


def _without_unrolling(tuning: Callable[..., Any]) -> Callable[..., Any]:
    """llvmlite's ``create_pipeline_tuning_options`` with loop unrolling off."""

    def create_pipeline_tuning_options(*args: Any, **kwargs: Any) -> Any:
        options = tuning(*args, **kwargs)
        options.loop_unrolling = False
        return options

    return create_pipeline_tuning_options


def system_arguments(native: NativeMechanics) -> tuple[tuple[Any, ...], tuple[int, ...]]:
    """The C functions and user_data of ``native``, as the marches take them (``native`` owns
    the machine code: keep it alive while a march runs)."""
    functions = (native.midpoint, native.legendre, native.constraints)
    return (
        tuple(CFunction(f.address) for f in functions),
        tuple(f.user_data for f in functions),
    )


def run_march(
    march: Callable[[int], int],
    steps: int,
    reached: Callable[[], float],
    progress: Callable[[float], None] | None,
) -> tuple[int, bool]:
    """Call ``march(chunk)`` with chunks of steps until it stops (about ``steps`` in all);
    ``reached()`` is the time of the last node reached, given to ``progress`` after every
    chunk.  Returns the last status and whether Ctrl-C stopped the march."""
    status = RUNNING
    size = CHUNK if progress is None else max(1, min(CHUNK, steps // 100))
    try:
        while status == RUNNING:
            status = march(size)
            if progress is not None:
                progress(reached())
    except KeyboardInterrupt:
        return status, True
    return status, False


def output_arrays(n: int, m: int, rows: int) -> tuple[np.ndarray, ...]:
    """The output arrays (q, v, residual, multipliers, node, t by output row), NaN-filled
    (node -1)."""
    return (
        np.full((rows, n), np.nan),
        np.full((rows, n), np.nan),
        np.full(rows, np.nan),
        np.full((rows, m), np.nan),
        np.full(rows, -1, dtype=np.int64),
        np.full(rows, np.nan),
    )
