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
from dataclasses import dataclass, replace

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, evaluate
from lagrangian.analysis.at_rest import (
    forcing_at_rest,
    velocity_jacobian_at_rest,
)
from lagrangian.analysis.evaluation import (
    EvaluationContext,
    condition_text,
    evaluation_context,
    otherwise_text,
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
from lagrangian.analysis.separable import (
    CoordinateRoots,
    equilibrium_count,
    listed_solutions,
    separable_reason,
    separate_roots,
)
from lagrangian.analysis.simplification import simplify_small_matrix
from lagrangian.analysis.stability import stability_of, stiffness_matrix
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.energies import rest_potential
from lagrangian.symbolic.probe import depends_on, is_zero


def static_forces(eom: EquationsOfMotion, subs: Mapping[sp.Symbol, sp.Expr]) -> sp.ImmutableMatrix:
    """forcing(q, 0, t) with the parameter substitutions: zero at an equilibrium."""
    static = forcing_at_rest(eom)
    return static.xreplace(dict(subs)) if subs else static


#: Unknowns up to which the static equations are solved whole by sympy.solve, also when they
#: separate (beyond, each coordinate's own equation is solved alone).
SOLVED_WHOLE = 3
#: Coordinates up to which the stiffness at each equilibrium is simplified entry by entry
#: (a chain of twenty links has 400 entries at each of its many equilibria).
SIMPLIFIED_COORDINATES = 6


@dataclass(frozen=True)
class _RestJacobians:
    """K(q) = -d forcing/dq at rest and d forcing/dq_dot at rest, with the parameter
    substitutions: found once, then taken at each equilibrium."""

    stiffness: sp.Matrix
    velocity_jacobian: sp.Matrix


def _rest_jacobians(eom: EquationsOfMotion, subs: Mapping[sp.Symbol, sp.Expr]) -> _RestJacobians:
    static = static_forces(eom, subs)
    at_rest = velocity_jacobian_at_rest(eom.forcing, eom.velocities)
    return _RestJacobians(
        stiffness_matrix(static, eom.coordinates),
        sp.Matrix(at_rest.xreplace(dict(subs)) if subs else at_rest),
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


def _free_stability(
    eom: EquationsOfMotion, numbers, subs, jacobians: _RestJacobians | None = None
) -> StabilityTest:
    """Stability from K = -d forcing/dq at rest, for a system without constraints."""

    found: list[_RestJacobians] = [] if jacobians is None else [jacobians]

    def test(state, free, multipliers, exact):
        if not found:  # the first equilibrium's test finds them
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
    return equilibria_at_values(evaluation_context(subject, parameters))


def equilibria_at_values(context: EvaluationContext) -> Equilibria:
    """:func:`equilibria` with the parameter values of ``context``: on the constraint
    manifold for a constrained system, else of the free static equations (also where every
    constraint is left out: a unilateral one taken as released)."""
    manifold = constraint_manifold(context.eom)
    if manifold is not None and manifold.size:
        return manifold_equilibria(context, manifold)
    return _free_equilibria(context)


@dataclass(frozen=True)
class _Specialized:
    """The static forces at rest where the values given decide more than the general case:
    forces that vanish for every q at the values (F = 0, F_theta r with F_theta = 0) are
    put to 0 with the parameter values that make them vanish (``condition``); ``general``
    says what holds otherwise."""

    static: sp.ImmutableMatrix
    substitutions: Mapping[sp.Symbol, sp.Expr]
    condition: sp.Basic = sp.true
    general: str = ""


def _relations(condition: sp.Basic) -> dict[sp.Basic, sp.Basic]:
    """``Eq(F, 0) & Eq(k, 2)`` as the substitution {F: 0, k: 2}; chained relations resolved
    (m2 = m3, m1 = m2 + m3 gives {m2: m3, m1: 2 m3}) so one xreplace applies them all."""
    relations = {c.lhs: c.rhs for c in sp.And.make_args(condition) if isinstance(c, sp.Eq)}
    for _ in relations:  # each pass resolves one more link of a chain
        resolved = {p: value.xreplace(relations) for p, value in relations.items()}
        if resolved == relations:
            break
        relations = resolved
    return relations


def _unknowns(eom: EquationsOfMotion, static: sp.MatrixBase) -> list[sp.Symbol]:
    """The coordinates the static forces hold (their symbols read once, not per coordinate)."""
    held = static.free_symbols
    return [q for q in eom.coordinates if q in held]


def _at_values(context: EvaluationContext, static: sp.ImmutableMatrix) -> _Specialized | str:
    """The static forces to solve (:class:`_Specialized`), or why there is no rest at the
    values given either.

    A constant force c(p) != 0 allows no rest; where c vanishes at the values (F = 0) the
    rest of the equations are solved there, and "for F ≠ 0: no rest" said.  A force that
    depends on q and vanishes for every q at the values (F_theta r) leaves every q at rest
    along it there; in general it does not ("for F_theta ≠ 0: ... the equilibria differ")."""
    eom, subs = context.eom, dict(context.substitutions)
    unknowns = _unknowns(eom, static)
    forces = [e for e in static if not is_zero(e)]
    constant = [e for e in forces if not depends_on(e, unknowns)]
    vanishing = {e: context.vanishing_condition(e) for e in forces}
    no_rest_text = f"the static forces {constant} do not depend on the coordinates: no rest"
    if any(vanishing[e] is None for e in constant):
        return no_rest_text
    varying = [e for e in forces if e not in constant and vanishing[e] is not None]
    if not constant and not varying:
        return _Specialized(static, subs)
    general = []
    if constant:
        when = sp.And(*[vanishing[e] for e in constant])
        general.append(f"for {otherwise_text(when)}: {no_rest_text}")
    if varying:
        when = sp.And(*[vanishing[e] for e in varying])
        general.append(
            f"for {otherwise_text(when)}: the static forces {varying} do not vanish for every "
            "configuration, and the equilibria differ"
        )
    condition = sp.And(*[vanishing[e] for e in (*constant, *varying)])
    subs.update(_relations(condition))
    return _Specialized(static_forces(eom, subs), subs, condition, "; ".join(general))


def _said_at_values(found: Equilibria, special: _Specialized) -> Equilibria:
    """``found`` at the values of ``special``: each equilibrium exists under its condition,
    and the reason says what holds in general."""
    if special.condition == sp.true:
        return found
    at = f"at the given parameter values ({condition_text(special.condition)}): "
    return replace(
        found,
        equilibria=tuple(
            replace(e, condition=sp.And(special.condition, e.condition)) for e in found
        ),
        reason=f"{at}{found.reason}; {special.general}",
        general=special.general,
    )


def _separable(
    eom: EquationsOfMotion,
    separated: list[CoordinateRoots],
    numbers: Mapping[sp.Symbol, sp.Expr],
    subs: Mapping[sp.Symbol, sp.Expr],
) -> Equilibria:
    """The equilibria of static equations that separate (:mod:`~lagrangian.analysis.separable`):
    the combinations of roots listed, each tested, and how many there are."""
    jacobians = _rest_jacobians(eom, subs)
    test = _free_stability(eom, numbers, subs, jacobians)
    solutions, listed = listed_solutions(separated)
    found = tuple(build_equilibrium(eom, s, numbers, True, test) for s in solutions)
    gyroscopic = any(e != 0 for e in jacobians.velocity_jacobian)
    reason = separable_reason(separated, listed, gyroscopic)
    count = None if listed == "all" else equilibrium_count(separated)
    return Equilibria(found, sp.ImmutableMatrix(), None, "symbolic", reason, count=count)


def _free_equilibria(context: EvaluationContext) -> Equilibria:
    """The equilibria of a system without constraints: forcing(q, 0, t) = 0."""
    eom, numbers = context.eom, context.values
    static = static_forces(eom, context.substitutions)
    if depends_on(static, [eom.time]):
        return no_rest(static, "the static forces depend on time (driven or rheonomic): no rest")
    special = _at_values(context, static)
    if isinstance(special, str):
        return no_rest(static, special)
    static, subs = special.static, special.substitutions
    potential = rest_potential(eom.system)
    if subs:  # values may be sums: m1 -> m + 1
        potential = sp.expand(potential.xreplace(dict(subs)))
    test = _free_stability(eom, numbers, subs)
    if all(is_zero(e) for e in static):
        everywhere = (build_equilibrium(eom, {}, numbers, True, test),)
        resting = Equilibria(everywhere, static, potential, "symbolic", "the static forces vanish")
        return _said_at_values(resting, special)
    unknowns = _unknowns(eom, static)
    if len(unknowns) > SOLVED_WHOLE:
        separated = separate_roots(static, unknowns, numbers)
        if separated is not None:
            each = _separable(eom, separated, numbers, subs)
            resting = replace(each, static_equations=static, effective_potential=potential)
            return _said_at_values(resting, special)
    solutions, method, reason = solve_static(static, unknowns, numbers)
    if solutions is None:
        return _said_at_values(no_rest(static, reason), special)
    solutions = normalize_angles(solutions, periodic_coordinates(unknowns, static), numbers)
    exact = method == "symbolic"
    found = tuple(build_equilibrium(eom, s, numbers, exact, test) for s in solutions)
    return _said_at_values(Equilibria(found, static, potential, method, reason), special)
