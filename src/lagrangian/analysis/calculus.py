"""Calculus on the plain state symbols that every analysis shares.

    d/dt e = de/dt + sum_j (de/dq_j q_dot_j + de/dq_dot_j q_ddot_j)      (chain rule)

plus a zero test that never simplifies a large expression (a numerical probe first, SymPy's
simplify only on small ones) and the split of an expression into parts homogeneous in the
velocities (L = L2 + L1 + L0).

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> time_derivative(sp.cos(sp.Symbol("theta")), eom)
-theta_dot*sin(theta)
"""

from __future__ import annotations

import random
from collections.abc import Iterable, Sequence
from typing import Any

import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.model.symbols import time_derivative as chain_rule_time_derivative

SMALL = 60  # count_ops up to which sympy.simplify is cheap enough to run
QUICK = 30  # a stricter limit for results that are many and rarely simplify much
PROBES = 3


def time_derivative(expr: sp.Expr, eom: EquationsOfMotion) -> sp.Expr:
    """The total time derivative of ``expr(q, q_dot, t)`` along the motion (chain rule)."""
    return chain_rule_time_derivative(expr, eom.coordinates)


def is_small(expr: sp.Basic, limit: int = SMALL) -> bool:
    """At most ``limit`` operations, found without walking all of a large expression."""
    for nodes, _ in enumerate(sp.preorder_traversal(expr)):
        if nodes > 4 * limit:
            return False
    return bool(sp.count_ops(expr) <= limit)


def tidy(expr: sp.Expr, limit: int = SMALL) -> sp.Expr:
    """``sympy.simplify`` for small expressions; large ones are left as they are."""
    expr = sp.sympify(expr)
    return sp.simplify(expr) if is_small(expr, limit) else expr


def tidy_matrix(matrix: sp.MatrixBase, limit: int = SMALL) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, [tidy(e, limit) for e in matrix])


def _probe(expr: sp.Expr, rng: random.Random) -> complex | None:
    """``expr`` at random values in (0.5, 1.5) of its symbols (None if not finite)."""
    values = {s: sp.Float(rng.uniform(0.5, 1.5), 30) for s in expr.free_symbols}
    try:
        number = complex(expr.xreplace(values).evalf(30))
    except (TypeError, ValueError):
        return None
    return number if abs(number) != float("inf") and number == number else None


def is_zero(expr: Any) -> bool:
    """True when ``expr`` vanishes identically.

    A non-zero value at a random point proves it does not; a zero is confirmed by simplify
    when the expression is small, and by several random probes otherwise.
    """
    expr = sp.sympify(expr)
    if expr == 0:
        return True
    if not expr.free_symbols:
        return bool(sp.simplify(expr) == 0)
    rng = random.Random(20240605)
    for _ in range(PROBES):
        value = _probe(expr, rng)
        if value is not None and abs(value) > 1e-15:
            return False
    if is_small(expr):
        return bool(sp.simplify(expr) == 0)
    return True


def all_zero(exprs: Iterable[Any]) -> bool:
    return all(is_zero(e) for e in exprs)


def depends_on(expr: Any, symbols: Iterable[sp.Symbol]) -> bool:
    free = sp.sympify(expr).free_symbols
    return any(s in free for s in symbols)


def homogeneous_parts(expr: sp.Expr, velocities: Sequence[sp.Symbol]) -> dict[int, sp.Expr] | None:
    """``expr`` split by total degree in the velocities, {2: T2, 1: T1, 0: T0}; None when it
    is not a polynomial in them."""
    expr = sp.expand(expr)
    if not depends_on(expr, velocities):
        return {0: expr} if expr != 0 else {}
    try:
        poly = sp.Poly(expr, *velocities)
    except sp.PolynomialError:
        return None
    if any(depends_on(c, velocities) for c in poly.coeffs()):
        return None
    parts: dict[int, sp.Expr] = {}
    for monomial, coefficient in poly.terms():
        degree = sum(monomial)
        term = coefficient * sp.Mul(*[v**k for v, k in zip(velocities, monomial)])
        parts[degree] = parts.get(degree, sp.Integer(0)) + term
    return {d: p for d, p in parts.items() if p != 0}
