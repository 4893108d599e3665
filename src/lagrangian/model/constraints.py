"""Constraint declarations: holonomic h(q, t) = 0, velocity (Pfaffian) a(q, t).q_dot + b(q, t)
= 0 and unilateral g(q, t) >= 0 (Goldstein, Classical Mechanics, 3rd ed., §1.3; the
``constraints`` section of a model file, README "Model files").

Each declaration is an immutable value holding one SymPy expression (an ``Eq(lhs, rhs)`` is
taken as ``lhs - rhs``) and an optional name used in messages.  What a constraint *is*
(holonomic or not, rheonomic, redundant) is decided by :func:`lagrangian.constraints.classify`;
here a System only checks that each expression is well formed:

- it uses declared names and restricts at least one coordinate;
- a holonomic or unilateral constraint does not use velocities;
- a velocity constraint uses velocities and is linear in them (its Hessian in the velocities
  is zero), so that it has the Pfaffian form a(q, t).q_dot + b(q, t) = 0.

>>> import sympy as sp
>>> x, y, l = sp.symbols("x y l")
>>> Holonomic(x**2 + y**2 - l**2, name="rod").expression
-l**2 + x**2 + y**2
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import symengine as se
import sympy as sp

from lagrangian.errors import Problem
from lagrangian.model.elements import as_expression
from lagrangian.symbolic.expressions import free_symbols
from lagrangian.symbolic.native import to_symengine, to_symengine_sharing

if TYPE_CHECKING:
    from lagrangian.model.validation import NameScope

#: The kind of expression a coefficient of restitution is (lagrangian.model.validation's).
CONSTANT = "constant"


def _as_expression(value: Any) -> Any:
    if isinstance(value, sp.Equality):
        return value.lhs - value.rhs
    return as_expression(value)


@dataclass(frozen=True)
class Holonomic:
    """A holonomic constraint h(q, t) = 0 (a rheonomic one when h depends on t)."""

    expression: sp.Expr
    name: str = ""
    kind: ClassVar[str] = "holonomic"

    def __post_init__(self) -> None:
        object.__setattr__(self, "expression", _as_expression(self.expression))


@dataclass(frozen=True)
class VelocityConstraint:
    """A velocity (Pfaffian) constraint a(q, t).q_dot + b(q, t) = 0, linear in the velocities;
    ``x_dot*sin(phi) - y_dot*cos(phi)`` is the knife edge."""

    expression: sp.Expr
    name: str = ""
    kind: ClassVar[str] = "velocity"
    #: True for constraints made linear in the velocities (their linearity is not checked).
    linear_by_construction: ClassVar[bool] = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "expression", _as_expression(self.expression))


@dataclass(frozen=True)
class Unilateral:
    """A unilateral constraint g(q, t) >= 0; while active (g = 0) it acts like a holonomic one.

    ``restitution``: the coefficient of restitution e (a number in [0, 1], or an expression of
    the parameters) of the impacts on it: where g reaches 0 with dg/dt < 0 the velocities jump
    by the impulsive Lagrange equations M (q_dot+ - q_dot-) = J^T Lambda with Newton's law
    dg/dt+ = -e dg/dt- (1: elastic, 0: plastic).  None: no impact is allowed, and a run
    reaching one stops there with a message.
    """

    expression: sp.Expr
    name: str = ""
    restitution: sp.Expr | None = None
    kind: ClassVar[str] = "unilateral"

    def __post_init__(self) -> None:
        object.__setattr__(self, "expression", _as_expression(self.expression))
        if self.restitution is not None:
            object.__setattr__(self, "restitution", _as_expression(self.restitution))


Constraint = Holonomic | VelocityConstraint | Unilateral


def label(index: int, constraint: Any) -> str:
    """How messages name a constraint: ``'rod' (constraints[0])`` or ``constraints[0]``."""
    where = f"constraints[{index}]"
    name = getattr(constraint, "name", "")
    return f"{name!r} ({where})" if name else where


def statement(constraint: Any) -> str:
    """The constraint as a statement: ``x**2 + y**2 - l**2 = 0`` or ``g >= 0``."""
    relation = ">=" if isinstance(constraint, Unilateral) else "="
    return f"{constraint.expression} {relation} 0"


def check_constraints(values: dict[str, Any], scope: NameScope, problems: list[Problem]) -> None:
    """Every problem of the canonical ``values["constraints"]`` (see the module docstring)."""
    names: dict[str, int] = {}
    for i, item in enumerate(values["constraints"]):
        field = f"constraints[{i}]"
        if item.name:
            if item.name in names:
                problems.append(
                    Problem(
                        f"{field}.name",
                        f"name {item.name!r} is taken by constraints[{names[item.name]}]",
                        "give each constraint its own name",
                    )
                )
            names.setdefault(item.name, i)
        _check_one(item, i, scope, problems)


def _check_restitution(item: Any, index: int, scope: NameScope, problems: list[Problem]) -> None:
    """A coefficient of restitution is a constant: a number in [0, 1] or an expression of the
    parameters (its value is checked at the values a simulation uses)."""
    restitution = getattr(item, "restitution", None)
    if restitution is None:
        return
    field = f"constraints[{index}].restitution"
    before = len(problems)
    scope.check(restitution, field, CONSTANT, problems)
    if len(problems) > before:
        return
    if restitution.is_number and not (0 <= float(restitution) <= 1):
        problems.append(
            Problem(
                field,
                f"the coefficient of restitution {restitution} is not in [0, 1]",
                "give e between 0 (plastic: the bodies stay in contact) and 1 (elastic)",
            )
        )


def _check_one(item: Any, index: int, scope: NameScope, problems: list[Problem]) -> None:
    _check_restitution(item, index, scope, problems)
    field = f"constraints[{index}].expression"
    who = f"constraint {item.name!r}" if item.name else "the constraint"
    expression = item.expression
    used = scope.symbols_if_fine(expression, "state")
    if used is None:
        before = len(problems)
        scope.check(expression, field, "state", problems)  # names, shape, derivatives
        if len(problems) > before:
            return
        used = free_symbols(expression)
    # by name (a velocity is a Symbol: its name is its text, without the printer's cost)
    velocities = sorted((s for s in used if s in scope.velocities), key=lambda v: v.name)
    if isinstance(item, VelocityConstraint):
        if not velocities:
            problems.append(
                Problem(
                    field,
                    f"{who} uses no velocity",
                    "a condition h(q, t) = 0 on the coordinates is a holonomic constraint; "
                    "declare it as one",
                )
            )
        elif not (item.linear_by_construction or _linear(expression, velocities)):
            problems.append(
                Problem(
                    field,
                    f"{who} ({statement(item)}) is not linear in the velocities",
                    "a velocity constraint must have the Pfaffian form "
                    "a(q, t).q_dot + b(q, t) = 0; nonlinear ones are not supported",
                )
            )
        return
    if velocities:
        names = ", ".join(v.name for v in velocities)
        noun = "velocity" if len(velocities) == 1 else "velocities"
        problems.append(
            Problem(
                field,
                f"{who} is {item.kind} but uses the {noun} {names}",
                f"a {item.kind} constraint depends on the coordinates and t only; declare a "
                "condition on the velocities as a velocity constraint",
            )
        )
    elif not used & scope.coordinates:
        problems.append(
            Problem(
                field,
                f"{who} ({statement(item)}) involves no coordinate",
                "a constraint restricts the coordinates; write it in terms of them or remove it",
            )
        )


def _linear(expression: sp.Expr, present: list[sp.Symbol]) -> bool:
    """True when the Hessian of ``expression`` in the velocities it uses (``present``, in
    order) vanishes: at sight when it is a sum of terms each at most one velocity times a
    factor free of velocities (the usual Pfaffian a(q, t).q_dot + b(q, t)), else when every
    second derivative expands to zero (in SymEngine, or SymPy for what SymEngine cannot
    hold)."""
    if _pfaffian_at_sight(expression, set(present)):
        return True
    try:  # each distinct part once: a constraint written as products of rotations repeats them
        expr = to_symengine_sharing(expression, {})
        names = [to_symengine(v) for v in present]
        expand: Any = se.expand
    except se.SympifyError:
        expr, names, expand = expression, present, sp.expand
    first = [expr.diff(v) for v in names]
    for i, row in enumerate(first):
        for v in names[i:]:
            second = row.diff(v)
            if second != 0 and expand(second) != 0:
                return False
    return True


def _pfaffian_at_sight(expression: sp.Expr, velocities: set[sp.Symbol]) -> bool:
    """True when every term of ``expression`` is a product of at most one velocity (to the
    first power) and factors free of velocities."""
    memo: dict[sp.Basic, bool] = {}  # the terms share their factors' parts

    def moving(part: sp.Basic) -> bool:
        known = memo.get(part)
        if known is None:
            if part in velocities:
                known = True
            elif isinstance(part, (sp.Add, sp.Mul, sp.Pow, sp.Function)):
                known = any(moving(arg) for arg in part.args)
            else:
                known = bool(part.free_symbols & velocities)
            memo[part] = known
        return known

    for term in sp.Add.make_args(expression):
        factors = sp.Mul.make_args(term)
        if sum(f in velocities for f in factors) > 1:
            return False
        if any(f not in velocities and moving(f) for f in factors):
            return False
    return True
