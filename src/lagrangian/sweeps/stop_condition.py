"""A stop condition given as text: ``"pi - Abs(theta)"`` -> g(t, q, q_dot), a member stops
where g turns negative (simulate_batch's ``stop_when``).

The text is read by the model-file parser (:func:`lagrangian.symbolic.conversion.parse_text`,
never ``eval``); it may name t, the coordinates, their ``NAME_dot`` and the parameters that
are not varied (replaced by their values).  The value is a small picklable record: each
process makes its functions from the expression on first use, so it travels to Dask workers
as text.  Called as it is, it evaluates arrays of members (``q[..., j]``: the NumPy batch) or
one member (the events of :func:`lagrangian.simulate`, for constrained systems); the C loop
compiles its ``expression``.

>>> import numpy as np, lagrangian as lg
>>> stop = stop_expression(lg.examples.simple_pendulum(), "1 - Abs(theta)")
>>> stop(0.0, np.array([[0.5], [2.0]]), np.zeros((2, 1)))
array([ 0.5, -1. ])
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.errors import Problem, SimulationInputError
from lagrangian.model import System
from lagrangian.symbolic.caches import remembered
from lagrangian.symbolic.conversion import parse_text

#: The field a stop condition is named by in errors.
FIELD = "stop_when"


@dataclass(frozen=True)
class StopExpression:
    """g(t, q, q_dot) of ``expression`` (numbers in place of the parameters) in the
    ``coordinates`` and their velocities (``NAME_dot``); ``text`` is what the user wrote."""

    text: str
    expression: sp.Expr
    coordinates: tuple[str, ...]

    def __call__(self, t: Any, q: Any, q_dot: Any) -> np.ndarray:
        q, q_dot = np.asarray(q, dtype=float), np.asarray(q_dot, dtype=float)
        function = _lambdified(self.expression, self.coordinates)
        columns = [q[..., j] for j in range(len(self.coordinates))]
        columns += [q_dot[..., j] for j in range(len(self.coordinates))]
        value = function(np.asarray(t, dtype=float), *columns)
        return np.broadcast_to(np.asarray(value, dtype=float), q.shape[:-1]).copy()


def stop_expression(system: System, text: str, varied: Collection[str] = ()) -> StopExpression:
    """The stop condition ``text`` for ``system``; ``varied`` parameters may not appear.

    Raises ExpressionError (bad text) or SimulationInputError (a name it may not use),
    naming ``stop_when``.
    """
    expression = parse_text(text, FIELD)
    coordinates = tuple(q.name for q in system.coordinates)
    allowed = {"t", *coordinates, *(v.name for v in system.velocities)}
    values = {p: v for p, v in system.parameters.items() if p.name not in varied}
    names = {s.name for s in expression.free_symbols}
    unknown = sorted(names - allowed - {p.name for p in values if values[p] is not None})
    if unknown:
        fix = "use t, the coordinates, their NAME_dot and parameters that are not swept: "
        fix += ", ".join(sorted(allowed | {p.name for p in values}))
        raise SimulationInputError(
            "Cannot read the stop condition:", [Problem(FIELD, f"unknown {unknown}", fix)]
        )
    numbers = {sp.Symbol(p.name): sp.Float(v) for p, v in values.items() if v is not None}
    return StopExpression(text, expression.xreplace(numbers), coordinates)


@remembered(maxsize=32)
def _lambdified(expression: sp.Expr, coordinates: tuple[str, ...]) -> Callable[..., Any]:
    """The NumPy function of ``expression`` of (t, q..., q_dot...), made once per process."""
    arguments = [sp.Symbol(name) for name in ("t", *coordinates)]
    arguments += [sp.Symbol(f"{name}_dot") for name in coordinates]
    return sp.lambdify(arguments, expression, "numpy")
