"""``analyze``: every analysis of a system in one report, robust part by part.

One orchestrator runs the table of parts (:data:`lagrangian.analysis.parts.PARTS`: momenta,
cyclic coordinates, energy, Hamiltonian, equilibria, normal modes, linearization, ...), each
in its variant for a free system or on the constraint manifold, all with one evaluation
context (:mod:`lagrangian.analysis.evaluation`): the parameter values every statement is
made at.  A part that cannot be done for this system (a singular Legendre transform, no
stable equilibrium, ...) is recorded in ``failures`` with its reason instead of stopping the
report (:mod:`lagrangian.analysis.attempts`).  On a constrained system an ``about`` state
off the constraints is refused (ConstraintError) unless projected.

>>> import lagrangian as lg
>>> report = analyze(lg.examples.planet())
>>> [c.name for c in report.conserved]
['p_theta', 'h', 'I_1']
>>> report.failure("normal_modes")
'No stable equilibrium to oscillate about (sympy.solve finds no solution of the static equations).'
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, operating_state
from lagrangian.analysis.attempts import Failure, PartRunner
from lagrangian.analysis.conserved import conserved_quantities
from lagrangian.analysis.energy import EnergyConservation
from lagrangian.analysis.evaluation import EvaluationContext, evaluation_context
from lagrangian.analysis.hamiltonian import HamiltonEquations, Hamiltonian
from lagrangian.analysis.integrals.search import SEARCH_SECONDS, ConservedQuantity
from lagrangian.analysis.linearize import Linearization
from lagrangian.analysis.manifold.constraint_forces import ConstraintForces
from lagrangian.analysis.manifold.constraint_manifold import (
    ConstraintManifold,
    constraint_manifold,
    numeric_point,
    require_on_manifold,
)
from lagrangian.analysis.modes import NormalModes
from lagrangian.analysis.momenta import ConjugateMomenta, CyclicCoordinate
from lagrangian.analysis.names import OutputNames
from lagrangian.analysis.parts import PARTS, AnalysisRequest, Found, symmetries_kept
from lagrangian.analysis.rest import Equilibria
from lagrangian.analysis.steady_motions import SteadyMotions
from lagrangian.constraints import ConstraintClass, project_state
from lagrangian.errors import AnalysisError, Fix, Setting
from lagrangian.limits import bounded
from lagrangian.size_limits import size_limit as sized_to

__all__ = ["AnalysisReport", "ConservedQuantity", "Failure", "analyze", "conserved_quantities"]


@dataclass(frozen=True)
class AnalysisReport:
    """Everything :func:`analyze` found; parts that failed are None and listed in
    ``failures``.  ``constraints`` holds the classification of each constraint.

    ``dof`` is the number of independent velocities (n minus every equality constraint, as
    Greenwood and Bloch count degrees of freedom), ``configuration_dimension`` n minus the
    holonomic ones; they differ for a non-holonomic system, and ``freedom`` says so."""

    name: str
    dof: int
    coordinates: tuple[sp.Symbol, ...]
    momenta: ConjugateMomenta | None
    cyclic: tuple[CyclicCoordinate, ...]
    conserved: tuple[ConservedQuantity, ...]
    energy: EnergyConservation | None
    hamiltonian: Hamiltonian | None
    hamilton_equations: HamiltonEquations | None
    equilibria: Equilibria | None
    normal_modes: NormalModes | None
    linearization: Linearization | None
    failures: tuple[Failure, ...]
    constraints: tuple[ConstraintClass, ...] = ()
    configuration_dimension: int | None = None
    independent_velocities: int | None = None
    freedom: str = ""
    steady_motions: SteadyMotions | None = None
    #: What the search for first integrals beyond cyclic coordinates and h covered.
    searched: tuple[str, ...] = ()
    #: Each multiplier solved for the state (constrained systems only).
    constraint_forces: ConstraintForces | None = None
    #: The names the report introduces (h, H, omega, p_q, ...), none a name of the model.
    names: OutputNames = OutputNames()
    #: Each parameter and the value every statement is decided at (None: none given), in
    #: the order of the equations' parameters.
    parameter_values: tuple[tuple[sp.Symbol, sp.Expr | None], ...] = ()

    def failure(self, part: str) -> str | None:
        """Why ``part`` failed, or None when it did not."""
        return next((f.reason for f in self.failures if f.part == part), None)


def _count(number: int, noun: str) -> str:
    """``1 non-holonomic constraint leaves``, ``2 ... constraints leave``."""
    return f"{number} {noun}{'' if number == 1 else 's'} leave{'s' if number == 1 else ''}"


def freedom_text(n: int, configuration: int, velocities: int) -> str:
    """How many coordinates, configurations and velocities are free, and which is the dof."""
    text = f"{n} coordinate{'' if n == 1 else 's'}"
    if configuration == velocities == n:
        return f"{text}, no constraint: dof = {n}"
    if configuration < n:
        text += (
            f"; {_count(n - configuration, 'independent holonomic constraint')} a "
            f"configuration manifold of dimension {configuration} (configuration_dimension)"
        )
    if velocities == configuration:
        return text + f"; dof = {velocities}"
    return text + (
        f"; {_count(configuration - velocities, 'non-holonomic constraint')} "
        f"{velocities} independent velocities: dof = {velocities}, the independent velocities "
        f"(Greenwood, Bloch), fewer than the {configuration} coordinates needed to say where "
        "the system is (non-holonomic constraints restrict how it moves, not where it can go)"
    )


@bounded("analyze")
def analyze(
    subject: Subject,
    about: Values | None = None,
    parameters: Values | None = None,
    inputs: Sequence[Any] = (),
    project: bool = False,
    independent: Sequence[Any] | None = None,
    search_degree: int = 2,
    search_seconds: float = SEARCH_SECONDS,
    *,
    time_limit: float | None = None,
    size_limit: float | None = None,
) -> AnalysisReport:
    """Momenta, cyclic coordinates, conserved quantities, energy function, Hamiltonian and
    Hamilton's equations, equilibria, normal modes, and (with ``about``) the linearization;
    on the constraint manifold for a constrained system.

    ``parameters`` are substitutions (numbers or expressions) applied first; ``about`` is a
    state (coordinate and ``NAME_dot`` values, the rest 0); ``inputs`` are parameters taken
    as inputs u of the linearization.  On a constrained system ``about`` must satisfy the
    constraints (ConstraintError names each one it misses) unless ``project``, which moves
    it onto them first; ``independent`` names the coordinates and velocities the
    linearization keeps.  ``search_degree`` bounds the degree of the functions in which
    further first integrals are sought (0: no search), ``search_seconds`` its time
    (:mod:`lagrangian.analysis.integrals.search`).  ``time_limit`` bounds the whole analysis
    in seconds (TimeLimitError; default ``$LAGRANGIAN_TIME_LIMIT`` or
    :data:`lagrangian.limits.DEFAULT_SECONDS`); each part may take its share of the time
    left (:data:`PART_SHARE`), past which it is listed among the ``failures``.  ``size_limit``
    bounds the operations of each expression derived and analyzed (default
    ``$LAGRANGIAN_SIZE_LIMIT`` or :data:`lagrangian.size_limits.DEFAULT_OPERATIONS`): a part
    whose expression would pass it is listed among the ``failures``, naming the expression.
    """
    if isinstance(search_degree, bool) or not isinstance(search_degree, int) or search_degree < 0:
        raise AnalysisError(f"search_degree must be a whole number >= 0, not {search_degree!r}")
    with sized_to(size_limit):
        eom = equations_of(subject)
        # wrong names and values are the caller's to fix, at once
        context = evaluation_context(eom, parameters)
        state = None if about is None else operating_state(eom, about)
        # inconsistent constraints: the error goes to the user
        manifold = constraint_manifold(eom)
        if manifold is not None and about is not None:
            state = _about_on_manifold(context, about, project)
        request = AnalysisRequest(
            context,
            manifold,
            state,
            tuple(inputs),
            None if independent is None else tuple(independent),
            search_degree,
            search_seconds,
        )
        return analysis_report(request)


def analysis_report(request: AnalysisRequest) -> AnalysisReport:
    """Every part of :data:`~lagrangian.analysis.parts.PARTS` in its variant for
    ``request`` (free, or on the constraint manifold), in order, each failure recorded,
    gathered into the report."""
    runner = PartRunner()
    found: dict[str, Any] = {}
    for part in PARTS:
        variant = part.variant(request, found)
        found[part.name] = None
        if variant is not None:
            found[part.name] = runner.run(part.name, partial(variant, request, found))
    return _gathered(request, found, tuple(runner.failures))


def _freedom(request: AnalysisRequest) -> tuple[int, int, str]:
    """(configuration dimension, independent velocities, the count explained)."""
    n, manifold = len(request.eom.coordinates), request.manifold
    if manifold is None:
        return n, n, freedom_text(n, n, n)
    dimension, velocities = manifold.configuration_dimension, manifold.independent_velocities
    left_out = "".join(f"; left out of this analysis: {why}" for why in manifold.left_out)
    return dimension, velocities, freedom_text(n, dimension, velocities) + left_out


def _constraints(manifold: ConstraintManifold | None) -> tuple[ConstraintClass, ...]:
    return () if manifold is None else tuple(manifold.classification.constraints)


def _gathered(
    request: AnalysisRequest, found: Found, failures: tuple[Failure, ...]
) -> AnalysisReport:
    """The report of the parts ``found``."""
    eom, legendre, search = request.eom, found["hamiltonian"], found["first_integrals"]
    dimension, velocities, freedom = _freedom(request)
    cyclic = tuple(found["cyclic"] or ())
    names = OutputNames.of(eom)
    conserved = conserved_quantities(
        cyclic, found["energy"], symmetries_kept(request, found), found["jacobi"], search, names
    )
    return AnalysisReport(
        name=eom.name,
        dof=velocities,
        coordinates=tuple(eom.coordinates),
        momenta=found["momenta"],
        cyclic=cyclic,
        conserved=conserved,
        searched=search.searched if search is not None else (),
        energy=found["energy"],
        hamiltonian=None if legendre is None else legendre[0],
        hamilton_equations=found["hamilton_equations"],
        equilibria=found["equilibria"],
        normal_modes=found["normal_modes"],
        linearization=found["linearization"],
        failures=failures,
        constraints=_constraints(request.manifold),
        configuration_dimension=dimension,
        independent_velocities=velocities,
        freedom=freedom,
        steady_motions=found["steady_motions"],
        names=names,
        constraint_forces=found["constraint_forces"],
        parameter_values=tuple((p, request.context.values.get(p)) for p in eom.parameters),
    )


def _about_on_manifold(
    context: EvaluationContext, about: Values, project: bool
) -> dict[sp.Symbol, Any]:
    """The operating state, checked against the constraints (ConstraintError naming each
    one it misses, with its residual), or moved onto them when ``project``."""
    eom, numbers = context.eom, context.values
    state = operating_state(eom, about)
    if not project:
        fix = Fix("pass {0} to move the state onto the constraints", (Setting("project", True),))
        require_on_manifold(eom, state, numbers, fix)
        return state
    moved = project_state(eom.system, numeric_point(eom, state, numbers))
    return {s: moved[s] for s in (*eom.coordinates, *eom.velocities, eom.time)}
