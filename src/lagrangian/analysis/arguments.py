"""The arguments every analysis takes, resolved: the equations of motion, parameter values and
states.

Each public analysis takes a :class:`~lagrangian.model.System` or its
:class:`~lagrangian.derivation.EquationsOfMotion` (``Subject``); :func:`equations_of` gives the
equations (a System is derived once: :func:`lagrangian.derive` remembers it).  ``parameters``
arguments are substitutions (numbers or expressions, by name or symbol) applied before the
analysis; the remaining parameters keep their symbols and their defaults are used wherever a
number is needed.

>>> import lagrangian as lg
>>> eom = equations_of(lg.examples.simple_pendulum())
>>> numeric_values(eom, {"l": 2})[sp.Symbol("l")]
2
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import sympy as sp

from lagrangian import derivation
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError, Problem, raise_if_problems, require
from lagrangian.model import System
from lagrangian.model.validation import not_finite_real
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.frozen import frozen as frozen  # results' mappings are read-only
from lagrangian.symbolic.probe import is_zero

Subject = System | EquationsOfMotion
#: Parameter substitutions as a user gives them: name or Symbol -> number or expression.
Values = Mapping[Any, Any]


def equations_of(subject: Subject) -> EquationsOfMotion:
    """The equations of motion of ``subject`` (derived when it is a System, once per System)."""
    return derivation.equations_of(subject, "an analysis")


def _lookup(
    eom: EquationsOfMotion, field: str, noun: str, names: Mapping[str, sp.Symbol], given: Values
) -> dict[sp.Symbol, sp.Expr]:
    """``given`` with keys resolved to symbols of ``names``; every unknown key is a problem."""
    require(given, Mapping, field, f"give {{name: value, ...}} for {noun} names")
    resolved: dict[sp.Symbol, sp.Expr] = {}
    problems = []
    for key, value in given.items():
        name = key.name if isinstance(key, sp.Symbol) else str(key)
        if name not in names:
            problems.append(
                Problem(
                    f"{field}.{name}",
                    f"{eom.name or 'the system'} has no {noun} named {name!r}",
                    f"use one of {', '.join(sorted(names))}",
                )
            )
            continue
        try:
            number = to_sympy(value, f"{field}.{name}")
        except (sp.SympifyError, TypeError):
            number = None
        wrong = "is not a number or expression" if not isinstance(number, sp.Expr) else None
        wrong = wrong or not_finite_real(number)
        if wrong is not None:
            shown = wrong if isinstance(number, sp.Expr) else f"{value!r} {wrong}"
            problems.append(Problem(f"{field}.{name}", shown, "give a real number"))
            continue
        resolved[names[name]] = number
    raise_if_problems(problems, f"Wrong names or values in {field}", AnalysisError)
    return resolved


def substitutions(eom: EquationsOfMotion, parameters: Values | None) -> dict[sp.Symbol, sp.Expr]:
    """The user's parameter substitutions, keyed by the parameter symbols."""
    names = {p.name: p for p in eom.parameters}
    return _lookup(eom, "parameters", "parameter", names, parameters or {})


def numeric_values(eom: EquationsOfMotion, parameters: Values | None = None) -> dict:
    """Parameter symbol -> value: the substitutions given, else the defaults (when set)."""
    values: dict[sp.Symbol, sp.Expr] = {
        p: to_sympy(v) for p, v in eom.parameters.items() if v is not None
    }
    values.update(substitutions(eom, parameters))
    return values


def substitute(expr: Any, values: Mapping[sp.Symbol, sp.Expr]) -> Any:
    """``expr`` with parameter values substituted (simultaneously, for chains like m1 -> m)."""
    return expr.xreplace(dict(values)) if values else expr


def evaluate(expr: Any, values: Mapping[sp.Symbol, sp.Expr], digits: int = 30) -> Any:
    """``expr`` at parameter values, numerically; parameters substituted repeatedly so that
    substitutions naming other parameters (m1 -> m) reach their defaults."""
    for _ in range(4):
        new = substitute(expr, values)
        if new == expr:
            break
        expr = new
    return expr.evalf(digits) if isinstance(expr, (sp.Expr, sp.MatrixBase)) else expr


def operating_state(eom: EquationsOfMotion, about: Values | None) -> dict[sp.Symbol, sp.Expr]:
    """Every coordinate and velocity with its value in ``about`` (names or symbols of
    coordinates, ``NAME_dot`` velocities, or ``t``); unlisted ones are 0."""
    names = {s.name: s for s in (*eom.coordinates, *eom.velocities, eom.time)}
    given = _lookup(eom, "state", "coordinate, velocity or time", names, about or {})
    state: dict[sp.Symbol, sp.Expr] = {s: sp.Integer(0) for s in names.values()}
    state.update(given)
    return state


def is_zero_value(value: Any) -> bool:
    """A state value that is 0: the number 0 (also the float 0.0, which SymPy does not
    call equal to 0) or an expression identically 0."""
    value = to_sympy(value)
    if value.is_Number:
        return bool(value.is_zero)
    return is_zero(value)


def positive_parameters(eom: EquationsOfMotion) -> dict[sp.Symbol, sp.Symbol]:
    """Parameters with a positive default -> positive symbols of the same name (used to
    simplify conditions: g/(R*omega**2) <= 1 rather than Abs(...) <= 1)."""
    return {
        p: sp.Symbol(p.name, positive=True)
        for p, v in eom.parameters.items()
        if v is not None and float(v) > 0
    }


def assuming_positive(expr: Any, eom: EquationsOfMotion, simplify: bool = True) -> Any:
    """``expr`` simplified with the positive parameters assumed positive, in plain symbols."""
    forward = positive_parameters(eom)
    backward = {v: k for k, v in forward.items()}
    result = expr.xreplace(forward)
    if simplify:
        result = sp.simplify(result)
    return result.xreplace(backward)
