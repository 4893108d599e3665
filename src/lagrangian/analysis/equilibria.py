"""Equilibria: every solution of the static equations, and its stability.

At rest (q_dot = q_ddot = 0) the equations M q_ddot = forcing reduce to

    forcing(q, 0, t) = 0,

which for a steady rheonomic system (T = T2 + T0, a bead on a hoop spinning at omega) is
grad V_eff = 0 with the effective potential V_eff = -L(q, 0) = V - T0.  Solved symbolically
with sympy.solve when possible (every branch, each with the condition for it to be real),
otherwise numerically with sympy.nsolve from several starting points at the parameter
values.  Stability from K = -d forcing/dq at rest (:mod:`lagrangian.analysis.stability`).
A constrained system is solved on its constraint manifold
(:mod:`lagrangian.analysis.manifold.statics`).

>>> import lagrangian as lg
>>> [dict(e.state) for e in equilibria(lg.examples.simple_pendulum())]
[{theta: 0}, {theta: pi}]
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    equations_of,
    evaluate,
    numeric_values,
    substitutions,
)
from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
from lagrangian.analysis.manifold.statics import manifold_equilibria
from lagrangian.analysis.rest import (
    Equilibria,
    StabilityTest,
    build_equilibrium,
    no_rest,
    positivity_condition,
    solve_static,
)
from lagrangian.analysis.roots import normalize_angles, periodic_coordinates
from lagrangian.analysis.simplification import simplify_small_matrix
from lagrangian.analysis.stability import stability_of, stiffness_matrix
from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.nonsmooth import jacobian
from lagrangian.symbolic.probe import depends_on, is_zero


def static_forces(eom: EquationsOfMotion, subs: Mapping[sp.Symbol, sp.Expr]) -> sp.ImmutableMatrix:
    """forcing(q, 0, t) with the parameter substitutions: zero at an equilibrium."""
    at_rest = {v: 0 for v in eom.velocities}
    return sp.ImmutableMatrix([f.xreplace(at_rest).xreplace(dict(subs)) for f in eom.forcing])


#: Coordinates up to which the stiffness at each equilibrium is simplified entry by entry
#: (a chain of twenty links has 400 entries at each of its many equilibria).
SIMPLIFIED_COORDINATES = 6


@dataclass(frozen=True)
class _RestJacobians:
    """K(q) = -d forcing/dq at rest and d forcing/dq_dot, with the parameter substitutions:
    found once, then taken at each equilibrium."""

    stiffness: sp.Matrix
    velocity_jacobian: sp.Matrix


def _rest_jacobians(eom: EquationsOfMotion, subs: Mapping[sp.Symbol, sp.Expr]) -> _RestJacobians:
    static = static_forces(eom, subs)
    forcing = sp.Matrix(eom.forcing).xreplace(dict(subs))
    return _RestJacobians(
        stiffness_matrix(static, eom.coordinates), jacobian(forcing, eom.velocities)
    )


def _stability(
    eom: EquationsOfMotion,
    state: Mapping[sp.Symbol, sp.Expr],
    free: tuple[sp.Symbol, ...],
    numbers: Mapping[sp.Symbol, sp.Expr],
    jacobians: _RestJacobians,
    exact: bool,
) -> tuple[bool | None, str, sp.ImmutableMatrix, sp.Basic | None]:
    point = {**state, **{v: 0 for v in eom.velocities}}
    stiffness = sp.ImmutableMatrix(jacobians.stiffness.xreplace(point))
    if len(eom.coordinates) <= SIMPLIFIED_COORDINATES:
        stiffness = simplify_small_matrix(stiffness)
    kept = [j for j, q in enumerate(eom.coordinates) if q not in free]
    reduced = stiffness.extract(kept, kept)
    condition = positivity_condition(reduced, eom, exact)
    numeric = evaluate(reduced, numbers)
    if numeric.free_symbols:
        verdict = condition if condition in (sp.true, sp.false) else None
        stable = None if verdict is None else bool(verdict)
        missing = ", ".join(sorted(s.name for s in numeric.free_symbols))
        return stable, f"stable when {condition} (no values for {missing})", stiffness, condition
    velocity_jacobian = jacobians.velocity_jacobian.xreplace(point)
    gyroscopic = evaluate(velocity_jacobian.extract(kept, kept), numbers)
    if gyroscopic.free_symbols:
        gyroscopic = None
    stable, reason = stability_of(numeric, gyroscopic, [q.name for q in free])
    return stable, reason, stiffness, condition


def _free_stability(eom: EquationsOfMotion, numbers, subs) -> StabilityTest:
    """Stability from K = -d forcing/dq at rest, for a system without constraints."""

    found: list[_RestJacobians] = []  # the first equilibrium's test finds them

    def test(state, free, multipliers, exact):
        if not found:
            found.append(_rest_jacobians(eom, subs))
        return (*_stability(eom, state, free, numbers, found[0], exact), ())

    return test


def equilibria(subject: Subject, parameters: Values | None = None) -> Equilibria:
    """Every equilibrium: symbolic when sympy.solve manages (each branch with its condition),
    otherwise numeric at the parameter values; each with its stability.

    >>> import lagrangian as lg
    >>> [e.stable for e in equilibria(lg.examples.simple_pendulum())]
    [True, False]
    """
    eom = equations_of(subject)
    manifold = constraint_manifold(eom)
    if manifold is not None:
        return manifold_equilibria(eom, manifold, parameters)
    subs = substitutions(eom, parameters)
    numbers = numeric_values(eom, parameters)
    static = static_forces(eom, subs)
    if depends_on(static, [eom.time]):
        return no_rest(static, "the static forces depend on time (driven or rheonomic): no rest")
    at_rest = {v: 0 for v in eom.velocities}
    potential = sp.expand(-eom.lagrangian.xreplace(at_rest).xreplace(dict(subs)))
    unknowns = [q for q in eom.coordinates if depends_on(static, [q])]
    nonzero = [e for e in static if not is_zero(e)]
    if not nonzero:
        test = _free_stability(eom, numbers, subs)
        everywhere = (build_equilibrium(eom, {}, numbers, True, test),)
        return Equilibria(everywhere, static, potential, "symbolic", "the static forces vanish")
    constant = [e for e in nonzero if not depends_on(e, unknowns)]
    if constant:
        return no_rest(
            static, f"the static forces {constant} do not depend on the coordinates: no rest"
        )
    solutions, method, reason = solve_static(static, unknowns, numbers)
    if solutions is None:
        return no_rest(static, reason)
    solutions = normalize_angles(solutions, periodic_coordinates(unknowns, static), numbers)
    test = _free_stability(eom, numbers, subs)
    found = tuple(build_equilibrium(eom, s, numbers, method == "symbolic", test) for s in solutions)
    return Equilibria(found, static, potential, method, reason)
