"""The equations of motion at rest, read term by term.

At rest (q_dot = 0) a term of the forcing that is a coefficient times a product of velocity
powers, c(q) q_dot_j q_dot_k ... (the Coriolis and centrifugal terms of every chain), vanishes,
and only a term of degree one in the velocities has a derivative there:

    forcing(q, 0)               the terms free of the velocities,
    d forcing/dq_dot at rest    the coefficients of the terms of degree one,

so both are read off the terms once, in time linear in the forcing's size, instead of
substituting into and differentiating every entry (n^2 derivatives of a chain's forcing of
n^2 terms: n^3).  A term of any other form (a velocity inside a function, |q_dot|) is
substituted or differentiated as before (:func:`lagrangian.symbolic.nonsmooth.derivative`).

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.double_pendulum())
>>> forcing_at_rest(eom) == eom.forcing.xreplace({v: 0 for v in eom.velocities})
True
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.nonsmooth import derivative

#: A term's (degree in the velocities, the factors of its coefficient, the velocity when the
#: degree is one), or None when it is not a coefficient times velocity powers.
Monomial = tuple[int, list[sp.Expr], sp.Symbol | None] | None


class VelocityFree:
    """Whether a factor is free of the velocities, each distinct factor walked once (a
    chain's sums of masses recur in n^2 terms: walking each again would cost n^3)."""

    def __init__(self, velocities: frozenset[sp.Symbol]) -> None:
        self.velocities = velocities
        self._known: dict[sp.Basic, bool] = {}

    def __call__(self, factor: sp.Basic) -> bool:
        known = self._known.get(factor)
        if known is None:
            known = self._known[factor] = not (factor.free_symbols & self.velocities)
        return known


def velocity_monomial(term: sp.Expr, free: VelocityFree) -> Monomial:
    """``term`` = coefficient * product of q_dot_j**k_j (k_j positive integers) as (degree,
    the coefficient's factors, the velocity of a degree-one term); None for any other form."""
    coefficient, degree, first = [], 0, None
    for factor in sp.Mul.make_args(term):
        base, exponent = factor.as_base_exp()
        if base in free.velocities:
            if not (exponent.is_Integer and exponent > 0):
                return None
            degree += int(exponent)
            first = base
        elif not free(factor):
            return None
        else:
            coefficient.append(factor)
    return degree, coefficient, first if degree == 1 else None


def expression_at_rest(expr: sp.Expr, free: VelocityFree) -> sp.Expr:
    """``expr`` with every velocity 0: the terms free of them kept as they are."""
    if free(expr):
        return expr
    at_rest = {v: sp.Integer(0) for v in free.velocities}
    kept = []
    for term in sp.Add.make_args(expr):
        monomial = velocity_monomial(term, free)
        if monomial is None:
            kept.append(term.xreplace(at_rest))
        elif monomial[0] == 0:
            kept.append(term)
    return sp.Add(*kept)


_FORCING_AT_REST: IdentityCache[EquationsOfMotion, sp.ImmutableMatrix] = IdentityCache()


def forcing_at_rest(eom: EquationsOfMotion) -> sp.ImmutableMatrix:
    """forcing(q, 0, t): the forcing with every velocity 0 (computed once per equations)."""

    def compute(eom: EquationsOfMotion) -> sp.ImmutableMatrix:
        free = VelocityFree(frozenset(eom.velocities))
        return sp.ImmutableMatrix([expression_at_rest(f, free) for f in eom.forcing])

    return _FORCING_AT_REST.get(eom, compute)


def velocity_jacobian_at_rest(
    forcing: sp.MatrixBase, velocities: Sequence[sp.Symbol]
) -> sp.ImmutableMatrix:
    """d forcing/dq_dot at q_dot = 0 (the gyroscopic and damping matrix of small motions),
    from the terms of degree one in the velocities."""
    wanted = frozenset(velocities)
    free = VelocityFree(wanted)
    column = {v: j for j, v in enumerate(velocities)}
    at_rest = {v: sp.Integer(0) for v in velocities}
    rows = []
    for f in forcing:
        row: list[list[sp.Expr]] = [[] for _ in velocities]
        for term in () if free(f) else sp.Add.make_args(f):
            monomial = velocity_monomial(term, free)
            if monomial is None:
                for v in sorted(term.free_symbols & wanted, key=column.__getitem__):
                    row[column[v]].append(derivative(term, v).xreplace(at_rest))
            elif monomial[0] == 1:
                row[column[monomial[2]]].append(sp.Mul(*monomial[1]))
        rows.append([sp.Add(*terms) for terms in row])
    return sp.ImmutableMatrix(len(rows), len(velocities), [e for r in rows for e in r])


def sparse_jacobian(exprs: sp.MatrixBase, variables: Sequence[sp.Symbol]) -> sp.Matrix:
    """d exprs_i / d variables_j, each entry differentiated only by the variables it holds
    (:func:`lagrangian.symbolic.nonsmooth.derivative`; 0 for the others)."""
    entries = []
    for e in exprs:
        free = e.free_symbols
        entries += [derivative(e, v) if v in free else sp.Integer(0) for v in variables]
    return sp.Matrix(len(exprs), len(variables), entries)
