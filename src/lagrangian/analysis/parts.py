"""The parts of an analysis report, each with its variant for a system without constraints
and its variant on the constraint manifold (:mod:`lagrangian.analysis.manifold`).

:data:`PARTS` is the table :func:`lagrangian.analysis.analyze` runs, in order; a part reads
the request (its :class:`~lagrangian.analysis.evaluation.EvaluationContext`, the constraint
manifold, the operating state, the search's bounds) and the parts found before it, and
returns its value (None: it does not apply to this system).  A part whose ``needs`` were not
found is not run.

    part                 free                          on the constraint manifold
    cyclic               p_j, dL/dq_j = 0              the same, constraint forces along q_j
    symmetries           Noether point symmetries      the same
    energy               h, dh/dt                      + the power of moving constraints
    jacobi               -                             J = h - c p_xi (constraints moving by xi)
    steady_motions       -                             critical points of V_eff
    equilibria           forcing(q, 0) = 0             forcing + A^T lambda = 0, h(q) = 0
    hamiltonian          Legendre transform of L       in reduced coordinates
    hamilton_equations   dH/dp, -dH/dq                 of the reduced H
    first_integrals      search on L                   on the reduced or constrained system
    normal_modes         K v = omega^2 M v             in the independent coordinates
    linearization        A, B about a state            with the dependent ones eliminated
    momenta              p_j = dL/dq_dot_j             the same
    constraint_forces    -                             lambda solved for the state

>>> [part.name for part in PARTS if part.free is None]
['jacobi', 'steady_motions', 'constraint_forces']
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis.conserved import conserved_quantities
from lagrangian.analysis.energy import energy_at_values
from lagrangian.analysis.equilibria import equilibria_at_values
from lagrangian.analysis.evaluation import EvaluationContext
from lagrangian.analysis.hamiltonian import HamiltonEquations, Hamiltonian
from lagrangian.analysis.hamiltonian import hamilton_equations as canonical_equations
from lagrangian.analysis.hamiltonian import hamiltonian as legendre_transform
from lagrangian.analysis.integrals.constrained import constrained_first_integrals
from lagrangian.analysis.integrals.noether import Symmetry, point_symmetries
from lagrangian.analysis.integrals.search import SEARCH_SECONDS, first_integrals
from lagrangian.analysis.linearize import linearization_at_values
from lagrangian.analysis.manifold.constraint_forces import constraint_forces
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold
from lagrangian.analysis.manifold.symmetries import jacobi_integral, kept_symmetries
from lagrangian.analysis.modes import modes_at_values
from lagrangian.analysis.momenta import conjugate_momenta, cyclic_at_values
from lagrangian.analysis.reduced_hamiltonian import reduced_legendre, stable_state
from lagrangian.analysis.rest import first_stable
from lagrangian.analysis.steady_motions import steady_motions_at_values
from lagrangian.derivation import EquationsOfMotion

#: H and Hamilton's equations: of L, or in reduced coordinates on the manifold (where both
#: come from one elimination).
Legendre = tuple[Hamiltonian, HamiltonEquations | None]


@dataclass(frozen=True)
class AnalysisRequest:
    """What one analysis is asked: the parameter values (``context``), the constraint
    manifold (None without constraints), the operating state to linearize about (checked on
    the manifold, or None), the parameters taken as inputs, the coordinates the
    linearization keeps, and the degree and seconds of the search for first integrals."""

    context: EvaluationContext
    manifold: ConstraintManifold | None
    state: Mapping[sp.Symbol, sp.Expr] | None
    inputs: tuple[Any, ...] = ()
    independent: tuple[Any, ...] | None = None
    search_degree: int = 2
    search_seconds: float = SEARCH_SECONDS

    @property
    def eom(self) -> EquationsOfMotion:
        return self.context.eom


#: The values of the parts found so far, by part name (None: failed or not applicable).
Found = Mapping[str, Any]
Variant = Callable[[AnalysisRequest, Found], Any]


@dataclass(frozen=True)
class Part:
    """One part of the report: its name (the key of its failure), its variant for a system
    without constraints and on the constraint manifold (None where it does not apply), and
    the parts it needs found first."""

    name: str
    free: Variant | None
    on_manifold: Variant | None
    needs: tuple[str, ...] = ()

    def variant(self, request: AnalysisRequest, found: Found) -> Variant | None:
        """The variant to run for ``request``; None when it does not apply or a part it
        needs was not found."""
        if any(found.get(name) is None for name in self.needs):
            return None
        return self.free if request.manifold is None else self.on_manifold


def symmetries_kept(request: AnalysisRequest, found: Found) -> tuple[Symmetry, ...]:
    """The point symmetries whose charges the constraints keep (all, without constraints)."""
    return kept_symmetries(found.get("symmetries") or (), request.manifold)


def _cyclic(request: AnalysisRequest, found: Found) -> Any:
    return cyclic_at_values(request.context)


def _symmetries(request: AnalysisRequest, found: Found) -> Any:
    return point_symmetries(request.eom)


def _energy(request: AnalysisRequest, found: Found) -> Any:
    return energy_at_values(request.context)


def _jacobi(request: AnalysisRequest, found: Found) -> Any:
    """The Jacobi integral, when h itself is not conserved."""
    energy = found["energy"]
    if energy.conserved:
        return None
    return jacobi_integral(request.eom, energy, found.get("symmetries") or ())


def _steady(request: AnalysisRequest, found: Found) -> Any:
    return steady_motions_at_values(request.context, found["jacobi"])


def _equilibria(request: AnalysisRequest, found: Found) -> Any:
    return equilibria_at_values(request.context)


def _through(request: AnalysisRequest, found: Found) -> dict | None:
    """The first stable equilibrium, picking the solution branch of the constraints."""
    return stable_state(found.get("equilibria"), request.context.values)


def _legendre(request: AnalysisRequest, found: Found) -> Legendre:
    return legendre_transform(request.eom), None


def _reduced_legendre(request: AnalysisRequest, found: Found) -> Legendre:
    return reduced_legendre(request.eom, _through(request, found))


def _canonical(request: AnalysisRequest, found: Found) -> Any:
    return canonical_equations(request.eom, found["hamiltonian"][0])


def _reduced_canonical(request: AnalysisRequest, found: Found) -> Any:
    return found["hamiltonian"][1]


def _known(found: Found, symmetries: tuple[Symmetry, ...]) -> list[sp.Expr]:
    """The conserved quantities found before the search, for it to stay independent of."""
    known = conserved_quantities(
        found.get("cyclic") or (), found.get("energy"), symmetries, found.get("jacobi")
    )
    return [c.expression for c in known]


def _search(request: AnalysisRequest, found: Found) -> Any:
    if request.search_degree <= 0:
        return None
    known = _known(found, symmetries_kept(request, found))
    return first_integrals(
        request.eom,
        request.context.parameters,
        known,
        request.search_degree,
        request.search_seconds,
    )


def _constrained_search(request: AnalysisRequest, found: Found) -> Any:
    if request.search_degree <= 0:
        return None
    return constrained_first_integrals(
        request.eom,
        request.context.parameters,
        _known(found, symmetries_kept(request, found)),
        request.search_degree,
        request.search_seconds,
        _through(request, found),
    )


def _modes(request: AnalysisRequest, found: Found) -> Any:
    about = first_stable(found["equilibria"])
    return modes_at_values(request.context, about)


def _linearization(request: AnalysisRequest, found: Found) -> Any:
    if request.state is None:
        return None
    return linearization_at_values(request.context, request.state, request.inputs)


def _manifold_linearization(request: AnalysisRequest, found: Found) -> Any:
    if request.state is None:
        return None
    return linearization_at_values(
        request.context, request.state, request.inputs, independent=request.independent
    )


def _constraint_forces(request: AnalysisRequest, found: Found) -> Any:
    assert request.manifold is not None  # the part runs on the manifold only
    return constraint_forces(request.eom, request.manifold)


def _momenta(request: AnalysisRequest, found: Found) -> Any:
    return conjugate_momenta(request.eom)


#: The parts in the order they run: the equilibria before the Hamiltonian and the search
#: (on a manifold both pick the constraints' solution branch through a stable equilibrium).
PARTS: tuple[Part, ...] = (
    Part("cyclic", _cyclic, _cyclic),
    Part("symmetries", _symmetries, _symmetries),
    Part("energy", _energy, _energy),
    Part("jacobi", None, _jacobi, needs=("energy",)),
    Part("steady_motions", None, _steady, needs=("jacobi",)),
    Part("equilibria", _equilibria, _equilibria),
    Part("hamiltonian", _legendre, _reduced_legendre),
    Part("hamilton_equations", _canonical, _reduced_canonical, needs=("hamiltonian",)),
    Part("first_integrals", _search, _constrained_search),
    Part("normal_modes", _modes, _modes, needs=("equilibria",)),
    Part("linearization", _linearization, _manifold_linearization),
    Part("momenta", _momenta, _momenta),
    Part("constraint_forces", None, _constraint_forces),
)
