"""Every constraint as a Pfaffian form, the constraint Jacobian and the acceleration terms.

A holonomic (or active unilateral) constraint h(q, t) = 0 holds along the motion when
its rate does, h_dot = dh/dq . q_dot + dh/dt = 0; a velocity constraint is a(q, t).q_dot +
b(q, t) = 0 already.  Either way the constraint at velocity level reads

    c(q, q_dot, t) = a(q, t) . q_dot + b(q, t) = 0,      the 1-form  omega = a.dq + b dt,

with a = dh/dq, b = dh/dt for a holonomic one.  The rows a_j make the constraint Jacobian A,
and differentiating c once more (holonomic: h twice) gives

    A q_ddot = gamma,    gamma_j = -(dc_j/dt with q_ddot = 0)    (chain rule, d/dt = sum
                                                                  q_dot d/dq + q_ddot d/dq_dot
                                                                  + d/dt).

>>> import sympy as sp
>>> from lagrangian.model import Holonomic
>>> x, y = sp.symbols("x y")
>>> form = pfaffian_form(Holonomic(x**2 + y**2 - 1), (x, y))
>>> form.coefficients, form.time_coefficient
((2*x, 2*y), 0)
>>> acceleration_terms([form], (x, y))
[-2*x_dot**2 - 2*y_dot**2]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se
import sympy as sp

from lagrangian.derivation.backend import SympyView, to_backend
from lagrangian.derivation.collect import collect_state
from lagrangian.derivation.trig import combine_trig, size
from lagrangian.model import VelocityConstraint, t, velocity
from lagrangian.model.constraints import Constraint

TIDY_OPS = 1000  # partial derivatives of a constraint's rate beyond this are not expanded


@dataclass(frozen=True)
class PfaffianForm:
    """omega = sum_k a_k dq_k + b dt of one constraint, and c = a.q_dot + b (= 0)."""

    coefficients: tuple[sp.Expr, ...]
    time_coefficient: sp.Expr
    velocity_expression: sp.Expr

    def depends_on_time(self) -> bool:
        """True when omega involves t (b != 0 or some a_k depends on t)."""
        return self.time_coefficient != 0 or any(t in a.free_symbols for a in self.coefficients)


def pfaffian_form(constraint: Constraint, coordinates: Sequence[sp.Symbol]) -> PfaffianForm:
    """The Pfaffian form of ``constraint`` (holonomic and unilateral ones through h_dot)."""
    expr = constraint.expression
    if isinstance(constraint, VelocityConstraint):
        coefficients = tuple(sp.expand(expr.diff(velocity(q))) for q in coordinates)
        at_rest = {velocity(q): 0 for q in coordinates}
        time_coefficient = sp.expand(expr.xreplace(at_rest))
        return PfaffianForm(coefficients, time_coefficient, expr)
    coefficients = tuple(expr.diff(q) for q in coordinates)
    rate = sum((a * velocity(q) for a, q in zip(coefficients, coordinates)), sp.Integer(0))
    return PfaffianForm(coefficients, expr.diff(t), rate + expr.diff(t))


def acceleration_terms(
    forms: Sequence[PfaffianForm], coordinates: Sequence[sp.Symbol]
) -> list[sp.Expr]:
    """gamma_j = -(dc_j/dt at q_ddot = 0) of every constraint c_j = a_j . q_dot + b_j:

        gamma_j = -(sum_l dc_j/dq_l q_dot_l + dc_j/dt),

    each partial derivative expanded and its trigonometry tidied on its own in SymEngine
    (:func:`lagrangian.derivation.trig.combine_trig`), then the terms grouped by state
    monomial.  Never the product of whole sums expanded at once, so a constraint written with
    a rotation matrix in world axes costs about what it costs in body axes; a partial
    derivative of more than ``TIDY_OPS`` operations (a rolling wheel's contact point) is left
    as it is, and so is then gamma."""
    q = [to_backend(s) for s in coordinates]
    q_dot = [to_backend(velocity(s)) for s in coordinates]
    state = {*q, *q_dot, to_backend(t)}
    view = SympyView({t, *coordinates}.union(*(f.velocity_expression.free_symbols for f in forms)))
    result = []
    for form in forms:
        c = to_backend(form.velocity_expression)
        slopes = [c.diff(x) for x in (*q, to_backend(t))]
        if all(size(slope) <= TIDY_OPS for slope in slopes):
            tidied = [combine_trig(slope) for slope in slopes]
            rate = se.expand(se.Add(*[a * v for a, v in zip(tidied, q_dot)], tidied[-1]))
            result.append(view(collect_state(-rate, state)))
        else:
            result.append(view(-se.Add(*[a * v for a, v in zip(slopes, q_dot)], slopes[-1])))
    return result


def jacobian(forms: Sequence[PfaffianForm], n: int) -> sp.ImmutableMatrix:
    """The constraint Jacobian A, one row a_j per constraint (m x n)."""
    return sp.ImmutableMatrix(len(forms), n, [a for f in forms for a in f.coefficients])
