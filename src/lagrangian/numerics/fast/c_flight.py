"""Flights in closed form from contact to contact with the lone impacts between them, in C:
the compiled step of :mod:`lagrangian.simulation.flight` for a mode whose motion is
polynomial in t (free flight, or a constant force).

``c_flight.c`` (compiled once per machine and kept on disk by
:mod:`~lagrangian.numerics.fast.c_build`, as the C loop is) takes the gaps of the contacts as
their form matrices K of the point (q, 1), each in its few coordinates, with the incidence of
coordinates on gaps, M^-1, each contact's coefficient of restitution and the mode's constant
acceleration: numbers only, nothing of a particular model.  From a calendar of contact times
it flies to the earliest contact, resolves a lone contact by the closed form
Lambda = -(1 + e) g_dot- / (a M^-1 a^T), finds again the contact times of the gaps whose
coordinates' velocities jumped, and so on until ``t_end`` or a contact it leaves to Python
(several at once, one without a coefficient of restitution, one that comes to rest), writing
the rows at the output times and each impact on the way (the C file's header says the steps).

Without a C compiler :func:`available` is False and the flight is found in NumPy, contact
by contact, by the same formulas.

>>> import numpy as np
>>> crossings(np.array([[1.0, -2.0, 0.5, 0.0, 0.0]]))  # doctest: +SKIP
array([0.58578644])
"""

from __future__ import annotations

import ctypes
from functools import cache
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from lagrangian.numerics.fast.c_build import compiled_library

#: The C source of the flights.
SOURCE = Path(__file__).with_name("c_flight.c")
#: LG_FLIGHT_ABI of the source: a library answering another number is compiled again.
ABI_VERSION = 2
#: How a call ends: at t_end, or at a contact left to Python.
END, CONTACT = 0, 1

_DOUBLE = ctypes.POINTER(ctypes.c_double)
_INT = ctypes.POINTER(ctypes.c_int64)


class _Gaps(ctypes.Structure):
    _fields_ = [
        ("n", ctypes.c_int64),
        ("m", ctypes.c_int64),
        ("width", ctypes.c_int64),
        ("index", _INT),
        ("forms", _DOUBLE),
        ("incidence_start", _INT),
        ("incidence", _INT),
        ("inverse_mass", _DOUBLE),
        ("restitution", _DOUBLE),
        ("a", _DOUBLE),
        ("accelerated", ctypes.c_int64),
        ("pattern_start", _INT),
        ("pattern", _INT),
    ]


@cache
def flight_library() -> ctypes.CDLL | None:
    """The loaded library of ``c_flight.c``, compiled on the first call on this machine;
    None without a C compiler or when it cannot be built."""
    library = compiled_library(SOURCE, "lg_flight_abi", ABI_VERSION)
    if library is None:
        return None
    library.lg_fly.restype = ctypes.c_int64
    library.lg_fly.argtypes = [
        ctypes.POINTER(_Gaps), _DOUBLE, _DOUBLE, ctypes.c_double,
        _DOUBLE, ctypes.c_int64, _DOUBLE, _INT,
        ctypes.c_int64, _DOUBLE, _INT, _DOUBLE, _DOUBLE, _INT, _INT,
        ctypes.c_double, ctypes.c_double, ctypes.c_double, _DOUBLE, _INT,
    ]  # fmt: skip
    library.lg_first_crossings.restype = None
    library.lg_first_crossings.argtypes = [_DOUBLE, ctypes.c_int64, _DOUBLE]
    return library


def available() -> bool:
    """Whether the compiled flights can run here (a C compiler, or the library built)."""
    return flight_library() is not None


class FlightModel:
    """The numbers ``lg_fly`` reads (the C file's header), held as contiguous arrays:
    ``index`` each gap's coordinates then n + 1 (the point's 1), ``forms`` the gaps' K,
    ``incidence`` per coordinate the gaps that involve it, M^-1, each gap's ``restitution``
    (NaN: none) and the mode's acceleration ``a``."""

    def __init__(
        self,
        index: np.ndarray,
        forms: np.ndarray,
        incidence: list[np.ndarray],
        inverse_mass: np.ndarray,
        restitution: np.ndarray,
        a: np.ndarray,
    ) -> None:
        n = len(a)
        self.n, self.m = n, len(index)
        self.index = np.ascontiguousarray(index, dtype=np.int64)
        self.forms = np.ascontiguousarray(forms, dtype=float)
        sizes = np.array([len(gaps) for gaps in incidence], dtype=np.int64)
        self.start = np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)
        joined = np.concatenate(incidence) if incidence else np.zeros(0)
        self.incidence = np.ascontiguousarray(joined, dtype=np.int64)
        self.inverse_mass = np.ascontiguousarray(inverse_mass, dtype=float)
        self.restitution = np.ascontiguousarray(restitution, dtype=float)
        self.a = np.ascontiguousarray(a, dtype=float)
        # each gap's nonzero entries of K, row-major (the products over its zeros skipped)
        gap, entry = np.nonzero(self.forms.reshape(self.m, -1))
        self.pattern = np.ascontiguousarray(entry, dtype=np.int64)
        found = np.searchsorted(gap, np.arange(self.m + 1))
        self.pattern_start = np.ascontiguousarray(found, dtype=np.int64)
        self.struct = _Gaps(
            n, self.m, self.index.shape[1] - 1,
            _pointer(self.index, _INT), _pointer(self.forms, _DOUBLE),
            _pointer(self.start, _INT), _pointer(self.incidence, _INT),
            _pointer(self.inverse_mass, _DOUBLE), _pointer(self.restitution, _DOUBLE),
            _pointer(self.a, _DOUBLE), int(np.any(self.a != 0)),
            _pointer(self.pattern_start, _INT), _pointer(self.pattern, _INT),
        )  # fmt: skip


class Flown(NamedTuple):
    """What a call flew: how it ended (``END`` at t_end, ``CONTACT`` at the contact ``hit``
    left to the caller), the time and state [q; v] there, the rows at the output times, and
    each impact resolved on the way: its time, gap, impulse, and states before and after
    (``states[k, 0]``, ``states[k, 1]``)."""

    code: int
    t: float
    x: np.ndarray
    hit: int
    rows: np.ndarray
    impact_t: np.ndarray
    impact_gap: np.ndarray
    impulses: np.ndarray
    states: np.ndarray


def fly(
    model: FlightModel,
    times: np.ndarray,
    t0: float,
    x0: np.ndarray,
    t_end: float,
    t_out: np.ndarray,
    max_impacts: int,
    tolerances: tuple[float, float, float],
) -> Flown:
    """Fly from (t0, x0 = [q; v]), the calendar's origin, whose gaps' next contact times are
    ``times`` (updated in place), to ``t_end`` or the first contact left to the caller,
    resolving at most ``max_impacts`` lone impacts on the way; rows at the sorted output
    times ``t_out`` up to where it stops.  ``tolerances``: (SIMULTANEOUS, the impulse's sign
    tolerance, the contact tolerance) of :mod:`lagrangian.simulation.unilateral` and
    :mod:`lagrangian.simulation.impacts`.  RuntimeError when the library is not available."""
    library = flight_library()
    if library is None:
        raise RuntimeError("the compiled flights are not available (no C compiler)")
    n = model.n
    if times.dtype != np.float64 or not times.flags.c_contiguous or len(times) != model.m:
        raise ValueError("times must be a contiguous float array, one entry per gap")
    state = np.concatenate(([t0], x0)).astype(float)
    out = np.ascontiguousarray(t_out, dtype=float)
    rows = np.empty((len(out), 2 * n))
    room = max(int(max_impacts), 0)
    impact_t, impulses = np.empty(room), np.empty(room)
    impact_gap = np.empty(room, dtype=np.int64)
    states = np.empty((room, 2, 2 * n))
    rows_done, done, hit = ctypes.c_int64(0), ctypes.c_int64(0), ctypes.c_int64(-1)
    work, stamp = np.empty(3 * n), np.empty(model.m, dtype=np.int64)
    code = library.lg_fly(
        ctypes.byref(model.struct), _pointer(times, _DOUBLE), _pointer(state, _DOUBLE),
        float(t_end), _pointer(out, _DOUBLE), len(out), _pointer(rows, _DOUBLE),
        ctypes.byref(rows_done), room, _pointer(impact_t, _DOUBLE),
        _pointer(impact_gap, _INT), _pointer(impulses, _DOUBLE), _pointer(states, _DOUBLE),
        ctypes.byref(done), ctypes.byref(hit), *map(float, tolerances),
        _pointer(work, _DOUBLE), _pointer(stamp, _INT),
    )  # fmt: skip
    k = done.value
    return Flown(
        int(code), float(state[0]), state[1:], int(hit.value), rows[: rows_done.value],
        impact_t[:k].copy(), impact_gap[:k].copy(), impulses[:k].copy(), states[:k].copy(),
    )  # fmt: skip


def crossings(coefficients: np.ndarray) -> np.ndarray:
    """Per row (c0, ..., c4), the first s > 0 where c0 + c1 s + ... + c4 s^4 turns negative,
    as the compiled flights find it (0 when closing now at g <= 0, inf when never)."""
    library = flight_library()
    if library is None:
        raise RuntimeError("the compiled flights are not available (no C compiler)")
    rows = np.ascontiguousarray(coefficients, dtype=float).reshape(-1, 5)
    s = np.empty(len(rows))
    library.lg_first_crossings(_pointer(rows, _DOUBLE), len(rows), _pointer(s, _DOUBLE))
    return s


def _pointer(array: np.ndarray, kind: Any) -> Any:
    return array.ctypes.data_as(kind)
