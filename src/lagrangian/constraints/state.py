"""A numerical state for questions about one configuration: values of the coordinates,
velocities, parameters (their defaults unless given) and t (0 unless given), and the
projection of a state onto the constraints.

The projection moves the coordinates to the nearest point of the holonomic constraint set
(Gauss–Newton least squares, :func:`lagrangian.constraints.probe.project`) and then the
velocities by the least-norm correction that satisfies every equality constraint at velocity
level, A q_dot + b = 0:

    q_dot <- q_dot - A^+ (A q_dot + b).

>>> import lagrangian as lg, sympy as sp
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)])
>>> fixed = project_state(ring, {"x": 2.0, "y": 0.0, "x_dot": 1.0, "y_dot": 1.0})
>>> round(fixed[x], 9), round(fixed[sp.Symbol("x_dot")], 9)
(1.0, 0.0)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.constraints.pfaffian import pfaffian_form
from lagrangian.constraints.probe import NumericFunction, project
from lagrangian.errors import ConstraintError, Problem, raise_if_problems
from lagrangian.model import Holonomic, System, Unilateral, t, velocity


def numeric_state(system: System, state: Mapping[Any, float]) -> dict[sp.Symbol, float]:
    """Symbols to floats: ``state`` (names or symbols) over the parameters' defaults and
    t = 0; every coordinate and every parameter must get a value."""
    known = {s.name: s for s in (*system.coordinates, *system.velocities, *system.parameters, t)}
    values: dict[sp.Symbol, float] = {t: 0.0}
    values.update({p: float(v) for p, v in system.parameters.items() if v is not None})
    problems = []
    for key, value in state.items():
        symbol = known.get(str(key))
        if symbol is None:
            problems.append(
                Problem(
                    f"state.{key}",
                    f"{key!s} is not a coordinate, velocity, parameter or t",
                    "give values by coordinate, NAME_dot, parameter name or t",
                )
            )
        else:
            values[symbol] = float(value)
    for symbol in (*system.coordinates, *system.parameters):
        if symbol not in values:
            problems.append(
                Problem(f"state.{symbol}", "has no value", f"give {symbol} a value in the state")
            )
    raise_if_problems(problems, "The state is incomplete or unknown", ConstraintError)
    return values


def project_state(system: System, state: Mapping[Any, float]) -> dict[sp.Symbol, float]:
    """``state`` moved onto the constraints: coordinates onto the holonomic (and active
    unilateral, g = 0 when g < 0) constraints, then velocities onto A q_dot + b = 0."""
    values = numeric_state(system, state)
    for v in system.velocities:
        values.setdefault(v, 0.0)
    equations = [
        c.expression
        for c in system.constraints
        if isinstance(c, Holonomic)
        or (isinstance(c, Unilateral) and _value(c.expression, values) < 0)
    ]
    found = project(equations, system.coordinates, values, starts=1)
    if not found.satisfied:
        raise ConstraintError(
            "No configuration near this state satisfies the holonomic constraints "
            f"(residuals {found.residuals}); check the constraints with classify()."
        )
    values = found.values
    rows = [c for c in system.constraints if not isinstance(c, Unilateral)]
    if rows:
        forms = [pfaffian_form(c, system.coordinates) for c in rows]
        symbols = sorted(values, key=str)
        a = NumericFunction(sp.Matrix([list(f.coefficients) for f in forms]), symbols)(values)
        b = NumericFunction(sp.Matrix([f.time_coefficient for f in forms]), symbols)(values)
        if a is None or b is None:
            raise ConstraintError("The constraint Jacobian is not defined at this state.")
        q_dot = np.array([values[velocity(q)] for q in system.coordinates])
        q_dot -= np.linalg.pinv(a) @ (a @ q_dot + b.ravel())
        values.update({velocity(q): float(v) for q, v in zip(system.coordinates, q_dot)})
    return values


def _value(expr: sp.Expr, values: Mapping[sp.Symbol, float]) -> float:
    number = NumericFunction(sp.Matrix([expr]), sorted(values, key=str))(values)
    return float("nan") if number is None else float(number[0, 0])
