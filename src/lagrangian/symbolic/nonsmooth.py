"""Piecewise-smooth functions, differentiated the way a mechanics user does it by hand.

A V-shaped well ``V = k |x|`` pushes with ``-k sign(x)``; Coulomb friction written as the
dissipation function ``F = mu N |x_dot|`` gives the force ``-mu N sign(x_dot)``; a switched
force ``f0 Heaviside(t - t1)`` is off, then on.  These are derivatives *almost everywhere*,
away from the kinks and jumps, of real arguments:

    d|u| = sign(u) du,      d sign(u) = 0,      d Heaviside(u) = 0.

SymPy treats symbols as complex: it answers ``Derivative(Abs(x), x)`` (from SymEngine) or a
sum of ``re`` and ``im`` parts, and gives jumps a ``DiracDelta``, none of which can be
integrated numerically.  :func:`derivative` differentiates by the rules above and
:func:`piecewise_smooth` rewrites what the complex rules left in an expression.  Expressions
keep SymPy's own Abs, sign and Heaviside throughout, so results compare equal to what a user
writes with SymPy.

What the almost-everywhere derivative leaves out is the impulse of a jump: a step in a
potential (``Heaviside`` or ``sign`` of a coordinate in V) would act as an impulsive force at
the step, which equations of motion between the jumps cannot hold; a wall is a unilateral
constraint (:class:`lagrangian.model.constraints.Unilateral`) or a stiff smooth barrier.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> derivative(sp.Abs(x**2 - 1), x)
2*x*sign(x**2 - 1)
>>> piecewise_smooth(sp.Derivative(sp.Abs(x), x) + sp.DiracDelta(x))
sign(x)
>>> piecewise_smooth(sp.Abs(x).diff(x))  # SymPy's complex rule, resolved
sign(x)
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.symbolic.objects import sympy_object


class _RealAbs(sp.Function):
    """|u| of a real u, inside :func:`derivative` only (never returned)."""

    def fdiff(self, argindex: int = 1) -> sp.Expr:
        return _RealSign(self.args[0])


class _RealSign(sp.Function):
    """sign(u), constant between its jumps, inside :func:`derivative` only."""

    def fdiff(self, argindex: int = 1) -> sp.Expr:
        return sp.S.Zero


class _RealStep(sp.Function):
    """Heaviside(u, H0), constant between its jumps, inside :func:`derivative` only."""

    def fdiff(self, argindex: int = 1) -> sp.Expr:
        return sp.S.Zero


_TO_REAL: dict[type, type] = {sp.Abs: _RealAbs, sp.sign: _RealSign, sp.Heaviside: _RealStep}
_FROM_REAL: dict[type, type] = {v: k for k, v in _TO_REAL.items()}
#: The functions whose kinks and jumps the rules above handle.
NONSMOOTH = tuple(_TO_REAL)


def derivative(expr: Any, *variables: Any) -> sp.Expr:
    """d expr / d variables with d|u| = sign(u) du and d sign(u) = d Heaviside(u) = 0."""
    expr = sympy_object(expr)
    if not expr.has(*NONSMOOTH):
        return expr.diff(*variables)
    real = expr.replace(lambda e: type(e) in _TO_REAL, lambda e: _TO_REAL[type(e)](*e.args))
    result = real.diff(*variables)
    return result.replace(lambda e: type(e) in _FROM_REAL, lambda e: _FROM_REAL[type(e)](*e.args))


def piecewise_smooth(expr: Any) -> Any:
    """``expr`` with the derivatives of Abs, sign and Heaviside that SymPy or SymEngine left
    unevaluated taken by :func:`derivative`, ``DiracDelta`` dropped and ``re``/``im`` of the
    (real) quantities of mechanics resolved.  Cheap when there is nothing to do."""
    if not isinstance(expr, sp.Basic) or not expr.has(
        sp.Derivative, sp.Subs, sp.DiracDelta, sp.re, sp.im
    ):
        return expr
    expr = expr.replace(lambda e: isinstance(e, sp.DiracDelta), lambda e: sp.S.Zero)
    expr = expr.replace(lambda e: isinstance(e, sp.re), lambda e: e.args[0])
    expr = expr.replace(lambda e: isinstance(e, sp.im), lambda e: sp.S.Zero)
    expr = expr.replace(
        lambda e: isinstance(e, sp.Derivative), lambda e: derivative(e.expr, *e.variable_count)
    )
    return expr.replace(lambda e: isinstance(e, sp.Subs), lambda e: e.doit())


def jacobian(exprs: Any, variables: Any) -> sp.Matrix:
    """The Jacobian d exprs_i / d variables_j by :func:`derivative` (SymPy's own when smooth)."""
    column = sp.Matrix(exprs)
    column = column.reshape(len(column), 1)
    variables = list(variables)
    if not any(e.has(*NONSMOOTH) for e in column):
        return column.jacobian(variables)
    return sp.Matrix(len(column), len(variables), lambda i, j: derivative(column[i], variables[j]))


def kinks_in(expr: Any, variables: Any) -> list[sp.Expr]:
    """The Abs, sign and Heaviside parts of ``expr`` whose argument depends on ``variables``,
    in a fixed order.

    A kinetic energy with such a part in the velocities has a momentum dT/dq_dot that jumps
    where the part's argument changes sign, and a mass matrix holding an impulse there: no
    equations of motion between the jumps describe it (a force by the sign of a velocity,
    Coulomb friction, is a dissipation function).  Even Abs(v)**2, equal to v**2 for a real
    v, differentiates almost everywhere to a mass matrix 2 sign(v)**2 that vanishes at rest:
    it is found too, for the user to write v**2.

    >>> x, v = sp.symbols("x v")
    >>> kinks_in(v**2/2 + sp.Abs(v), [v]), kinks_in(v**2 + sp.Abs(x), [v])
    ([Abs(v)], [])
    """
    expr = sympy_object(expr)
    if not isinstance(expr, sp.Basic) or not expr.has(*NONSMOOTH):
        return []
    wanted = set(variables)
    found = {f for f in expr.atoms(*NONSMOOTH) if f.args[0].free_symbols & wanted}
    return sorted(found, key=sp.default_sort_key)
