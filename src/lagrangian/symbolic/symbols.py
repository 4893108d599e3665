"""Names of the generalized coordinates, their velocities and accelerations, and time.

Internally a coordinate ``theta`` has the plain symbols ``theta``, ``theta_dot`` and
``theta_ddot`` (plain symbols make differentiation cheap; d/dt is the chain rule; see
docs/architecture.md, "Symbolic core").
Users may also write SymPy ``dynamicsymbols`` / ``Function('x')(t)`` with ``.diff(t)``;
:func:`from_time_functions` turns those into the plain symbols.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import sympy as sp

from lagrangian.errors import require

#: The time symbol every expression of lagrangian uses.
t = sp.Symbol("t")

DOT_SUFFIX = "_dot"
DDOT_SUFFIX = "_ddot"


def velocity(coordinate: sp.Symbol | str) -> sp.Symbol:
    """The generalized velocity symbol of ``coordinate`` (a Symbol or a name): ``theta`` ->
    ``theta_dot``."""
    return sp.Symbol(_coordinate_name(coordinate, "velocity") + DOT_SUFFIX)


def acceleration(coordinate: sp.Symbol | str) -> sp.Symbol:
    """The generalized acceleration symbol of ``coordinate`` (a Symbol or a name): ``theta``
    -> ``theta_ddot``."""
    return sp.Symbol(_coordinate_name(coordinate, "acceleration") + DDOT_SUFFIX)


def _coordinate_name(coordinate: Any, function: str) -> str:
    if isinstance(coordinate, sp.Symbol):
        return coordinate.name
    require(coordinate, (sp.Symbol, str), f"{function}(coordinate)", "give a Symbol or a name")
    return str(coordinate)


def name_of(key: Any) -> str:
    """The name a user means by ``key``: a string as it is, a Symbol (or anything with a
    ``name``) by its name, anything else as text.

    >>> name_of("theta"), name_of(sp.Symbol("theta_dot")), name_of(3)
    ('theta', 'theta_dot', '3')
    """
    if isinstance(key, str):
        return key
    name = getattr(key, "name", None)
    return name if isinstance(name, str) else str(key)


def coordinates(names: str | Iterable[str]) -> tuple[sp.Symbol, ...]:
    """Coordinate symbols from a space-separated string or an iterable of names.

    >>> coordinates("x y")
    (x, y)
    """
    if isinstance(names, str):
        names = names.replace(",", " ").split()
    fix = "give names such as 'x theta' or ['x', 'theta']"
    require(names, Iterable, "coordinates(names)", fix)
    names = list(names)
    for name in names:
        require(name, str, "coordinates(names)", fix)
    return tuple(sp.Symbol(name) for name in names)


def _time_function_name(expr: sp.Basic) -> str | None:
    """The name of an applied undefined function of time only, ``x(t)`` -> ``x``."""
    if isinstance(expr, sp.core.function.AppliedUndef) and len(expr.args) == 1:
        (arg,) = expr.args
        if isinstance(arg, sp.Symbol) and arg.name == "t":
            return str(expr.func.__name__)
    return None


def from_time_functions(expr: sp.Basic) -> sp.Basic:
    """Replace ``x(t)``, ``x(t).diff(t)`` and ``x(t).diff(t, 2)`` by ``x``, ``x_dot``, ``x_ddot``.

    Any other symbol named ``t`` is replaced by :data:`t`.  Higher derivatives are left for
    the validator to refuse.
    """
    if not isinstance(expr, sp.Basic):
        return expr
    replacements: dict[sp.Basic, sp.Basic] = {}
    for derivative in expr.atoms(sp.Derivative):
        name = _time_function_name(derivative.expr)
        if name is None or len(derivative.variables) > 2:
            continue
        if not all(getattr(v, "name", None) == "t" for v in derivative.variables):
            continue
        suffix = DOT_SUFFIX if len(derivative.variables) == 1 else DDOT_SUFFIX
        replacements[derivative] = sp.Symbol(name + suffix)
    if replacements:
        expr = expr.xreplace(replacements)
    functions = {
        f: sp.Symbol(name)
        for f in expr.atoms(sp.core.function.AppliedUndef)
        if (name := _time_function_name(f)) is not None
    }
    if functions:
        expr = expr.xreplace(functions)
    times = {s: t for s in expr.free_symbols if s.name == "t" and s != t}
    if times:
        expr = expr.xreplace(times)
    return expr


def as_coordinate(item: str | sp.Basic) -> sp.Symbol | None:
    """A coordinate symbol from a name, a Symbol or a time function ``x(t)``; None if not one."""
    if isinstance(item, str):
        return sp.Symbol(item) if item.isidentifier() else None
    if isinstance(item, sp.Symbol):
        return item
    name = _time_function_name(item) if isinstance(item, sp.Basic) else None
    return sp.Symbol(name) if name else None


def time_derivative(expr: sp.Expr, coordinates: Iterable[sp.Symbol]) -> sp.Expr:
    """d/dt of ``expr(q, q_dot, t)`` by the chain rule: sum(de/dq q_dot + de/dq_dot q_ddot)
    + de/dt, with the plain symbols q, q_dot, q_ddot (docs/architecture.md, "Symbolic core").

    >>> x = sp.Symbol("x")
    >>> time_derivative(x**2, [x])
    2*x*x_dot
    """
    result = sp.diff(expr, t)
    for q in coordinates:
        result += sp.diff(expr, q) * velocity(q) + sp.diff(expr, velocity(q)) * acceleration(q)
    return result
