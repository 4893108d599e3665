"""Crossings of a surface of the state, G(q, q_dot, t) = 0, in a direction.

A transition's guard (:mod:`lagrangian.simulation.transitions`), the section of a return map
(:mod:`lagrangian.simulation.limit_cycle`) and a Poincaré section
(:mod:`lagrangian.simulation.poincare`) are one thing: an event function G whose zeros the
loop locates on the integrator's dense output (:mod:`lagrangian.simulation.integrators.events`),
counted only in its direction (``rising``: G from negative to positive; ``falling``; ``both``).
A section the caller gives is an expression of the coordinates, ``NAME_dot``, the parameters
and t, text read by the model files' parser (never ``eval``) or SymPy.

>>> import numpy as np, lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> section = section_crossing(eom, "theta", np.array([1.0, 9.81, 1.0]))
>>> section.direction, section(0.0, np.array([0.25]), np.array([0.0]))
(1.0, 0.25)
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model.transitions import DIRECTIONS
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.expressions import parse_expression
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.symbols import from_time_functions


class Crossing:
    """The event function G(t, q, q_dot) of a surface: ``guard`` compiled as a function of
    (q, q_dot, t, p), evaluated at the parameters ``p``; named, terminal or not, counted in
    its ``direction`` (a word of :data:`~lagrangian.model.transitions.DIRECTIONS`).

    ``traced``, when given, is G at those parameters in the equations' own symbols
    (``symbols``: t, then the coordinates, then the velocities): called with symbols, the
    function returns it, so that the C loop compiles the event beside the right-hand side
    (:mod:`lagrangian.simulation.integrators.event_trace`)."""

    def __init__(
        self,
        name: str,
        guard: NumericFunction,
        p: np.ndarray,
        direction: str,
        *,
        terminal: bool = True,
        traced: sp.Expr | None = None,
        symbols: tuple[sp.Symbol, ...] = (),
    ) -> None:
        self.__name__ = name
        self.guard, self.p = guard, p
        self.direction = DIRECTIONS[direction]
        self.terminal = terminal
        self.traced, self.symbols = traced, symbols

    def __call__(self, t: Any, q: Any, q_dot: Any) -> Any:
        if self.traced is not None and np.asarray(q).dtype == object:
            values = (t, *np.ravel(q), *np.ravel(q_dot))
            return self.traced.xreplace(dict(zip(self.symbols, values)))
        return float(self.guard(q, q_dot, t, self.p))


def section_crossing(
    eom: EquationsOfMotion,
    section: Any,
    p: np.ndarray,
    direction: str = "rising",
    *,
    name: str = "section",
    terminal: bool = False,
    field: str = "section",
) -> Crossing:
    """The crossing of the surface ``section`` = 0 (text or SymPy, see
    :func:`state_expression`) at the parameters ``p`` (in the order of ``eom.parameters``);
    ``field`` names it in errors.

    Raises ExpressionError (text that does not parse) or SimulationInputError (a name the
    system does not have, an unknown direction)."""
    if direction not in DIRECTIONS:
        raise SimulationInputError(
            f"direction: unknown direction {direction!r}; use one of {', '.join(DIRECTIONS)}"
        )
    expression = state_expression(eom, section, field)
    groups = (list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters))
    guard = NumericFunction(groups, [expression], ())
    at_values = expression.xreplace(dict(zip(eom.parameters, map(sp.Float, p))))
    symbols = (eom.time, *eom.coordinates, *eom.velocities)
    return Crossing(name, guard, p, direction, terminal=terminal, traced=at_values,
                    symbols=symbols)  # fmt: skip


def state_expression(eom: EquationsOfMotion, value: Any, field: str) -> sp.Expr:
    """``value`` as an expression of the coordinates, ``NAME_dot``, the parameters and t of
    ``eom``: text read by the model files' parser, or SymPy (time functions converted).

    Raises ExpressionError for text that does not parse, SimulationInputError for a value
    that is no expression or uses a name the system does not have."""
    names = state_names(eom)
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        return parse_expression(value, names, field=field, zero_test=is_zero)
    if not isinstance(value, sp.Expr):
        raise SimulationInputError(
            f"{field} is a {type(value).__name__}; give an expression (text or SymPy)."
        )
    expr = to_sympy(from_time_functions(value))
    unknown = sorted(s.name for s in expr.free_symbols if names.get(s.name) != s)
    if unknown:
        raise SimulationInputError(f"{field} uses {', '.join(unknown)}, not a name of this system.")
    return expr


def state_names(eom: EquationsOfMotion) -> dict[str, sp.Basic]:
    """The names an expression of the state may use: the coordinates, ``NAME_dot``, the
    parameters and t."""
    names: dict[str, sp.Basic] = {s.name: s for s in (*eom.coordinates, *eom.velocities)}
    names.update((s.name, s) for s in eom.parameters)
    names["t"] = eom.time
    return names
