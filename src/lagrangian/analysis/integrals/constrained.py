"""First integrals of a constrained system: on the reduced system when its holonomic
constraints can be solved for some coordinates in closed form, else on the constrained
equations themselves.

Solving h(q, t) = 0 for the dependent coordinates, q_dep = f(q_ind, t)
(:func:`lagrangian.analysis.reduced_hamiltonian.reduce_holonomic`), gives a free system in
the independent coordinates whose motions are the constrained ones (Goldstein §1.3: the
constraint forces do no virtual work); its first integrals, found by
:func:`~lagrangian.analysis.integrals.search.first_integrals`, are those of the constrained
motion, written in the independent coordinates.  The quantities already known (the momenta,
charges and energy of the full system) are rewritten there too, so that only independent ones
are added.  This is done when the solution is rational in the independent coordinates: a
radical (z = sqrt(R**2 - x**2 - y**2) of a sphere) is defined on part of the configurations
only, where random samples would mostly fall outside.

Otherwise, and for non-holonomic constraints (which remove no coordinate: Bloch,
*Nonholonomic Mechanics and Control*, §5.8), the integrals are sought on the constrained
equations in the system's own coordinates (:mod:`~lagrangian.analysis.manifold.integrals`:
dI/dt = 0 on the multiplier form at states on the constraints).  Each line of ``searched``
says which of the two was done, and why.

>>> import lagrangian as lg
>>> search = constrained_first_integrals(lg.examples.cylinder_on_incline())
>>> search.searched[0]
'searched on the reduced system in x (phi = x/r)'
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute
from lagrangian.analysis.integrals.search import (
    SEARCH_SECONDS,
    FirstIntegralSearch,
    first_integrals,
)
from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
from lagrangian.analysis.reduced_hamiltonian import reduce_holonomic
from lagrangian.analysis.simplification import simplify_small
from lagrangian.constraints import project_state
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import LagrangianError
from lagrangian.model import System, t
from lagrangian.symbolic.symbols import time_derivative, velocity


def constrained_first_integrals(
    subject: Subject,
    parameters: Values | None = None,
    known: Sequence[sp.Expr] = (),
    degree: int = 2,
    seconds: float = SEARCH_SECONDS,
    through: Mapping[sp.Symbol, Any] | None = None,
) -> FirstIntegralSearch:
    """The first integrals of the reduced system of a holonomically constrained ``subject``
    independent of ``known`` (module docstring); ``through`` a state that picks the solution
    branch when the constraints have several (else the initial values)."""
    eom = equations_of(subject)
    manifold = constraint_manifold(eom)
    if manifold is None:
        return first_integrals(eom, parameters, known, degree, seconds)
    if not manifold.size:  # every constraint unilateral, taken as released
        search = first_integrals(eom, parameters, known, degree, seconds)
        free = "searched without the constraints, away from contact: " + "; ".join(
            manifold.left_out
        )
        away = "; while no unilateral constraint is in contact"
        found = tuple(replace(c, reason=c.reason + away) for c in search.found)
        return FirstIntegralSearch(found, (free, *search.searched))
    several = len(manifold.nonholonomic) > 1
    why = (
        f"the constraint{'s' if several else ''} {', '.join(manifold.nonholonomic)} "
        f"{'are' if several else 'is'} non-holonomic"
    )
    if not manifold.nonholonomic:
        try:
            reduced, rule = reduce_holonomic(eom.system, manifold, through or _generic_point(eom))
        except LagrangianError as error:
            why = f"the constraints were not solved ({error})"
        else:
            kept = tuple(reduced.coordinates)
            radicals = [f for f in rule.values() if not f.is_rational_function(*kept, t)]
            why = (
                f"the solution {radicals[0]} is defined on part of the configurations only"
                if radicals
                else "the reduced system keeps constraints"
            )
            if not radicals and not reduced.constraints:
                return _reduced_search(reduced, rule, parameters, known, degree, seconds)
    search = first_integrals(eom, parameters, known, degree, seconds)
    names = ", ".join(q.name for q in eom.coordinates)
    how = f"searched on the constrained equations in {names}, at states on the constraints"
    return replace(search, searched=(f"{how} ({why})", *search.searched))


def _reduced_search(
    reduced: System,
    rule: dict[sp.Symbol, sp.Expr],
    parameters: Values | None,
    known: Sequence[sp.Expr],
    degree: int,
    seconds: float,
) -> FirstIntegralSearch:
    """The search on the reduced system, the known quantities rewritten there."""
    rule = {q: simplify_small(f) for q, f in rule.items()}
    kept = tuple(reduced.coordinates)
    moved: dict[sp.Symbol, sp.Expr] = dict(rule)
    moved.update({velocity(q): time_derivative(f, kept) for q, f in rule.items()})
    search = first_integrals(
        reduced, parameters, [substitute(k, moved) for k in known], degree, seconds
    )
    names = ", ".join(q.name for q in kept)
    solved = ", ".join(f"{q} = {f}" for q, f in rule.items())
    note = f"on the reduced system in {names} ({solved})"
    return FirstIntegralSearch(
        tuple(replace(c, reason=f"{c.reason}; {note}") for c in search.found),
        (f"searched {note}", *search.searched),
    )


def _generic_point(eom: EquationsOfMotion) -> dict[sp.Symbol, float] | None:
    """A point on the constraints near no special configuration, to pick a solution branch
    when there is no other reference (a particle on a sphere: the lower or upper half)."""
    start = {q.name: 0.3 + 0.2 * i for i, q in enumerate(eom.coordinates)}
    try:
        return project_state(eom.system, start)
    except (LagrangianError, ArithmeticError, ValueError):
        return None
