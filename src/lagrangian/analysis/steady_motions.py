"""Steady motions of a system whose constraints move by a symmetry: relative equilibria.

When the constraints move by a symmetry xi of L at the rate c (b = -c A xi, the Jacobi
integral of :mod:`lagrangian.analysis.manifold.symmetries`), the system can move along with
them, q_dot = c xi(q): a bead turning with its hoop, at rest relative to it.  With the relative
velocity w = q_dot - c xi, the Jacobi integral of a natural system splits as

    J = 1/2 w^T M w + V_eff(q),      V_eff = J(q, c xi(q)) = V - 1/2 c^2 xi^T M xi,

(the centrifugal potential of the co-moving frame; Goldstein §2.7), so the steady motions are
the critical points of V_eff on the constraints as they stand at t = 0,

    grad V_eff = A_h^T mu,     h_j(q, 0) = 0,

and one is stable (relative to the moving constraints) where V_eff has a strict minimum
there: K = P^T (d2 V_eff - sum mu_j d2 h_j) P > 0, P a basis of the tangent space.  For a
bead on a hoop of radius R spinning at omega about its vertical diameter this gives the bottom
(stable while omega^2 < g/R) and cos(theta) = g/(R omega^2) (stable beyond).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, evaluate, frozen
from lagrangian.analysis.evaluation import EvaluationContext, evaluation_context
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, constraint_manifold
from lagrangian.analysis.manifold.linearize import numbers_at, reduced_state_space, tangent_map
from lagrangian.analysis.manifold.statics import complete_solutions, symbolic_limit
from lagrangian.analysis.manifold.symmetries import JacobiIntegral, jacobi_integral
from lagrangian.analysis.partition import dependent_columns
from lagrangian.analysis.rest import (
    Equilibrium,
    StabilityTest,
    build_equilibrium,
    positivity_condition,
    solve_static,
)
from lagrangian.analysis.simplification import simplify_small, simplify_small_matrix
from lagrangian.analysis.stability import stability_of
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.probe import depends_on


@dataclass(frozen=True)
class SteadyMotions:
    """The steady motions found: each as its configuration at t = 0 (an Equilibrium of
    V_eff, with its stability relative to the moving constraints and the multipliers of the
    motion there) and its velocities c xi(q); the effective potential, the rate c, the
    symmetry, and how they were found."""

    motions: tuple[Equilibrium, ...]
    velocities: tuple[Mapping[sp.Symbol, sp.Expr], ...]
    effective_potential: sp.Expr
    rate: sp.Expr
    symmetry: str
    method: str
    reason: str

    def __iter__(self):
        return iter(self.motions)

    def __len__(self) -> int:
        return len(self.motions)


def _effective_potential(eom, jacobi: JacobiIntegral, subs) -> tuple[sp.Expr, sp.Expr, dict]:
    """V_eff(q) = J(q, c xi(q), 0), c = -kappa, and the velocities c xi(q)."""
    rate = -jacobi.kappa
    moving = {v: rate * x for v, x in zip(eom.velocities, jacobi.symmetry.generator)}
    at_zero = {eom.time: 0}
    potential = jacobi.expression.xreplace(moving).xreplace(at_zero).xreplace(dict(subs))
    return simplify_small(sp.expand(potential)), rate, moving


def _relative_test(eom, manifold, potential, levels, numbers) -> StabilityTest:
    """K = P^T (d2 V_eff - sum mu d2 h) P on the constraints at t = 0 (module docstring)."""
    q = list(eom.coordinates)
    mus = [manifold.multipliers[row] for row in manifold.holonomic_rows]

    def test(state, free, multipliers, exact):
        point = {k: (0 if k in free else v) for k, v in state.items()}
        bordered = sp.hessian(potential, q) - sum(
            (multipliers.get(mu, 0) * sp.hessian(h, q) for mu, h in zip(mus, levels)),
            sp.zeros(len(q)),
        )
        jacobian = sp.Matrix(levels).jacobian(q).xreplace(point)
        dependent = list(dependent_columns(numbers_at(jacobian, numbers), range(len(q))))
        independent = [j for j in range(len(q)) if j not in dependent]
        basis = tangent_map(jacobian, dependent, independent, len(q))
        kept = [k for k, j in enumerate(independent) if q[j] not in free]
        stiffness = simplify_small_matrix(basis.T * bordered.xreplace(point) * basis)
        reduced = stiffness.extract(kept, kept)
        condition = positivity_condition(reduced, eom, exact)
        numeric = evaluate(reduced, numbers)
        if numeric.free_symbols:
            return None, "no values for the parameters", stiffness, condition, ()
        stable, reason = stability_of(numeric, None, [s.name for s in free])
        reason = (
            "relative to the moving constraints (the Jacobi integral J = T_rel + V_eff), " + reason
        )
        return stable, reason, stiffness, condition, tuple(q[j] for j in independent)

    return test


def _with_forces(eom, manifold, motion: Equilibrium, state, subs, numbers) -> Equilibrium:
    """``motion`` with the multipliers of the actual motion at t = 0 (the forces that keep
    the system turning with the constraints), from the multiplier form there."""
    point = {**state, eom.time: 0}
    try:
        reduced = reduced_state_space(eom, manifold, point, (), subs, numbers)
    except AnalysisError:
        return motion
    forces = {k: simplify_small(v) for k, v in reduced.multipliers.items()}
    return replace(motion, multipliers=frozen(forces))


def _refuse(manifold: ConstraintManifold | None, jacobi: JacobiIntegral | None) -> None:
    if manifold is None or jacobi is None:
        raise AnalysisError(
            "no family of steady motions: steady motions with moving constraints are found "
            "when the constraints move by a symmetry of L (a Jacobi integral); linearize "
            "about a state to test whether it is a steady motion"
        )
    if manifold.velocity_rows:
        raise AnalysisError(
            "steady motions of moving velocity constraints are not computed; linearize about "
            "a state to test whether it is a steady motion"
        )


def steady_motions(
    subject: Subject, parameters: Values | None = None, jacobi: JacobiIntegral | None = None
) -> SteadyMotions:
    """The steady motions of constraints that move by a symmetry (see the module docstring),
    each with its stability relative to them; AnalysisError when the constraints do not
    move that way."""
    return steady_motions_at_values(evaluation_context(subject, parameters), jacobi)


def steady_motions_at_values(
    context: EvaluationContext, jacobi: JacobiIntegral | None = None
) -> SteadyMotions:
    """:func:`steady_motions` at the parameter values of ``context``."""
    eom, subs, numbers = context.eom, context.substitutions, context.values
    manifold = constraint_manifold(eom)
    jacobi = jacobi or (jacobi_integral(eom) if manifold is not None else None)
    _refuse(manifold, jacobi)
    assert manifold is not None and jacobi is not None  # _refuse said so
    potential, rate, moving = _effective_potential(eom, jacobi, subs)
    levels = [h.xreplace({eom.time: 0}).xreplace(dict(subs)) for h in manifold.position_equations]
    mus = [manifold.multipliers[row] for row in manifold.holonomic_rows]
    gradient = sp.Matrix([potential]).jacobian(list(eom.coordinates)).T
    normal = sp.Matrix(levels).jacobian(list(eom.coordinates)).T * sp.Matrix(mus)
    static = sp.ImmutableMatrix([*(-gradient + normal), *levels])
    unknowns = [q for q in eom.coordinates if depends_on(static, [q])]
    unknowns += [mu for mu in mus if depends_on(static, [mu])]
    most = symbolic_limit(static, [u for u in unknowns if u in eom.coordinates], len(mus))
    solutions, method, reason = solve_static(static, unknowns, numbers, most)
    solutions = solutions or []
    if method == "symbolic":
        solutions = complete_solutions(static, unknowns, solutions)
    test = _relative_test(eom, manifold, potential, levels, numbers)
    found, velocities = [], []
    for solution in solutions:
        motion = build_equilibrium(eom, solution, numbers, method == "symbolic", test)
        state = {q: (0 if q in motion.free else v) for q, v in motion.state.items()}
        rates = {
            v: simplify_small(c.xreplace(state).xreplace(dict(subs))) for v, c in moving.items()
        }
        if motion.exists is not False:
            motion = _with_forces(eom, manifold, motion, {**state, **rates}, subs, numbers)
        found.append(motion)
        velocities.append(frozen(rates))
    return SteadyMotions(
        motions=tuple(found),
        velocities=tuple(velocities),
        effective_potential=potential,
        rate=rate,
        symmetry=jacobi.symmetry.description,
        method=method,
        reason=f"{reason}: critical points of V_eff on the constraints at t = 0, moving by "
        f"the {jacobi.symmetry.description} at the rate {rate}",
    )
