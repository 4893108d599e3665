"""The Hamiltonian of a constrained system: in reduced coordinates when the constraints are
holonomic, and why there is none otherwise.

Holonomic constraints h(q, t) = 0 can be solved for some coordinates, q_dep = f(q_ind, t)
(:func:`lagrangian.constraints.eliminate`); the Lagrangian in the independent coordinates is
regular again and its Legendre transform is the Hamiltonian of the constrained motion
(Goldstein, *Classical Mechanics*, §8.1, with the constraints used to pick the coordinates).
The independent coordinates are tried in order, ``(x,)`` before ``(y,)``; when the constraints
have several solution branches, the one through the reference state (the initial values, else
the ``through`` state, a stable equilibrium) is kept.

A non-holonomic constraint cannot be used to remove a coordinate: the constrained motion is
not the flow of a Hamiltonian on a symplectic manifold (the 2-form is not preserved; Bloch,
*Nonholonomic Mechanics and Control*, §5.8), so there is no Hamiltonian in the usual sense —
the energy function h is what is left (and it is conserved when the constraints do not move).

>>> import lagrangian as lg
>>> reduced_hamiltonian(lg.examples.cylinder_on_incline()).coordinates
(x,)
"""

from __future__ import annotations

from collections.abc import Mapping
from itertools import combinations, islice
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import Subject, equations_of, evaluate, frozen
from lagrangian.analysis.hamiltonian import HamiltonEquations, Hamiltonian, hamilton_equations
from lagrangian.analysis.hamiltonian import hamiltonian as legendre_transform
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, constraint_manifold
from lagrangian.analysis.simplification import simplify_small
from lagrangian.constraints import eliminate
from lagrangian.constraints.eliminate import elimination_rule
from lagrangian.derivation import derive
from lagrangian.errors import AnalysisError, LagrangianError
from lagrangian.model import System
from lagrangian.symbolic.conversion import to_sympy

#: Choices of independent coordinates tried before giving up.
CHOICES = 12


def _refuse_nonholonomic(manifold: ConstraintManifold) -> None:
    classes = manifold.classification.constraints
    for index, name in zip(manifold.indices, manifold.labels):
        found = classes[index]
        if not found.holonomic:
            raise AnalysisError(
                f"no Hamiltonian in the usual sense: the constraint {name} is non-holonomic "
                f"({found.reason}), so it cannot remove a coordinate and the constrained motion "
                "preserves no symplectic form (Bloch, Nonholonomic Mechanics and Control, "
                "§5.8); the energy function h and the linearization on the manifold are given "
                "instead"
            )
        if found.kind == "velocity":
            integrated = f" to {found.integrated} = const" if found.integrated is not None else ""
            raise AnalysisError(
                f"the velocity constraint {name} integrates{integrated}: write it as a "
                "holonomic constraint (holonomic: ... in a model file, lg.Holonomic in Python) "
                "to get the Hamiltonian in reduced coordinates"
            )


def _reference(system: System, through: Mapping[sp.Symbol, Any] | None) -> System:
    """``system`` with initial values that pick a solution branch: its own, else ``through``
    (numbers at the parameter defaults)."""
    if through is None or all(q in system.initial for q in system.coordinates):
        return system
    values = {p: v for p, v in system.parameters.items() if v is not None}
    initial = dict(system.initial)
    for q in system.coordinates:
        if q in through and q not in initial:
            number = evaluate(to_sympy(through[q]), values)
            if not number.free_symbols:
                initial[q] = float(number)
    return system.replace(initial=initial)


def _closed_form_likely(levels: list[sp.Expr], dependent: list[sp.Symbol]) -> bool:
    """sympy.solve is tried for one dependent coordinate, or for several that enter the
    constraints polynomially (coupled trigonometric equations, as in a four-bar linkage,
    can keep it busy for minutes without an answer)."""
    return len(dependent) <= 1 or all(h.is_polynomial(*dependent) for h in levels)


def reduce_holonomic(
    system: System, manifold: ConstraintManifold, through: Mapping[sp.Symbol, Any] | None = None
) -> tuple[System, dict[sp.Symbol, sp.Expr]]:
    """The System in independent coordinates and the rule q_dep = f(q_ind, t), trying the
    choices of independent coordinates in order; AnalysisError saying why when none works."""
    _refuse_nonholonomic(manifold)
    reference = _reference(system, through)
    size = manifold.configuration_dimension
    reasons: list[str] = []
    levels = list(manifold.position_equations)
    for independent in islice(combinations(system.coordinates, size), CHOICES):
        dependent = [q for q in system.coordinates if q not in independent]
        if not _closed_form_likely(levels, dependent):
            names = ", ".join(q.name for q in dependent)
            reasons.append(
                f"{names} enter the constraints inside functions and together (a closed "
                "chain): no closed-form solution is attempted"
            )
            continue
        try:
            rule = elimination_rule(reference, independent)
            return eliminate(reference, independent), rule
        except (LagrangianError, NotImplementedError, ValueError, TypeError) as error:
            names = ", ".join(q.name for q in independent)
            reasons.append(f"with {names} independent: {error}")
    raise AnalysisError(
        "the holonomic constraints could not be solved for a set of dependent coordinates ("
        + "; ".join(reasons[:3])
        + "); eliminate them with lagrangian.constraints.eliminate(system, independent, "
        "parametrization) and analyze the reduced system"
    )


def reduced_hamiltonian(
    subject: Subject, through: Mapping[sp.Symbol, Any] | None = None
) -> Hamiltonian:
    """H in the reduced coordinates of a holonomically constrained system (see the module
    docstring); AnalysisError for a non-holonomic one, or when elimination fails."""
    return reduced_legendre(subject, through)[0]


def reduced_legendre(
    subject: Subject, through: Mapping[sp.Symbol, Any] | None = None
) -> tuple[Hamiltonian, HamiltonEquations]:
    """H and Hamilton's equations, in the reduced coordinates of a holonomically
    constrained system (as :func:`reduced_hamiltonian`)."""
    eom = equations_of(subject)
    manifold = constraint_manifold(eom)
    if manifold is None:
        found = legendre_transform(eom)
        return found, hamilton_equations(eom, found)
    reduced, rule = reduce_holonomic(eom.system, manifold, through)
    rule = {q: simplify_small(f) for q, f in rule.items()}
    reduced_eom = derive(reduced)
    found = legendre_transform(reduced_eom)
    kept = ", ".join(q.name for q in reduced.coordinates)
    eliminated = ", ".join(f"{q} = {f}" for q, f in rule.items())
    solved = f", the constraints solved as {eliminated}" if eliminated else ""
    legendre = Hamiltonian(
        hamiltonian=simplify_small(found.hamiltonian),
        coordinates=found.coordinates,
        momenta=found.momenta,
        velocities=found.velocities,
        reason=f"in the reduced coordinates ({kept}){solved}; " + found.reason,
        eliminated=frozen(rule),
    )
    return legendre, hamilton_equations(reduced_eom, legendre)


def stable_state(found: Any, values: Mapping[sp.Symbol, Any]) -> dict | None:
    """The coordinates of the first stable equilibrium in ``found`` (free ones at 0) at the
    parameter ``values``, as a reference for picking solution branches; None when there is
    none."""
    stable = [e for e in (found or ()) if e.stable]
    if not stable:
        return None
    return {
        q: 0 if q in stable[0].free else evaluate(to_sympy(v), values)
        for q, v in stable[0].state.items()
    }
