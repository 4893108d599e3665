"""Event functions read as expressions, so that the C loop can evaluate them compiled.

An event function g(t, q, q_dot) (:mod:`lagrangian.simulation.integrators.events`) is plain Python.
Most are arithmetic on their arguments (``q[0]``, ``q[0]**2 + q[1]**2 - 1``,
``q_dot[1] - 0.5*t``): called once with the time, the coordinates and the velocities as
SymPy symbols (arrays of them), such a function returns its own expression, which SymEngine's
LLVM backend then compiles beside the right-hand side.  A function that branches on its
arguments, converts them to ``float`` or calls NumPy's or ``math``'s functions on them raises
on symbols: it has no expression, and the run keeps SciPy's solvers, which call it as given.

An expression is taken only when it is one of the state: no symbol but t and the symbols of
the state x of the loop (the coordinates and the velocities it holds), and it must
give the function's own value, to rounding, at the initial state and at a second state near
it (a function whose symbolic and numeric meanings differ is not compiled).

>>> import numpy as np, lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> def crossing(t, q, q_dot):
...     return q[0]
>>> unpack = lambda t, x: (x[:1], x[1:])
>>> state = [eom.time, *eom.coordinates, *eom.velocities]
>>> traced_events(eom, [crossing], state, 0.0, np.array([0.1, 0.0]), unpack)
(theta,)
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.simulation.integrators.events import EventFunction, Unpack

#: How far the values of an expression and of its function may differ (relative to 1 + |g|).
AGREEMENT = 1e-9
#: The second state of the check: x0 moved by this much (relative to 1 + |x0|).
NUDGE = 0.0123


def traced_events(
    eom: EquationsOfMotion,
    functions: Sequence[EventFunction],
    state: Sequence[sp.Symbol],
    t0: float,
    x0: np.ndarray,
    unpack: Unpack,
) -> tuple[sp.Expr, ...] | None:
    """The expression of every event function of the state (module docstring), or None
    when one of them has none.  ``state`` is [t, the symbols of x]; ``unpack`` gives q and
    q_dot at (t, x) for the check."""
    expressions = []
    for function in functions:
        expression = _expression(eom, function)
        if expression is None:
            return None
        expressions.append(expression)
    if any(not e.free_symbols <= set(state) for e in expressions):
        return None
    nudged = x0 + NUDGE * (1.0 + np.abs(x0)) * np.cos(np.arange(len(x0)) + 1.0)
    for t, x in ((t0, x0), (t0 + NUDGE, nudged)):
        if not _agrees(functions, expressions, state, t, x, unpack):
            return None
    return tuple(expressions)


def _expression(eom: EquationsOfMotion, function: EventFunction) -> sp.Expr | None:
    """g(t, q, q_dot) called with symbols, or None when that raises or gives no expression."""
    q = np.array(eom.coordinates, dtype=object)
    q_dot = np.array(eom.velocities, dtype=object)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            value = function(eom.time, q, q_dot)
    except Exception:  # any failure on symbols: the function keeps its numeric path
        return None
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value.item()
    if isinstance(value, sp.Expr):
        return value if value.is_real is not False and not value.has(sp.zoo, sp.nan) else None
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        number = float(value)
        return sp.Float(number) if math.isfinite(number) else None
    return None


def _agrees(
    functions: Sequence[EventFunction],
    expressions: Sequence[sp.Expr],
    state: Sequence[sp.Symbol],
    t: float,
    x: np.ndarray,
    unpack: Unpack,
) -> bool:
    """Whether every expression gives its function's value at (t, x)."""
    values = {s: sp.Float(float(v)) for s, v in zip(state, (t, *x))}
    try:
        q, q_dot = unpack(t, x)
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            numeric = [float(g(t, q.copy(), q_dot.copy())) for g in functions]
            symbolic = [float(e.xreplace(values).evalf()) for e in expressions]
    except Exception:  # a function that fails here is left to its numeric path
        return False
    return all(
        math.isfinite(a) and abs(a - b) <= AGREEMENT * (1.0 + abs(a))
        for a, b in zip(numeric, symbolic)
    )
