"""Equilibria on the constraint manifold and their stability.

At rest (q_dot = q_ddot = 0) the multiplier form M q_ddot = forcing + A^T lambda becomes the
statics of constrained systems (virtual work with multipliers; Greenwood, *Advanced
Dynamics* §2.3):

    forcing(q, 0, t) + A(q, t)^T lambda = 0,      h_j(q, t) = 0 (holonomic rows),

n + r_h equations for q and the m multipliers, which is G(q) = A^T lambda for a conservative
system.  A constraint that moves (b != 0) allows no rest.  A non-holonomic constraint adds
a multiplier and no equation, so its equilibria come in families (the free coordinates).

Stability on the manifold: with the deviations confined to the holonomic constraints,
dq = P ds (:mod:`lagrangian.analysis.manifold.linearize`), the stiffness is the bordered
Hessian

    K = P^T (-d/dq (forcing + A^T lambda0)) P      (= P^T (d2V - sum lambda_j d2h_j) P),

and K > 0 means a strict minimum of the energy on the manifold: stable (Lagrange–Dirichlet;
non-holonomic constraints that do no work keep the argument).  When a non-holonomic
constraint pushes at the equilibrium (lambda != 0) or K does not decide, the eigenvalues of
the linearization on the manifold do: a positive real part is an instability.
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping

import mpmath
import sympy as sp

from lagrangian.analysis.arguments import evaluate
from lagrangian.analysis.evaluation import EvaluationContext
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold
from lagrangian.analysis.manifold.linearize import pieces, reduced_state_space
from lagrangian.analysis.rest import (
    Equilibria,
    StabilityTest,
    build_equilibrium,
    no_rest,
    positivity_condition,
    solve_static,
)
from lagrangian.analysis.roots import STARTS, normalize_angles, periodic_coordinates
from lagrangian.analysis.simplification import simplify_small_matrix
from lagrangian.analysis.spectrum import eigenvalues, growth_rates
from lagrangian.analysis.stability import stability_of
from lagrangian.constraints.projection import project
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import SEED, PointFunction, depends_on, is_zero

#: Unknowns beyond the multipliers up to which sympy.solve is tried (as for free systems).
COORDINATE_UNKNOWNS = 3


def manifold_stiffness(
    eom: EquationsOfMotion,
    manifold: ConstraintManifold,
    state: Mapping[sp.Symbol, sp.Expr],
    multipliers: Mapping[sp.Symbol, sp.Expr],
    subs: Mapping[sp.Symbol, sp.Expr],
    numbers: Mapping[sp.Symbol, sp.Expr],
) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix, sp.ImmutableMatrix, tuple[sp.Symbol, ...]]:
    """(K, M, P, independent coordinates) on the manifold at the rest state ``state``:
    K = P^T (-d(forcing + A^T lambda)/dq) P and M = P^T M(q0) P, P the map from the
    independent coordinates to all of them."""
    point = {**state, **{v: 0 for v in eom.velocities}}
    reduced = reduced_state_space(eom, manifold, point, (), subs, numbers)
    n = len(eom.coordinates)
    independent = tuple(s for s in reduced.state_vector if s in eom.coordinates)
    position = sp.Matrix(reduced.embedding[:n, : len(independent)])
    p = pieces(eom, manifold, subs)
    lam = sp.Matrix([multipliers.get(s, reduced.multipliers[s]) for s in manifold.multipliers])
    forces = (p.forcing + p.jacobian.T * lam).xreplace({v: 0 for v in eom.velocities})
    full = -forces.jacobian(list(eom.coordinates)).xreplace(point)
    stiffness = simplify_small_matrix(position.T * full * position)
    mass = simplify_small_matrix(position.T * p.mass.xreplace(point) * position)
    return stiffness, mass, sp.ImmutableMatrix(position), independent


def _pushing(manifold: ConstraintManifold, multipliers, numbers) -> list[str]:
    """Labels of the velocity-level constraints whose multiplier is not 0 at rest."""
    pushing = []
    for row in manifold.velocity_rows:
        value = evaluate(to_sympy(multipliers.get(manifold.multipliers[row], 0)), numbers)
        if value.free_symbols or abs(complex(value)) > 1e-9:
            pushing.append(manifold.labels[row])
    return pushing


def _by_eigenvalues(eom, manifold, point, subs, numbers, why: str) -> tuple[bool | None, str]:
    """The verdict of the linearization on the manifold: growth -> unstable, else open."""
    reduced = reduced_state_space(eom, manifold, point, (), subs, numbers)
    numeric = evaluate(reduced.A, numbers)
    if numeric.free_symbols:
        return None, f"{why}; the linearization needs values for its parameters"
    values = eigenvalues(numeric)
    growth = growth_rates(values)
    listing = ", ".join(str(v) for v in values)
    if growth:
        return False, f"{why}; the linearization on the manifold grows (eigenvalues {listing})"
    return None, f"{why}; no eigenvalue of the linearization grows (eigenvalues {listing})"


def _manifold_test(eom, manifold, numbers, subs) -> StabilityTest:
    """Stability on the manifold (see the module docstring)."""

    def test(state, free, multipliers, exact):
        at_rest = {q: (0 if q in free else v) for q, v in state.items()}
        stiffness, _, _, independent = manifold_stiffness(
            eom, manifold, at_rest, multipliers, subs, numbers
        )
        kept = [i for i, q in enumerate(independent) if q not in free]
        reduced = stiffness.extract(kept, kept)
        condition = positivity_condition(reduced, eom, exact)
        pushing = _pushing(manifold, multipliers, numbers)
        numeric = evaluate(reduced, numbers)
        point = {**at_rest, **{v: 0 for v in eom.velocities}}
        if pushing:
            why = f"the non-holonomic {', '.join(pushing)} pushes at rest (lambda != 0)"
            stable, reason = _by_eigenvalues(eom, manifold, point, subs, numbers, why)
        elif numeric.free_symbols:
            verdict = condition if condition in (sp.true, sp.false) else None
            stable = None if verdict is None else bool(verdict)
            missing = ", ".join(sorted(s.name for s in numeric.free_symbols))
            reason = f"stable when {condition} (no values for {missing})"
        else:
            stable, reason = stability_of(numeric, None, [q.name for q in free])
            reason = "on the constraint manifold, " + reason
            if stable is None:
                stable, reason = _by_eigenvalues(eom, manifold, point, subs, numbers, reason)
        return stable, reason, stiffness, condition, independent

    return test


def symbolic_limit(static: sp.MatrixBase, coordinates: list[sp.Symbol], multipliers: int) -> int:
    """How many unknowns sympy.solve may take: the multipliers (they enter linearly) and up
    to ``COORDINATE_UNKNOWNS`` coordinates when the equations are polynomial in them, two
    when functions of them appear (trigonometric systems in three angles, as a four-bar
    linkage's, keep sympy.solve busy for minutes)."""
    polynomial = all(to_sympy(e).is_polynomial(*coordinates) for e in static)
    return multipliers + (COORDINATE_UNKNOWNS if polynomial else 2)


def _static_equations(eom, manifold, subs) -> tuple[sp.ImmutableMatrix, list[sp.Symbol]]:
    """forcing(q, 0, t) + A^T lambda, then h_j(q, t), and the unknowns (q, lambda)."""
    p = pieces(eom, manifold, subs)
    at_rest = {v: 0 for v in eom.velocities}
    lam = sp.Matrix(manifold.multipliers)
    forces = (p.forcing + p.jacobian.T * lam).xreplace(at_rest)
    positions = [h.xreplace(dict(subs)) for h in manifold.position_equations]
    static = sp.ImmutableMatrix([*forces, *positions])
    unknowns = [q for q in eom.coordinates if depends_on(static, [q])]
    return static, [*unknowns, *(s for s in manifold.multipliers if depends_on(static, [s]))]


def _starts_on_manifold(
    eom: EquationsOfMotion,
    manifold: ConstraintManifold,
    static: sp.MatrixBase,
    unknowns: list[sp.Symbol],
    numbers: Mapping[sp.Symbol, sp.Expr],
) -> list[list[float]]:
    """Starting points for Newton's method on the statics: random configurations moved onto
    the holonomic constraints, each with the multipliers that fit best there (least
    squares), so that the search starts on the manifold."""
    rng = random.Random(SEED)
    coordinates = [q for q in unknowns if q in eom.coordinates]
    multipliers = [s for s in unknowns if s not in eom.coordinates]
    angles = periodic_coordinates(coordinates, static)
    levels = [evaluate(h, numbers) for h in manifold.position_equations]
    n = len(eom.coordinates)
    forces = _ForcesAtRest(static[:n, :], list(eom.coordinates), multipliers, numbers)
    starts = []
    for attempt in range(STARTS):
        scale = (0.5, 2.0, 8.0)[attempt % 3]
        guess = {
            q: rng.uniform(-math.pi, math.pi) if q in angles else rng.uniform(-scale, scale)
            for q in eom.coordinates
        }
        landed = project(levels, list(eom.coordinates), guess, starts=1)
        if not landed.satisfied:
            continue
        q0 = {q: sp.Float(v, 20) for q, v in landed.values.items() if q in eom.coordinates}
        linear = forces(q0)
        if linear is None:
            continue
        slopes, rhs = linear
        try:
            lam = mpmath.qr_solve(mpmath.matrix(slopes), mpmath.matrix(rhs))[0]
        except (ZeroDivisionError, ValueError, TypeError):
            continue
        starts.append([float(q0[q]) for q in coordinates] + [float(x) for x in lam])
    return starts


class _ForcesAtRest:
    """The static forces F(q) + S(q) lambda (linear in the multipliers) at a configuration,
    as (S, -F) in numbers: compiled once (:class:`PointFunction`) when the parameters have
    numeric values, else substituted into the expressions at each configuration."""

    def __init__(
        self,
        forces: sp.MatrixBase,
        coordinates: list[sp.Symbol],
        multipliers: list[sp.Symbol],
        numbers: Mapping[sp.Symbol, sp.Expr],
    ) -> None:
        self.forces, self.multipliers, self.numbers = forces, multipliers, numbers
        self.parameters: dict[sp.Symbol, float] | None = {}
        self.function: PointFunction | None = None
        known = {*coordinates, *multipliers}
        for symbol in sorted(forces.free_symbols - known, key=str):
            value = evaluate(symbol, numbers)
            if not (isinstance(value, sp.Expr) and value.is_number and value.is_real):
                self.parameters = None  # no number to compile with: substitute instead
                return
            self.parameters[symbol] = float(value)
        self.symbols = [*coordinates, *multipliers, *self.parameters]
        self.function = PointFunction(forces, self.symbols)

    def __call__(self, q0: Mapping[sp.Symbol, sp.Expr]) -> tuple[list, list] | None:
        """(S, -F) at ``q0`` as nested lists, or None where they are not finite numbers."""
        n, m = self.forces.rows, len(self.multipliers)
        if self.function is None or self.parameters is None:
            forces = evaluate(self.forces.xreplace(dict(q0)), self.numbers)
            known = forces.xreplace({s: 0 for s in self.multipliers})
            slopes = forces.jacobian(self.multipliers) if self.multipliers else sp.zeros(n, 0)
            return slopes.tolist(), (-known).tolist()
        point: dict[sp.Symbol, float] = {q: float(v) for q, v in q0.items()}
        point.update(self.parameters)
        values = []
        for j in range(-1, m):  # lambda = 0, then each unit multiplier: F, then F + S e_j
            point.update({s: float(i == j) for i, s in enumerate(self.multipliers)})
            value = self.function(point)
            if value is None:
                return None
            values.append(value[:, 0])
        known = values[0]
        slopes = [[values[j + 1][i] - known[i] for j in range(m)] for i in range(n)]
        return slopes, [[-float(x)] for x in known]


def complete_solutions(
    static: sp.MatrixBase, unknowns: list[sp.Symbol], solutions: list[dict]
) -> list[dict]:
    """Solutions that satisfy every static equation: sympy.solve can return a branch with
    some unknowns left out ({phi: pi/2} without its lambda) or one that fails an equation
    ({lambda: 0} with a force left over); the rest is solved for, or the branch dropped."""
    complete = []
    for solution in solutions:
        residual = [e for e in static.xreplace(solution) if not is_zero(e)]
        if not residual:
            complete.append(solution)
            continue
        missing = [
            u for u in unknowns if u not in solution and depends_on(sp.Matrix(residual), [u])
        ]
        if not missing:
            continue
        try:
            extensions = sp.solve(residual, missing, dict=True)
        except (NotImplementedError, ValueError, TypeError):
            continue
        for extension in extensions:
            merged = {**solution, **extension}
            if all(is_zero(e) for e in static.xreplace(merged)):
                complete.append(merged)
    return complete


def manifold_equilibria(context: EvaluationContext, manifold: ConstraintManifold) -> Equilibria:
    """Every equilibrium on the manifold (see the module docstring) at the parameter values
    of ``context``, each with its multipliers and its stability; families of equilibria keep
    their free coordinates."""
    eom, subs, numbers = context.eom, context.substitutions, context.values
    static, unknowns = _static_equations(eom, manifold, subs)
    moving = [manifold.labels[row] for row in manifold.moving]
    if moving:
        return no_rest(
            static,
            f"the constraint {', '.join(moving)} moves with time (b != 0): no state of rest; "
            "see the energy (a Jacobi integral) and the linearization about a steady motion",
        )
    if depends_on(static, [eom.time]):
        return no_rest(static, "the static equations depend on time (driven or rheonomic)")
    test = _manifold_test(eom, manifold, numbers, subs)
    if all(is_zero(e) for e in static):
        return Equilibria(
            (build_equilibrium(eom, {}, numbers, True, test),),
            static,
            None,
            "symbolic",
            "the static forces vanish",
        )
    solutions, method, reason = solve_static(
        static,
        unknowns,
        numbers,
        symbolic_limit(static, [u for u in unknowns if u in eom.coordinates], manifold.size),
        lambda: _starts_on_manifold(eom, manifold, static, unknowns, numbers),
    )
    if solutions is None:
        return no_rest(static, reason)
    if method == "symbolic":
        solutions = complete_solutions(static, unknowns, solutions)
    if method == "numeric" and len([e for e in static if e != 0]) != len(unknowns):
        return no_rest(
            static,
            "sympy.solve failed, and the static equations are not square (non-holonomic "
            "constraints leave families of equilibria), so no numeric search either",
        )
    angles = periodic_coordinates([q for q in unknowns if q in eom.coordinates], static)
    solutions = normalize_angles(solutions, angles, numbers)
    found = []
    for solution in solutions:
        try:
            found.append(build_equilibrium(eom, solution, numbers, method == "symbolic", test))
        except AnalysisError:
            continue  # a singular point of the constraints: not a regular equilibrium
    reason += " (forcing + A^T lambda = 0 with the holonomic constraints)"
    return Equilibria(tuple(found), static, None, method, reason)
