"""SciPy's RK45 and DOP853, and the classical RK4, in a C loop compiled once per machine: the
one compiled engine of the explicit Runge–Kutta family, for ``simulate`` and for batches.

The loop (``c_loop.c``, compiled and kept on disk by :mod:`~lagrangian.numerics.fast.c_build`)
is SciPy's ``RungeKutta`` solver written in C, operation for operation: SciPy's initial step,
error norms, step control and dense output, so its steps agree with ``solve_ivp`` to
rounding; RK4 takes the steps of :mod:`lagrangian.simulation.integrators.rk4` (landing
exactly on t0 + i h) with its cubic Hermite dense output.  The methods are those with a
tableau in :mod:`~lagrangian.numerics.fast.tableaus`.  It calls the right-hand side through
the C function pointer of SymEngine's LLVM backend (``as_ctypes()``): a new model costs its
LLVM compilation (milliseconds), no C compilation.

The right-hand side may be any linear system whose first unknowns are the accelerations:
the free state equations (:func:`native_equations`) or the multiplier form of a constrained
system (:mod:`lagrangian.numerics.fast.c_constrained`).  Events (:class:`LoopEvents`) are one
more compiled function g(t, x, p): after every accepted step a sign change of g_i in its
direction is located on the step's dense output by SciPy's brentq, written in C, as
:mod:`lagrangian.simulation.integrators.events` locates it on SciPy's path.

Per step, as :mod:`lagrangian.simulation.integrators.budget` does after every step of SciPy's
solvers, it counts the step against :class:`Limits`: accepted steps, wall time, stiffness
(h |lambda| near the edge of the stability region for most of the last steps) and a
collapsed step size.

The C loop returns to Python after ``max_call`` accepted steps or every
:data:`SLICE_SECONDS`, so that a progress callback is called and Ctrl-C is seen (the run
then ends ``interrupted`` with its rows so far); with a progress callback it returns after
every step.  How it ended is a :class:`~lagrangian.numerics.status.Status`.

Where there is no C compiler (:func:`available` is False) or SymEngine cannot compile the
equations (:func:`native_equations` is None), callers use SciPy's solvers instead.

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.fast.settings import Settings
>>> fast = native_equations(lg.derive(lg.examples.simple_pendulum()))
>>> settings = Settings("DOP853", (0.0, 1.0), np.linspace(0.0, 1.0, 3), 1e-10, 1e-10)
>>> x0, p = np.array([0.1, 0.0]), np.array([1.0, 9.81, 1.0])
>>> run = integrate(fast, settings, x0, p)  # doctest: +SKIP
>>> run.status, run.x.shape  # doctest: +SKIP
(0, (3, 2))
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.derivation.backend import backend_entries
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.numerics.fast.c_build import loop_library
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.native import NativeFunction, llvm_function
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.fast.tableaus import fixed_steps, tableau_of
from lagrangian.numerics.state_equations import state_equations
from lagrangian.numerics.status import Status
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.nonsmooth import piecewise_smooth

#: The C loop's returns that are no end: go on, or make room for more rows or event records.
RUNNING, FULL, EVENTS_FULL = -1, -2, -3
#: Seconds between returns to Python (progress, Ctrl-C) when there is no progress callback.
SLICE_SECONDS = 0.05
#: Rows of every-step output before the first time the arrays grow.
FIRST_ROWS = 256

_CACHE: IdentityCache[EquationsOfMotion, FastEquations | None] = IdentityCache()


def available() -> bool:
    """Whether the C loop can run here (a C compiler, or its library already built)."""
    return _functions() is not None


def native_equations(eom: EquationsOfMotion) -> FastEquations | None:
    """The state equations of ``eom`` compiled by SymEngine's LLVM backend as one C function
    (:class:`~lagrangian.numerics.fast.compiled_rates.FastEquations`), built once per
    EquationsOfMotion object; None where SymEngine cannot compile them (this path never falls
    back on numba)."""
    return _CACHE.get(eom, _build)


def state_symbols(eom: EquationsOfMotion) -> list[sp.Symbol]:
    """The inputs of the loop's C functions, in order: t, the coordinates, the velocities of
    the second-order coordinates (the state x), the parameters."""
    second = state_equations(eom).second
    return [eom.time, *eom.coordinates, *(eom.velocities[j] for j in second), *eom.parameters]


def loop_function(eom: EquationsOfMotion, expressions: Sequence[sp.Expr]) -> NativeFunction | None:
    """``expressions`` of (t, x, p) (:func:`state_symbols`) compiled by SymEngine's LLVM
    backend as one C function of the loop's signature, or None where it cannot compile them."""
    return c_function(state_symbols(eom), expressions)


def c_function(
    symbols: Sequence[sp.Symbol], expressions: Sequence[sp.Expr]
) -> NativeFunction | None:
    """``expressions`` of the vector ``symbols`` compiled by SymEngine's LLVM backend as one
    C function ``f(out, in, user_data)`` (:mod:`~lagrangian.numerics.fast.native`), or None
    where it cannot compile them (this path never falls back on numba)."""
    return _native_function(symbols, [piecewise_smooth(e) for e in expressions])


def _native_function(
    symbols: Sequence[sp.Symbol], expressions: Sequence[Any], *, backend: bool = False
) -> NativeFunction | None:
    compiled = llvm_function(symbols, expressions, backend=backend)
    if compiled is None:
        return None
    trampoline, user_data = compiled.as_ctypes()
    return NativeFunction(
        address=int(ctypes.cast(trampoline, ctypes.c_void_p).value or 0),
        user_data=int(user_data.value or 0),
        inputs=len(symbols),
        outputs=len(expressions),
        compiler="llvm",
        owner=compiled,
    )


def _build(eom: EquationsOfMotion) -> FastEquations | None:
    equations = state_equations(eom)
    velocities = [eom.velocities[j] for j in equations.second]
    function = _from_backend(eom, equations.matrix, equations.vector)
    if function is None:
        function = loop_function(eom, [*equations.matrix, *equations.vector])
    if function is None:
        return None
    return FastEquations(
        coordinates=tuple(s.name for s in eom.coordinates),
        parameters=tuple(s.name for s in eom.parameters),
        state_names=(*(s.name for s in eom.coordinates), *(s.name for s in velocities)),
        second=equations.second,
        first=equations.first,
        size=len(equations.vector),
        function=function,
    )


def _from_backend(
    eom: EquationsOfMotion, matrix: sp.ImmutableMatrix, vector: sp.ImmutableMatrix
) -> NativeFunction | None:
    """The loop's function compiled from the SymEngine entries the derivation converted to
    ``matrix`` and ``vector`` (no conversion back from SymPy), or None when they were built
    otherwise or contain what SymEngine cannot compile (the SymPy form resolves those)."""
    entries = backend_entries(matrix), backend_entries(vector)
    if entries[0] is None or entries[1] is None:
        return None
    return _native_function(state_symbols(eom), [*entries[0], *entries[1]], backend=True)


def state_matrix(fast: FastEquations, t: float, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The matrix of the state equations compiled in ``fast`` at (t, x, p), (size, size):
    the mass matrix itself when every coordinate is of second order (evaluated by the
    compiled function the loop calls, so it costs no compilation of its own)."""
    inputs = np.concatenate(([t], np.asarray(x, dtype=float), np.asarray(p, dtype=float)))
    values = np.asarray(fast.function.owner(inputs), dtype=float).ravel()
    return values[: fast.size * fast.size].reshape(fast.size, fast.size)


@dataclass(frozen=True)
class Limits:
    """The budget of one run, checked after every accepted step (the rules of
    :class:`lagrangian.simulation.integrators.budget.Budget`).

    max_steps, max_wall_time:
        Accepted steps and seconds the run may take (None: no limit).
    stiffness_edge:
        |h lambda| at the edge of the method's stability region (0: stiffness not watched);
        the run is stiff from the step where more than ``share`` of the last ``window`` steps
        had h |lambda| above ``near`` times the edge, and is stopped (STIFF) once it would
        still need more than ``stiff_steps_left`` steps at its step size.
    collapse_steps, collapse:
        COLLAPSED when the last ``collapse_steps`` steps advanced t by at most ``collapse``
        times the time span (0 steps: not watched).
    """

    max_steps: int | None = None
    max_wall_time: float | None = None
    stiffness_edge: float = 0.0
    near: float = 0.85
    share: float = 0.8
    window: int = 50
    stiff_steps_left: float = 100_000.0
    collapse_steps: int = 0
    collapse: float = 1e-9


@dataclass(frozen=True)
class LoopEvents:
    """Event functions for the loop (:mod:`lagrangian.simulation.integrators.events`): ``function``
    gives
    g_i(t, x, p) (:func:`loop_function`), ``directions`` (> 0: rising zeros only, < 0:
    falling, 0: both) and ``limits`` (how many zeros end the run; inf: never) one per event."""

    function: NativeFunction
    directions: np.ndarray
    limits: np.ndarray


@dataclass(frozen=True)
class LoopRun:
    """One run of the C loop: output times and states, and how it ended.

    ``status`` says how it ended; ``t_reached``, ``x_reached`` the last accepted step; ``steps``
    the accepted steps; ``last_step`` the size of the last one; ``stiff_since`` the time the
    run became stiff (None: never); ``advanced`` how far t moved over the last
    ``collapse_steps`` steps; ``failed_at`` the (t, x) where the right-hand side failed
    (SINGULAR); ``interrupted`` whether Ctrl-C (or a KeyboardInterrupt from ``progress``)
    ended it; ``events`` the zeros of the event functions as (index, time, state) in the
    order of time (a terminal one, STOPPED, is the last).
    """

    t: np.ndarray
    x: np.ndarray
    status: Status
    t_reached: float
    x_reached: np.ndarray
    steps: int
    last_step: float
    stiff_since: float | None
    advanced: float
    failed_at: tuple[float, np.ndarray] | None = None
    interrupted: bool = False
    events: tuple[tuple[int, float, np.ndarray], ...] = ()


def integrate(
    fast: FastEquations,
    settings: Settings,
    x0: np.ndarray,
    p: np.ndarray,
    limits: Limits | None = None,
    progress: Callable[[float], None] | None = None,
    events: LoopEvents | None = None,
) -> LoopRun:
    """Integrate from x0 with the parameters p by ``settings.method`` (RK45, DOP853, or RK4
    of step ``settings.dt``) over ``settings.span``, output at ``settings.t_out`` (empty:
    every step), within ``limits``; ``progress(t)`` after every accepted step; the zeros of
    ``events`` located (a terminal one ends the run, status STOPPED, its time and state the
    last output row).
    ``settings.max_steps`` is not read (the step budget is ``limits.max_steps``).
    RuntimeError when the C loop is not :func:`available`.
    """
    functions = _functions()
    if functions is None:
        raise RuntimeError("the C integration loop needs a C compiler")
    try:
        tableau = tableau_of(settings.method)
    except KeyError:
        raise ValueError(f"the C loop has no tableau for {settings.method!r}") from None
    if tableau.fixed and not settings.dt:
        raise ValueError(f"{settings.method} in the C loop needs its step settings.dt")
    run = _Run(functions, fast, settings, x0, p, limits or Limits(), events)
    max_call = 1 if progress is not None else 2**62
    status, interrupted = RUNNING, False
    try:
        status = functions.start(run.pointer)
        while status in (RUNNING, FULL, EVENTS_FULL):
            if status == FULL:
                run.grow()
            if status == EVENTS_FULL:
                run.grow_events()
            steps = run.struct.steps
            status = functions.advance(run.pointer, max_call, functions.clock() + SLICE_SECONDS)
            if progress is not None and run.struct.steps > steps:
                progress(run.struct.t)
    except KeyboardInterrupt:  # Ctrl-C: keep what was computed, the caller decides
        interrupted = True
    return run.result(status, interrupted)


class _System(ctypes.Structure):
    _fields_ = [
        ("function", ctypes.c_void_p),
        ("user_data", ctypes.c_void_p),
        ("inputs", ctypes.c_void_p),
        ("outputs", ctypes.c_void_p),
        ("second", ctypes.c_void_p),
        ("first", ctypes.c_void_p),
        ("nx", ctypes.c_int64),
        ("size", ctypes.c_int64),
        ("n_second", ctypes.c_int64),
        ("n_first", ctypes.c_int64),
    ]


class _Tableau(ctypes.Structure):
    _fields_ = [
        *((name, ctypes.c_void_p) for name in ("A", "B", "C", "E", "E3", "P", "A_extra")),
        ("C_extra", ctypes.c_void_p),
        ("D", ctypes.c_void_p),
        *(
            (name, ctypes.c_int64)
            for name in ("stages", "extra", "p_cols", "d_rows", "dop853", "error_order")
        ),
        ("end_stage", ctypes.c_int64),
        ("fixed", ctypes.c_int64),
    ]


_DOUBLE, _INT = ctypes.c_double, ctypes.c_int64
_POINTER = ctypes.c_void_p


class _RunStruct(ctypes.Structure):
    _fields_ = [
        ("system", _System),
        ("tableau", _Tableau),
        *((name, _DOUBLE) for name in ("t0", "t1", "rtol", "atol", "max_step")),
        ("t_out", _POINTER),
        ("n_out", _INT),
        ("n_fixed", _INT),
        ("max_steps", _INT),
        *((name, _DOUBLE) for name in ("deadline", "stiff_edge", "stiff_near", "stiff_share")),
        ("stiff_steps_left", _DOUBLE),
        ("window", _INT),
        ("collapse_steps", _INT),
        ("collapse", _DOUBLE),
        ("out_t", _POINTER),
        ("out_x", _POINTER),
        ("capacity", _INT),
        *((name, _POINTER) for name in ("y", "f", "y_old", "y_new", "K", "F", "work")),
        ("recent", _POINTER),
        ("times", _POINTER),
        *((name, _INT) for name in ("rows", "steps", "recent_count", "recent_sum")),
        ("times_count", _INT),
        *((name, _DOUBLE) for name in ("t", "h_abs", "h_last", "stiff_since", "advanced")),
        ("event_function", _POINTER),
        ("event_user_data", _POINTER),
        *(
            (name, _POINTER)
            for name in ("event_inputs", "event_old", "event_new", "event_work", "event_state")
        ),
        *((name, _POINTER) for name in ("directions", "limits", "counts", "roots", "order")),
        ("n_events", _INT),
        *((name, _POINTER) for name in ("found_index", "found_t", "found_x")),
        ("event_capacity", _INT),
        ("n_found", _INT),
    ]


@dataclass(frozen=True)
class _Functions:
    start: Any
    advance: Any
    clock: Any


def _functions() -> _Functions | None:
    """The C functions of the loaded library, or None (no compiler, or a library whose
    structures are not those declared here)."""
    library = loop_library()
    return None if library is None else _bind(library)


@cache
def _bind(library: ctypes.CDLL) -> _Functions | None:
    library.lg_layout.restype = ctypes.c_int64
    library.lg_layout.argtypes = [ctypes.c_int64]
    sizes = [library.lg_layout(i) for i in range(3)]
    if sizes != [ctypes.sizeof(s) for s in (_System, _Tableau, _RunStruct)]:
        return None
    start, advance, clock = library.lg_start, library.lg_advance, library.lg_clock
    start.restype, start.argtypes = ctypes.c_int64, [ctypes.c_void_p]
    advance.restype = ctypes.c_int64
    advance.argtypes = [ctypes.c_void_p, ctypes.c_int64, ctypes.c_double]
    clock.restype, clock.argtypes = ctypes.c_double, []
    return _Functions(start, advance, clock)


@cache
def _tableau_arrays(method: str) -> tuple[dict[str, np.ndarray], dict[str, int]]:
    """The arrays and sizes of ``struct lg_tableau`` for ``method`` (tableaus.py)."""
    tableau = tableau_of(method)
    stages = tableau.B.size
    ends = [j for j in range(1, stages) if tableau.C[j] == 1.0]
    names = ("A", "B", "C", "E", "E3", "P", "A_extra", "C_extra", "D")
    sizes = {
        "stages": stages,
        "extra": tableau.A_extra.shape[0] if tableau.dop853 else 0,
        "p_cols": tableau.P.shape[1],
        "d_rows": tableau.D.shape[0] if tableau.dop853 else 0,
        "dop853": int(tableau.dop853),
        "error_order": int(tableau.error_order),
        "end_stage": ends[0] if ends else -1,
        "fixed": int(tableau.fixed),
    }
    contiguous = {k: np.ascontiguousarray(getattr(tableau, k), dtype=float) for k in names}
    return contiguous, sizes


class _Run:
    """The buffers of one run and the ``struct lg_run`` pointing at them (every array is
    kept here for as long as the C loop may use it)."""

    def __init__(
        self,
        functions: _Functions,
        fast: FastEquations,
        settings: Settings,
        x0: np.ndarray,
        p: np.ndarray,
        limits: Limits,
        events: LoopEvents | None = None,
    ) -> None:
        self.fast = fast  # owns the machine code of the right-hand side
        self.events = events  # owns the machine code of the event functions
        nx, size = len(fast.state_names), fast.size
        self.tableau, sizes = _tableau_arrays(settings.method)
        k_rows = sizes["stages"] + 1 + sizes["extra"]
        f_rows = 3 + sizes["d_rows"] if sizes["dop853"] else sizes["p_cols"]
        p = np.ascontiguousarray(p, dtype=float)
        self.inputs = np.concatenate((np.zeros(1 + nx), p))
        self.outputs = np.empty((size + 1) * size)
        self.second = np.array(fast.second, dtype=np.int64)
        self.first = np.array(fast.first, dtype=np.int64)
        self.t_out = np.ascontiguousarray(settings.t_out, dtype=float)
        every = self.t_out.size == 0
        rows = FIRST_ROWS if every else self.t_out.size
        self.out_t = np.empty(rows if every else 0)
        self.out_x = np.full((rows, nx), np.nan)
        self.state = {name: np.empty(nx) for name in ("y", "f", "y_old", "y_new")} | {
            "K": np.empty(k_rows * nx),
            "F": np.empty(f_rows * nx),
            "work": np.empty(3 * nx),
        }
        self.state["y"][:] = x0
        self.recent = np.zeros(max(limits.window, 1), dtype=np.int64)
        self.times = np.empty(max(limits.collapse_steps, 0))
        self.struct = _RunStruct()
        self._fill(fast, settings, limits, sizes, functions)
        self._fill_events(events, nx, p)
        self.pointer = ctypes.addressof(self.struct)

    def _fill_events(self, events: LoopEvents | None, nx: int, p: np.ndarray) -> None:
        m = 0 if events is None else len(events.directions)
        self.event_arrays = {
            name: np.zeros(m) for name in ("event_old", "event_new", "event_work", "roots")
        } | {
            "event_inputs": np.concatenate((np.zeros(1 + nx), p)),
            "event_state": np.zeros(nx),
            "counts": np.zeros(m, dtype=np.int64),
            "order": np.zeros(m, dtype=np.int64),
        }
        s = self.struct
        if events is not None:
            self.event_arrays["directions"] = np.ascontiguousarray(events.directions, float)
            self.event_arrays["limits"] = np.ascontiguousarray(events.limits, float)
            s.event_function = events.function.address
            s.event_user_data = events.function.user_data
        for name, array in self.event_arrays.items():
            setattr(s, name, _address(array))
        s.n_events = m
        self.found_index = np.zeros(4 * m, dtype=np.int64)
        self.found_t, self.found_x = np.zeros(4 * m), np.zeros((4 * m, nx))
        s.found_index, s.found_t = _address(self.found_index), _address(self.found_t)
        s.found_x, s.event_capacity = _address(self.found_x), 4 * m

    def grow_events(self) -> None:
        """Twice the room for event records (those so far kept)."""
        found, rows = int(self.struct.n_found), 2 * len(self.found_t)
        index, t, x = (
            np.zeros(rows, np.int64),
            np.zeros(rows),
            np.zeros((rows, len(self.state["y"]))),
        )
        index[:found], t[:found], x[:found] = (
            self.found_index[:found],
            self.found_t[:found],
            self.found_x[:found],
        )
        self.found_index, self.found_t, self.found_x = index, t, x
        s = self.struct
        s.found_index, s.found_t, s.found_x = _address(index), _address(t), _address(x)
        s.event_capacity = rows

    def _fill(
        self,
        fast: FastEquations,
        settings: Settings,
        limits: Limits,
        sizes: dict[str, int],
        functions: _Functions,
    ) -> None:
        s = self.struct
        system = s.system
        system.function, system.user_data = fast.function.address, fast.function.user_data
        system.inputs, system.outputs = _address(self.inputs), _address(self.outputs)
        system.second, system.first = _address(self.second), _address(self.first)
        system.nx, system.size = len(fast.state_names), fast.size
        system.n_second, system.n_first = len(fast.second), len(fast.first)
        for name, array in self.tableau.items():
            setattr(s.tableau, name, _address(array))
        for name, value in sizes.items():
            setattr(s.tableau, name, value)
        s.t0, s.t1 = float(settings.span[0]), float(settings.span[1])
        s.rtol, s.atol, s.max_step = settings.rtol, settings.atol, settings.max_step
        s.t_out, s.n_out = _address(self.t_out), self.t_out.size
        if sizes["fixed"]:
            s.n_fixed = fixed_steps(s.t0, s.t1, float(settings.dt or 0.0))
        s.max_steps = limits.max_steps or 0
        wall = limits.max_wall_time
        s.deadline = math.inf if wall is None else functions.clock() + wall
        s.stiff_edge, s.stiff_near, s.stiff_share = limits.stiffness_edge, limits.near, limits.share
        s.stiff_steps_left, s.window = limits.stiff_steps_left, max(limits.window, 1)
        s.collapse_steps, s.collapse = max(limits.collapse_steps, 0), limits.collapse
        s.out_t, s.out_x, s.capacity = _address(self.out_t), _address(self.out_x), len(self.out_x)
        for name, array in self.state.items():
            setattr(s, name, _address(array))
        s.recent, s.times = _address(self.recent), _address(self.times)

    def grow(self) -> None:
        """Twice the room for every-step output (the rows so far kept)."""
        rows = self.struct.rows
        out_t = np.empty(2 * len(self.out_t))
        out_x = np.empty((2 * len(self.out_x), self.out_x.shape[1]))
        out_t[:rows], out_x[:rows] = self.out_t[:rows], self.out_x[:rows]
        self.out_t, self.out_x = out_t, out_x
        self.struct.out_t, self.struct.out_x = _address(out_t), _address(out_x)
        self.struct.capacity = len(out_x)

    def result(self, status: int, interrupted: bool) -> LoopRun:
        s, nx = self.struct, self.out_x.shape[1]
        rows = min(int(s.rows), len(self.out_x))
        times = self.out_t[:rows] if self.t_out.size == 0 else self.t_out[:rows]
        failed_at = None
        if status == Status.SINGULAR:  # the failed evaluation's (t, x) are still in its inputs
            failed_at = (float(self.inputs[0]), self.inputs[1 : 1 + nx].copy())
        return LoopRun(
            t=times.copy(),
            x=self.out_x[:rows].copy(),
            status=Status.INTERRUPTED if interrupted else Status(status),
            t_reached=float(s.t),
            x_reached=self.state["y"].copy(),
            steps=int(s.steps),
            last_step=float(s.h_last),
            stiff_since=None if math.isnan(s.stiff_since) else float(s.stiff_since),
            advanced=float(s.advanced),
            failed_at=failed_at,
            interrupted=interrupted,
            events=tuple(
                (int(self.found_index[k]), float(self.found_t[k]), self.found_x[k].copy())
                for k in range(int(s.n_found))
            ),
        )


def _address(array: np.ndarray) -> int:
    return int(array.ctypes.data)
