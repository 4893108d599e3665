"""Small oscillations about an equilibrium on the constraint manifold.

With holonomic constraints only, the deviations dq = P ds of the independent coordinates s
(:mod:`lagrangian.analysis.manifold.linearize`) oscillate as

    K v = omega^2 M v,    K = P^T (-d(forcing + A^T lambda0)/dq) P,   M = P^T M(q0) P,

(the bordered Hessian of :mod:`lagrangian.analysis.manifold.statics`), and each mode shape
in all the coordinates is P v: a Cartesian pendulum at (0, -l) swings along x alone, at
sqrt(g/l).  With velocity constraints the linearized motion is not of that symmetric form;
its frequencies are the imaginary parts of the eigenvalues of the linearization on the
manifold, and the shapes the coordinate parts of its eigenvectors.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Values, evaluate, is_zero_value, operating_state
from lagrangian.analysis.equilibria import equilibria_at_values
from lagrangian.analysis.evaluation import EvaluationContext
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, require_on_manifold
from lagrangian.analysis.manifold.linearize import reduced_state_space
from lagrangian.analysis.manifold.statics import manifold_stiffness
from lagrangian.analysis.rest import Equilibrium, first_stable
from lagrangian.analysis.simplification import simplify_small
from lagrangian.analysis.spectrum import TOLERANCE, eigenpairs
from lagrangian.analysis.stability import stability_of
from lagrangian.errors import AnalysisError


@dataclass(frozen=True)
class ManifoldOscillation:
    """K and M on the manifold about ``point`` (the coordinates at rest), in the
    independent coordinates ``independent`` (a family's free ones left out), and P, the
    map from those to every coordinate."""

    point: dict[sp.Symbol, sp.Expr]
    stiffness: sp.ImmutableMatrix
    mass: sp.ImmutableMatrix
    embedding: sp.ImmutableMatrix
    independent: tuple[sp.Symbol, ...]


def _from_equilibrium(eom, equilibrium: Equilibrium) -> tuple[dict, dict, tuple]:
    point = {q: 0 if q in equilibrium.free else v for q, v in equilibrium.state.items()}
    if equilibrium.stable is not True:
        raise AnalysisError(
            f"{point} is not known to be stable on the constraint manifold ({equilibrium.reason})."
        )
    return point, dict(equilibrium.multipliers), equilibrium.free


def _from_state(eom, manifold, about, subs, numbers) -> tuple[dict, dict, tuple]:
    state = operating_state(eom, about)
    moving = [v.name for v in eom.velocities if not is_zero_value(state[v])]
    if moving:
        raise AnalysisError(
            f"Normal modes are small oscillations about a state of rest, but {', '.join(moving)}"
            " is not 0; use linearize() for steady motions."
        )
    require_on_manifold(eom, state, numbers, "give a configuration on the constraints")
    reduced = reduced_state_space(eom, manifold, state, (), subs, numbers)
    residual = evaluate(reduced.accelerations, numbers)
    if residual.free_symbols or any(abs(complex(a)) > 1e-9 for a in residual):
        point = {q: state[q] for q in eom.coordinates}
        raise AnalysisError(
            f"{point} is not an equilibrium on the constraint manifold: the constrained "
            f"accelerations there are {[simplify_small(a) for a in reduced.accelerations]}."
        )
    return {q: state[q] for q in eom.coordinates}, dict(reduced.multipliers), ()


def manifold_oscillation(
    context: EvaluationContext,
    manifold: ConstraintManifold,
    about: Values | Equilibrium | None,
) -> ManifoldOscillation:
    """K, M and P about ``about`` (an Equilibrium, a state of rest on the manifold, or by
    default the first stable equilibrium); AnalysisError when it is not a stable
    equilibrium."""
    eom, subs, numbers = context.eom, dict(context.substitutions), context.values
    if about is None or isinstance(about, Equilibrium):
        chosen = about or first_stable(equilibria_at_values(context))
        point, multipliers, free = _from_equilibrium(eom, chosen)
        checked = True
    else:
        point, multipliers, free = _from_state(eom, manifold, about, subs, numbers)
        checked = False
    stiffness, mass, embedding, independent = manifold_stiffness(
        eom, manifold, point, multipliers, subs, numbers
    )
    kept = [i for i, q in enumerate(independent) if q not in free]
    stiffness, mass = stiffness.extract(kept, kept), mass.extract(kept, kept)
    numeric = evaluate(stiffness, numbers)
    if not checked and not numeric.free_symbols:
        stable, why = stability_of(numeric)
        if not stable and not manifold.velocity_rows:
            raise AnalysisError(f"{point} is not a stable equilibrium on the manifold ({why}).")
    return ManifoldOscillation(
        point=point,
        stiffness=stiffness,
        mass=mass,
        embedding=sp.ImmutableMatrix(embedding.extract(list(range(embedding.rows)), kept)),
        independent=tuple(independent[i] for i in kept),
    )


def _shape(vector: list[complex]) -> sp.ImmutableMatrix:
    """A complex mode shape turned so that its largest entry is +1, real parts kept."""
    biggest = max(vector, key=abs)
    return sp.ImmutableMatrix([sp.Float((z / biggest).real, 15) for z in vector])


def linearized_modes(
    context: EvaluationContext,
    manifold: ConstraintManifold,
    point: Mapping[sp.Symbol, sp.Expr],
) -> tuple[tuple[sp.Expr, ...], tuple[sp.ImmutableMatrix, ...]]:
    """Frequencies (ascending) and coordinate shapes from the eigenvalues and eigenvectors
    of the linearization on the manifold at the state of rest ``point``."""
    eom, subs, numbers = context.eom, dict(context.substitutions), context.values
    state = {**point, **{v: 0 for v in eom.velocities}}
    reduced = reduced_state_space(eom, manifold, state, (), subs, numbers)
    numeric = evaluate(reduced.A, numbers)
    embedding = evaluate(reduced.embedding, numbers)
    if numeric.free_symbols or embedding.free_symbols:
        raise AnalysisError("No numbers for the parameters of the linearization.")
    n = len(eom.coordinates)
    found: list[tuple[float, sp.ImmutableMatrix]] = []
    for value, vector in eigenpairs(numeric):
        if value.imag <= TOLERANCE * max(1.0, abs(value)):
            continue
        full = embedding * sp.Matrix(vector)
        omega = value.imag
        if any(abs(omega - w) <= 1e-9 * max(1.0, omega) for w, _ in found):
            continue
        found.append((omega, _shape([complex(full[r]) for r in range(n)])))
    found.sort(key=lambda pair: pair[0])
    return tuple(sp.Float(w, 15) for w, _ in found), tuple(s for _, s in found)
