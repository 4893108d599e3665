"""The evaluation context of one analysis: the parameter values every part decides with.

An analysis is made at the values given: the model's parameter defaults with the caller's
overrides (``--set``, ``parameters=``).  A statement such as "p_x is conserved" or "there is
no rest" may hold at those values and not in general (a cart pushed by a force F given as
0).  Every part reads the values through one :class:`EvaluationContext`, made once per
analysis, so that all of them decide alike:

    at the values        expr(q, q_dot, t; p = values) == 0 for every state,
    in general           expr(q, q_dot, t; p) == 0 for every state and every p,

and where the two differ, the condition on the parameters under which the statement at the
values holds (F = 0) is what the part reports with it.

>>> import lagrangian as lg, sympy as sp
>>> context = evaluation_context(lg.examples.mass_on_spring())
>>> F = sp.Symbol("F")
>>> context.is_zero_in_general(F), context.is_zero_at_values(F)
(False, True)
>>> context.vanishing_condition(F)
Eq(F, 0)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    equations_of,
    evaluate,
    frozen,
    numeric_values,
    substitutions,
)
from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero

#: A number within this of 0 (after the values are put in) is 0: round-off of the values.
ROUND_OFF = 1e-12
#: Relations between parameters are looked for in expressions of at most this many
#: parameters and operations (a short linear solve; beyond, every parameter's value is said).
RELATION_PARAMETERS, RELATION_OPS = 8, 200


@dataclass(frozen=True)
class EvaluationContext:
    """The equations of motion and the parameter values one analysis decides with.

    ``parameters`` are the caller's substitutions as given (for the parts' public
    functions), ``substitutions`` the same keyed by symbol (applied before any statement in
    general), ``values`` every parameter with a value: the defaults after the
    substitutions."""

    eom: EquationsOfMotion
    parameters: Mapping[Any, Any]
    substitutions: Mapping[sp.Symbol, sp.Expr]
    values: Mapping[sp.Symbol, sp.Expr]

    @property
    def numbered(self) -> frozenset[sp.Symbol]:
        """The parameters whose value is a number (not an expression of other symbols)."""
        return frozenset(
            p for p in self.eom.parameters if not to_sympy(evaluate(p, self.values)).free_symbols
        )

    def in_general(self, expr: Any) -> Any:
        """``expr`` with the caller's substitutions: what a statement in general is about."""
        return to_sympy(expr).xreplace(dict(self.substitutions))

    def is_zero_in_general(self, expr: Any) -> bool:
        """expr = 0 for every state and every value of the parameters left free."""
        return is_zero(self.in_general(expr))

    def is_zero_at_values(self, expr: Any) -> bool:
        """expr = 0 for every state at the parameter values (those without one stay free)."""
        return vanishes(evaluate(to_sympy(expr), self.values))

    def vanishing_condition(self, expr: Any) -> sp.Basic | None:
        """The parameter values under which ``expr`` vanishes for every state, as
        ``Eq(F, 0) & ...``: the parameters at 0 when those suffice, else relations between
        the parameters that the values satisfy (balanced masses: m1 = m2 + m3), else every
        parameter it uses; None when the values given do not make it vanish."""
        expr = to_sympy(expr)
        used = sorted((p for p in expr.free_symbols if p in self.values), key=str)
        zeros = [p for p in used if to_sympy(self.values[p]).is_zero]
        values = {p: sp.Integer(0) for p in zeros}
        if zeros and vanishes(expr.xreplace(values)):
            return sp.And(*[sp.Eq(p, 0) for p in zeros])
        if not vanishes(evaluate(expr, self.values)):
            return None
        relations = self._relations(expr, used)
        if relations is not None:
            return relations
        return sp.And(*[sp.Eq(p, self.values[p]) for p in used])

    def _relations(self, expr: sp.Expr, used: list[sp.Symbol]) -> sp.Basic | None:
        """Relations between parameters that make ``expr`` vanish for every state and that
        the values satisfy, from its coefficients of the state (small expressions only):
        g (m1 - m2 - m3) gives m1 = m2 + m3 when g is not 0."""
        if not used or len(used) > RELATION_PARAMETERS or sp.count_ops(expr) > RELATION_OPS:
            return None
        eom = self.eom
        state = (*eom.coordinates, *eom.velocities, eom.time)
        coefficients: dict[sp.Expr, sp.Expr] = {}
        for term in sp.Add.make_args(sp.expand(expr)):
            coefficient, monomial = term.as_independent(*state, as_Add=False)
            coefficients[monomial] = coefficients.get(monomial, 0) + coefficient
        try:
            solutions = sp.solve(list(coefficients.values()), used, dict=True)
        except (NotImplementedError, ValueError, TypeError):
            return None
        for solution in solutions:
            held = all(vanishes(evaluate(p - value, self.values)) for p, value in solution.items())
            if held and not any(value == 0 for value in solution.values()):
                return sp.And(*[sp.Eq(p, value) for p, value in solution.items()])
        return None


def vanishes(expr: sp.Expr) -> bool:
    """Identically 0; a number (parameter values put in) within round-off of 0."""
    if not expr.free_symbols:
        return bool(abs(complex(expr.evalf())) < ROUND_OFF)
    return is_zero(expr)


def evaluation_context(subject: Subject, parameters: Values | None = None) -> EvaluationContext:
    """The context of an analysis of ``subject`` with the substitutions ``parameters``
    (wrong names or values are refused here, once: AnalysisError naming each)."""
    eom = equations_of(subject)
    given = substitutions(eom, parameters)  # refuses what is not {name: value}, first
    return EvaluationContext(
        eom=eom,
        parameters=frozen(dict(parameters or {})),
        substitutions=frozen(given),
        values=frozen(numeric_values(eom, parameters)),
    )


def condition_text(condition: sp.Basic) -> str:
    """A condition on parameters as people write it: ``F = 0, k = 2``."""
    parts = condition.args if isinstance(condition, sp.And) else (condition,)
    return ", ".join(
        f"{p.lhs} = {number_text(p.rhs)}" if isinstance(p, sp.Eq) else str(p) for p in parts
    )


def number_text(value: Any) -> str:
    """A value as given: 9.81, not 9.81000000000000; 1, not 1.0; an expression as written
    (the one way every report writes a parameter's value; None: it has none).

    >>> [number_text(v) for v in (sp.Float(9.81), 1.0, sp.Symbol("m") / 2, None)]
    ['9.81', '1', 'm/2', 'no value']
    """
    if value is None:
        return "no value"
    if isinstance(value, sp.Basic) and not isinstance(value, sp.Float):
        return str(value)
    return f"{float(value):g}"


#: The most names a one-line statement lists (a gas has thousands of contacts).
NAMES_SHOWN = 6


def names_text(names: Sequence[str], more: str = "more") -> str:
    """The names, the first :data:`NAMES_SHOWN` of a long list and how many ``more``.

    >>> names_text([f"c{i}" for i in range(8)], "more constraints")
    'c0, c1, c2, c3, c4, c5 and 2 more constraints'
    """
    shown = ", ".join(names[:NAMES_SHOWN])
    return shown if len(names) <= NAMES_SHOWN else f"{shown} and {len(names) - NAMES_SHOWN} {more}"


def otherwise_text(condition: sp.Basic) -> str:
    """The general case a condition leaves out, as people write it: ``F ≠ 0 or k ≠ 2``."""
    parts = condition.args if isinstance(condition, sp.And) else (condition,)
    return " or ".join(
        f"{p.lhs} ≠ {number_text(p.rhs)}" if isinstance(p, sp.Eq) else f"not {p}" for p in parts
    )
