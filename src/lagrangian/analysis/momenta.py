"""Conjugate momenta and cyclic coordinates (Goldstein, Classical Mechanics, 3rd ed., §2.6).

    p_j = dL/dq_dot_j,       d/dt p_j = dL/dq_j + Q_j - dF/dq_dot_j,

so a coordinate that L (and the dissipation function F) does not contain is *cyclic*, and its
momentum is a constant of the motion when no applied, dissipative or constraint force acts
along it; with constraints d/dt p_j gains sum_k lambda_k a_kj, so a constraint whose Jacobian
column j is not zero changes p_j too.  A cart pushed by a force F is cyclic, and p_x is not
conserved (unless F = 0).

>>> import lagrangian as lg
>>> [c.coordinate for c in cyclic_coordinates(lg.examples.planet())]
[theta]
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of
from lagrangian.analysis.at_rest import VelocityFree, expression_at_rest
from lagrangian.analysis.evaluation import EvaluationContext, condition_text, evaluation_context
from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
from lagrangian.analysis.manifold.left_out import constraint_names
from lagrangian.analysis.names import OutputNames
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.steps import step_momenta, step_slopes
from lagrangian.symbolic.nonsmooth import derivative
from lagrangian.symbolic.probe import is_zero


def momentum_symbols(eom: EquationsOfMotion) -> tuple[sp.Symbol, ...]:
    """``p_q`` for every coordinate (``P_q`` where the model has a ``p_q`` of its own:
    :class:`~lagrangian.analysis.names.OutputNames`)."""
    names = OutputNames.of(eom)
    return tuple(sp.Symbol(names.momentum(q)) for q in eom.coordinates)


@dataclass(frozen=True)
class ConjugateMomenta:
    """p_j = dL/dq_dot_j for every coordinate, in the order of ``coordinates``."""

    coordinates: tuple[sp.Symbol, ...]
    momenta: sp.ImmutableMatrix

    def __getitem__(self, coordinate: sp.Symbol | str) -> sp.Expr:
        names = [q.name for q in self.coordinates]
        key = coordinate if isinstance(coordinate, str) else coordinate.name
        return self.momenta[names.index(key)]

    def by_name(self) -> dict[str, sp.Expr]:
        return {q.name: p for q, p in zip(self.coordinates, self.momenta)}


@dataclass(frozen=True)
class CyclicCoordinate:
    """A coordinate absent from L and from the Rayleigh function F (Goldstein §2.6), its
    momentum, and whether that momentum is conserved: ``obstructions`` names what changes
    it ("force", "dissipation", "constraint"), ``condition`` the parameter values under
    which it is conserved all the same (a force parameter that is 0)."""

    coordinate: sp.Symbol
    momentum: sp.Expr
    reason: str
    conserved: bool = True
    obstructions: tuple[str, ...] = ()
    condition: sp.Basic = sp.true


def conjugate_momenta(subject: Subject) -> ConjugateMomenta:
    """The generalized momenta p_j = dL/dq_dot_j (the first step of each derivation).

    >>> import lagrangian as lg
    >>> conjugate_momenta(lg.examples.planet())["theta"]
    m*r**2*theta_dot
    """
    eom = equations_of(subject)
    return ConjugateMomenta(
        coordinates=tuple(eom.coordinates),
        momenta=sp.ImmutableMatrix(step_momenta(eom.system)),
    )


def _obstructions(eom: EquationsOfMotion, j: int) -> list[tuple[str, str, sp.Expr]]:
    """(kind, description, expression) of everything that changes p_j: the applied force
    Q_j, the dissipative force -dF/dq_dot_j, each kept constraint with a force along q_j (a
    non-zero column j of its Jacobian), and the unilateral constraints whose g contains q_j,
    said together (a disk of a gas touches its walls and every other disk)."""
    q = eom.coordinates[j]
    found = []
    if not is_zero(eom.generalized_forces[j]):
        force = eom.generalized_forces[j]
        found.append(("force", f"the applied force Q_{q.name} = {force}", force))
    if not is_zero(eom.dissipation_forces[j]):
        friction = eom.dissipation_forces[j]
        found.append(("dissipation", f"the dissipative force {friction}", friction))
    manifold = constraint_manifold(eom)
    if manifold is None:
        return found
    for row, name in enumerate(manifold.labels):
        column = manifold.jacobian[row, j]
        if not is_zero(column):
            found.append(("constraint", f"the constraint {name} (a_{q.name} = {column})", column))
    # dg/dq_j from the classification's Jacobian (a row per constraint), not differentiated
    # again: a gas of n disks has n (n - 1) / 2 contacts, O(n) of them along each coordinate
    gradients = manifold.classification.constraint_jacobian
    touching = [
        (i, c, gradients[i, j])
        for i, c in enumerate(eom.system.constraints)
        if c.kind == "unilateral" and not is_zero(gradients[i, j])
    ]
    if touching:
        named = constraint_names([(i, c) for i, c, _ in touching])
        several = " constraints" if len(touching) > 1 else ""
        what = f"the unilateral{several} {named} while in contact"
        found += [("constraint", what, slope) for _, _, slope in touching]
    return found


def _cyclic(context: EvaluationContext, j: int) -> CyclicCoordinate:
    eom = context.eom
    q, momentum = eom.coordinates[j], step_momenta(eom.system)[j]
    absent = f"{q.name} does not appear in L (nor in the dissipation function F)"
    blocking = _obstructions(eom, j)
    if not blocking:
        reason = (
            f"{q.name} does not appear in L and no applied or dissipative force acts on it, "
            f"so d/dt p_{q.name} = dL/d{q.name} = 0"
        )
        return CyclicCoordinate(q, momentum, reason)
    kinds = tuple(dict.fromkeys(kind for kind, _, _ in blocking))
    causes = "; ".join(dict.fromkeys(what for _, what, _ in blocking))
    conditions = []
    for _, _, expr in blocking:  # the first that the values leave non-zero settles it
        condition = context.vanishing_condition(expr)
        if condition is None:
            break
        conditions.append(condition)
    else:
        condition = sp.And(*conditions)
        reason = (
            f"{absent}; {causes} vanishes at the given parameter values "
            f"({condition_text(condition)}), so "
            f"p_{q.name} is conserved there (for other values it changes p_{q.name})"
        )
        return CyclicCoordinate(q, momentum, reason, True, kinds, condition)
    changes = "change" if len(blocking) > 1 else "changes"
    reason = (
        f"{absent}, so it is cyclic, but p_{q.name} is not conserved: {causes} {changes} it "
        f"(d/dt p_{q.name} = Q_{q.name} - dF/d{q.name}_dot + sum_j lambda_j a_j{q.name})"
    )
    return CyclicCoordinate(q, momentum, reason, False, kinds, sp.false)


def _slopes_at_rest(eom: EquationsOfMotion, velocities: VelocityFree) -> list[sp.Expr]:
    """dL/dq_j at rest, = d L(q, 0, t)/dq_j, each from the terms of T, V and U at rest that
    hold q_j (a chain's V: one term per coordinate), nothing expanded."""
    column = {q: j for j, q in enumerate(eom.coordinates)}
    slopes: list[list[sp.Expr]] = [[] for _ in column]
    pieces = ((1, eom.kinetic_energy), (-1, eom.potential_energy), (-1, eom.velocity_potential))
    for sign, piece in pieces:
        for term in sp.Add.make_args(expression_at_rest(piece, velocities)):
            for q in term.free_symbols & column.keys():
                slopes[column[q]].append(sign * derivative(term, q))
    return [sp.Add(*terms) for terms in slopes]


def _vanishes(expr: sp.Expr, velocities: VelocityFree) -> bool:
    """``expr`` = 0 identically: not when its part at rest (a few terms, -dV/dq for a
    natural system) is not, found without evaluating all of it; else by probing all."""
    if not is_zero(expression_at_rest(expr, velocities)):
        return False
    return is_zero(expr)


def cyclic_coordinates(
    subject: Subject, parameters: Values | None = None
) -> tuple[CyclicCoordinate, ...]:
    """Coordinates absent from L and from the dissipation function F (dL/dq_j = 0 and
    dF/dq_j = 0: Goldstein's cyclic coordinates), each with whether p_j is conserved: not
    when an applied force, dissipation or a constraint force acts along q_j, unless that
    vanishes at the parameter values (``parameters`` over the defaults), said as the
    condition.

    >>> import lagrangian as lg
    >>> cyclic_coordinates(lg.examples.spherical_pendulum())[0].momentum
    l**2*m*phi_dot*sin(theta)**2
    """
    return cyclic_at_values(evaluation_context(subject, parameters))


def cyclic_at_values(context: EvaluationContext) -> tuple[CyclicCoordinate, ...]:
    """:func:`cyclic_coordinates` with the parameter values of ``context``."""
    eom = context.eom
    dissipation = eom.dissipation_function
    # the symbols of L = T - V - U and of F once, not once per coordinate (a chain's L has
    # n^2 terms); a symbol of T that L has lost to a cancellation is tested by dL/dq = 0
    pieces = (eom.kinetic_energy, eom.potential_energy, eom.velocity_potential)
    in_lagrangian = set().union(*(piece.free_symbols for piece in pieces))
    in_dissipation = dissipation.free_symbols
    velocities = VelocityFree(frozenset(eom.velocities))
    at_rest = _slopes_at_rest(eom, velocities)
    found = []
    for j, q in enumerate(eom.coordinates):
        # dL/dq_j at rest not 0 (-dV/dq_j of a pendulum) proves dL/dq_j != 0 before the
        # steps' dL/dq_j (n^2 terms each for a chain) are converted to be probed
        if q in in_lagrangian and (
            not is_zero(at_rest[j]) or not _vanishes(step_slopes(eom.system)[j], velocities)
        ):
            continue
        if q in in_dissipation and not is_zero(dissipation.diff(q)):
            continue
        found.append(_cyclic(context, j))
    return tuple(found)
