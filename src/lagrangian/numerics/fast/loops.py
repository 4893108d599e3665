"""How numba compiles the variational marches once for every system: the system's functions
are function values.

Every system's functions are C functions of one signature, ``f(out, in, user_data)``
(:data:`C_FUNCTION`), passed to the marches (:mod:`~lagrangian.numerics.fast.discrete_loops`)
as first-class function values (:class:`CFunction`), so each march is compiled once per
machine (several seconds) with an explicit signature and kept in numba's on-disk cache
(:func:`compile_cached`); a new system costs only its own C functions (milliseconds with
SymEngine's LLVM backend).  The cache is ``__pycache__`` beside these files, or, where the
package folder is read-only (an installed package), numba's user-wide cache folder, or
``NUMBA_CACHE_DIR`` when set; where no folder is writable at all, the loops are compiled in
every process instead.  Numba checks a cached march against the time stamp of the march's own
file only: after editing the helpers it calls (``newton.py``), delete the cache
(``__pycache__/*.nbi``, ``*.nbc``).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import pickle
import warnings
from typing import Any

import numba.experimental.function_type  # noqa: F401  (numba types a WrapperAddressProtocol)
from numba import njit, types
from numba.core.errors import NumbaExperimentalFeatureWarning

_f = types.float64

#: void f(double *out, const double *in, void *user_data): every system's function.
C_FUNCTION = types.void(types.CPointer(_f), types.CPointer(_f), types.intp)


class CFunction(types.WrapperAddressProtocol):
    """A C function of signature C_FUNCTION at ``address``, as numba passes it to the marches."""

    def __init__(self, address: int) -> None:
        self.address = address

    def __wrapper_address__(self) -> int:
        return self.address

    def signature(self) -> Any:
        return C_FUNCTION


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
