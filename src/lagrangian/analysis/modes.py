"""Small oscillations about a stable equilibrium (normal modes).

Near an equilibrium q0, with M = M(q0) and K = -d forcing/dq at rest (the Hessian of the
effective potential), q = q0 + v cos(omega t) solves

    K v = omega^2 M v          (generalized symmetric eigenproblem),

giving the frequencies omega (rad/s) and the mode shapes v.  Damping and gyroscopic terms
are left out (see :func:`~lagrangian.analysis.linearize.linearize` for those).

>>> import lagrangian as lg
>>> normal_modes(lg.examples.simple_pendulum()).frequencies
(sqrt(g)/sqrt(l),)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    assuming_positive,
    evaluate,
    frozen,
    is_zero_value,
    operating_state,
)
from lagrangian.analysis.equilibria import equilibria_at_values, static_forces
from lagrangian.analysis.evaluation import EvaluationContext, evaluation_context
from lagrangian.analysis.linearize import linearize
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, constraint_manifold
from lagrangian.analysis.manifold.modes import linearized_modes, manifold_oscillation
from lagrangian.analysis.pencil import solve_pencil
from lagrangian.analysis.rest import Equilibrium, first_stable
from lagrangian.analysis.simplification import simplify_small, simplify_small_matrix
from lagrangian.analysis.spectrum import symmetric_eigenvalues
from lagrangian.analysis.stability import stability_of, stiffness_matrix
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.probe import is_zero


@dataclass(frozen=True)
class NormalModes:
    """Frequencies (ascending) and mode shapes about the equilibrium ``about``; on a
    constraint manifold K and M are written in its independent coordinates and the shapes
    in all the coordinates."""

    about: Mapping[sp.Symbol, sp.Expr]
    mass_matrix: sp.ImmutableMatrix
    stiffness_matrix: sp.ImmutableMatrix
    squared_frequencies: tuple[sp.Expr, ...]
    frequencies: tuple[sp.Expr, ...]
    shapes: tuple[sp.ImmutableMatrix, ...]
    symbolic: bool
    reason: str


def _eigenvalue_text(context: EvaluationContext, point) -> str:
    eom, parameters = context.eom, context.parameters
    try:
        values = linearize(eom, point, parameters=parameters).eigenvalues
    except AnalysisError as error:
        return f"(no linearization: {error})"
    return "linearization eigenvalues: " + (", ".join(str(v) for v in values) or "unknown")


def _check_rest(context: EvaluationContext, state) -> None:
    eom, subs, numbers = context.eom, context.substitutions, context.values
    moving = [v.name for v in eom.velocities if not is_zero_value(state[v])]
    if moving:
        raise AnalysisError(
            f"Normal modes are small oscillations about a state of rest, but {', '.join(moving)}"
            " is not 0; use linearize() for steady motions."
        )
    residual = static_forces(eom, subs).xreplace(state)
    numeric = evaluate(residual, numbers)
    if all(is_zero(r) for r in residual) or (
        not numeric.free_symbols and all(abs(complex(r)) < 1e-9 for r in numeric)
    ):
        return
    point = {q: state[q] for q in eom.coordinates}
    raise AnalysisError(
        f"{point} is not an equilibrium: the static forces there are "
        f"{[simplify_small(r) for r in residual]}; {_eigenvalue_text(context, point)}"
    )


def _check_inertia(m: sp.MatrixBase, numeric: sp.MatrixBase | None, point) -> None:
    if numeric is not None:
        regular = all(v > 1e-12 * max(1.0, abs(v)) for v in symmetric_eigenvalues(numeric))
    else:
        regular = not is_zero(m.det())
    if not regular:
        raise AnalysisError(
            f"The mass matrix at {point} is {m.tolist()}, not positive definite: a singular "
            "point of the coordinates (or a coordinate without inertia); no normal modes here."
        )


def _rest_point(context: EvaluationContext, about) -> tuple[dict, bool]:
    """The coordinates of the equilibrium to oscillate about (a family's free ones at 0),
    and whether its stability is still to be checked."""
    if about is None or isinstance(about, Equilibrium):
        equilibrium = about or first_stable(equilibria_at_values(context))
        point = {q: 0 if q in equilibrium.free else v for q, v in equilibrium.state.items()}
        if equilibrium.stable is not True:
            raise AnalysisError(
                f"{point} is not known to be stable ({equilibrium.reason}); "
                f"{_eigenvalue_text(context, point)}"
            )
        return point, False
    state = operating_state(context.eom, about)
    _check_rest(context, state)
    return {q: state[q] for q in context.eom.coordinates}, True


def normal_modes(
    subject: Subject,
    about: Values | Equilibrium | None = None,
    parameters: Values | None = None,
) -> NormalModes:
    """K v = omega^2 M v about ``about`` (a state, an :class:`Equilibrium` found before, or
    by default the first stable equilibrium); symbolic when 2 x 2 (or 1 x 1) and short,
    numeric at the parameter values otherwise.

    Refused (AnalysisError) about a non-equilibrium or an unstable point; the message gives
    the linearization's eigenvalues.

    >>> import lagrangian as lg
    >>> normal_modes(lg.examples.two_masses_three_springs(),
    ...              parameters={"m2": "m1", "k2": "k1", "k3": "k1"}).squared_frequencies
    (k1/m1, 3*k1/m1)
    """
    return modes_at_values(evaluation_context(subject, parameters), about)


def modes_at_values(
    context: EvaluationContext, about: Values | Equilibrium | None = None
) -> NormalModes:
    """:func:`normal_modes` at the parameter values of ``context``."""
    eom, subs, numbers = context.eom, dict(context.substitutions), context.values
    manifold = constraint_manifold(eom)
    if manifold is not None:
        return _manifold_modes(context, manifold, about)
    point, unchecked = _rest_point(context, about)
    at_point = {**point, **{v: 0 for v in eom.velocities}}
    k = simplify_small_matrix(
        stiffness_matrix(static_forces(eom, subs), eom.coordinates).xreplace(at_point)
    )
    m = simplify_small_matrix(sp.Matrix(eom.mass_matrix).xreplace(subs).xreplace(at_point))
    k_numeric, m_numeric = evaluate(k, numbers), evaluate(m, numbers)
    known = not (k_numeric.free_symbols or m_numeric.free_symbols)
    _check_inertia(m, m_numeric if known else None, point)
    if unchecked and known:
        stable, why = stability_of(k_numeric)
        if not stable:
            raise AnalysisError(
                f"{point} is not a stable equilibrium ({why}); {_eigenvalue_text(context, point)}"
            )
    squares, shapes, symbolic, reason = solve_pencil(k, m, k_numeric, m_numeric, eom, numbers)
    frequencies = tuple(
        assuming_positive(sp.sqrt(w2), eom) if symbolic else sp.sqrt(max(w2, 0)) for w2 in squares
    )
    return NormalModes(
        about=frozen(point),
        mass_matrix=m,
        stiffness_matrix=k,
        squared_frequencies=squares,
        frequencies=frequencies,
        shapes=shapes,
        symbolic=symbolic,
        reason=reason + "; damping and gyroscopic terms left out",
    )


def _manifold_modes(
    context: EvaluationContext,
    manifold: ConstraintManifold,
    about: Values | Equilibrium | None,
) -> NormalModes:
    """Normal modes on the constraint manifold (:mod:`lagrangian.analysis.manifold.modes`):
    K v = omega^2 M v in the independent coordinates, shapes in all of them."""
    eom, numbers = context.eom, context.values
    found = manifold_oscillation(context, manifold, about)
    names = ", ".join(q.name for q in found.independent)
    if manifold.velocity_rows:
        frequencies, shapes = linearized_modes(context, manifold, found.point)
        return NormalModes(
            about=frozen(found.point),
            mass_matrix=found.mass,
            stiffness_matrix=found.stiffness,
            squared_frequencies=tuple(w**2 for w in frequencies),
            frequencies=frequencies,
            shapes=shapes,
            symbolic=False,
            reason="eigenvalues and eigenvectors of the linearization on the constraint "
            "manifold (velocity constraints: no symmetric K v = omega^2 M v); shapes are "
            "the coordinate parts of the eigenvectors",
        )
    k, m = found.stiffness, found.mass
    k_numeric, m_numeric = evaluate(k, numbers), evaluate(m, numbers)
    if not (k_numeric.free_symbols or m_numeric.free_symbols):
        _check_inertia(m, m_numeric, found.point)
    squares, shapes, symbolic, reason = solve_pencil(k, m, k_numeric, m_numeric, eom, numbers)
    full = tuple(
        sp.ImmutableMatrix([simplify_small(x) for x in found.embedding * sp.Matrix(v)])
        for v in shapes
    )
    return NormalModes(
        about=frozen(found.point),
        mass_matrix=m,
        stiffness_matrix=k,
        squared_frequencies=squares,
        frequencies=tuple(
            assuming_positive(sp.sqrt(w2), eom) if symbolic else sp.sqrt(max(w2, 0))
            for w2 in squares
        ),
        shapes=full,
        symbolic=symbolic,
        reason=f"{reason} on the constraint manifold: K and M in the independent coordinates "
        f"({names}), the shapes in all the coordinates; damping and gyroscopic terms left out",
    )
