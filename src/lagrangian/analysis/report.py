"""``analyze``: every analysis of a system in one report, robust part by part.

Each part (momenta, cyclic coordinates, energy, Hamiltonian, equilibria, normal modes,
linearization) is computed on its own; a part that cannot be done for this system (a
singular Legendre transform, no stable equilibrium, ...) is recorded in ``failures`` with
its reason instead of stopping the report.  A constrained system is analyzed on its constraint
manifold (:func:`constrained_report`): every part there, plus the Jacobi integral and the
steady motions of constraints that move by a symmetry; an ``about`` state off the constraints
is refused (ConstraintError) unless projected.

>>> import lagrangian as lg
>>> report = analyze(lg.examples.planet())
>>> [c.name for c in report.conserved]
['p_theta', 'h']
>>> report.failure("normal_modes")
'No stable equilibrium to oscillate about (sympy.solve finds no solution of the static equations).'
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import sympy as sp

from lagrangian import limits
from lagrangian.analysis.arguments import (
    Subject,
    Values,
    equations_of,
    numeric_values,
    operating_state,
    substitutions,
)
from lagrangian.analysis.energy import EnergyConservation, energy_conservation
from lagrangian.analysis.equilibria import equilibria
from lagrangian.analysis.hamiltonian import (
    HamiltonEquations,
    Hamiltonian,
    hamilton_equations,
    hamiltonian,
)
from lagrangian.analysis.integrals.constrained import constrained_first_integrals
from lagrangian.analysis.integrals.noether import Symmetry, point_symmetries
from lagrangian.analysis.integrals.search import (
    SEARCH_SECONDS,
    ConservedQuantity,
    FirstIntegralSearch,
    first_integrals,
)
from lagrangian.analysis.linearize import Linearization, linearize
from lagrangian.analysis.manifold.constraint_manifold import (
    constraint_manifold,
    numeric_point,
    require_on_manifold,
)
from lagrangian.analysis.manifold.symmetries import (
    JacobiIntegral,
    jacobi_integral,
    kept_symmetries,
)
from lagrangian.analysis.modes import NormalModes, normal_modes
from lagrangian.analysis.momenta import (
    ConjugateMomenta,
    CyclicCoordinate,
    conjugate_momenta,
    cyclic_coordinates,
)
from lagrangian.analysis.reduced_hamiltonian import reduced_legendre, stable_state
from lagrangian.analysis.rest import Equilibria, first_stable
from lagrangian.analysis.steady_motions import SteadyMotions, steady_motions
from lagrangian.constraints import project_state
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError, LagrangianError, TimeLimitError
from lagrangian.limits import bounded
from lagrangian.size_limits import size_limit as sized_to
from lagrangian.symbolic.probe import is_zero

T = TypeVar("T")


@dataclass(frozen=True)
class Failure:
    """A part of the report that could not be computed for this system, and why."""

    part: str
    reason: str


@dataclass(frozen=True)
class AnalysisReport:
    """Everything :func:`analyze` found; parts that failed are None and listed in
    ``failures``.  ``constraints`` holds the classification of each constraint (as_dict).

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
    constraints: tuple[Any, ...] = ()
    configuration_dimension: int | None = None
    independent_velocities: int | None = None
    freedom: str = ""
    steady_motions: SteadyMotions | None = None
    #: What the search for first integrals beyond cyclic coordinates and h covered.
    searched: tuple[str, ...] = ()

    def failure(self, part: str) -> str | None:
        """Why ``part`` failed, or None when it did not."""
        return next((f.reason for f in self.failures if f.part == part), None)


def conserved_quantities(
    cyclic: Sequence[CyclicCoordinate],
    energy: EnergyConservation | None,
    symmetries: Sequence[Symmetry] = (),
    jacobi: JacobiIntegral | None = None,
    search: FirstIntegralSearch | None = None,
) -> tuple[ConservedQuantity, ...]:
    """The momenta of cyclic coordinates that are conserved (with their conditions), the
    Noether charges of the other point symmetries, h when it is conserved, the Jacobi
    integral of constraints that move by a symmetry, and the independent first integrals of
    the ``search``."""
    kept = [c for c in cyclic if c.conserved]
    found = [
        ConservedQuantity(
            f"p_{c.coordinate.name}", c.momentum, c.reason, c.condition, "cyclic coordinate"
        )
        for c in kept
    ]
    known = [c.momentum for c in kept]
    for symmetry in symmetries:
        if is_zero(symmetry.conserved):
            continue  # a coordinate without inertia: nothing to conserve
        if any(sp.simplify(symmetry.conserved / p).is_number for p in known if p != 0):
            continue  # the momentum of a cyclic coordinate, found again
        found.append(
            ConservedQuantity(
                f"noether_{len(found) + 1}",
                symmetry.conserved,
                f"Noether: L is invariant under the {symmetry.description}",
                origin="point symmetry",
            )
        )
    if energy is not None and energy.conserved:
        found.append(ConservedQuantity("h", energy.energy_function, energy.reason, origin="energy"))
    if jacobi is not None:
        found.append(
            ConservedQuantity("jacobi", jacobi.expression, jacobi.reason, origin="Jacobi integral")
        )
    if search is not None:
        found += search.found
    return tuple(found)


#: The share of the analysis's time left that one part may take: a part still running then
#: is stopped and listed among the failures, and the report goes on with the next part, so
#: that no part whose expressions grow can take the whole time and leave no report.
PART_SHARE = 0.25


def part_limit_message(part: str, seconds: float, left: float) -> str:
    """What the report says of a part stopped at the end of its share of the time."""
    return (
        f"{part} stopped after {seconds:.3g} s, its share ({PART_SHARE:.0%}) of the "
        f"{left:.3g} s the analysis had left: its expressions are too large for the time (the "
        "other parts are reported); give the analysis more time (lagrangian --timeout "
        "SECONDS, analyze(..., time_limit=SECONDS), or $LAGRANGIAN_TIME_LIMIT), or simplify "
        "the model"
    )


class _Attempts:
    """Runs the parts, keeping each failure's reason; each part within its share of the time
    left (:data:`PART_SHARE`)."""

    def __init__(self) -> None:
        self.failures: list[Failure] = []

    def run(self, part: str, compute: Callable[[], T]) -> T | None:
        left = limits.remaining_seconds()
        message = None
        try:
            if left is None:  # no time limit: none for the part either
                return compute()
            limits.check_time()  # the command's time is spent: no part may start
            seconds = max(PART_SHARE * left, 1e-3)
            message = part_limit_message(part, seconds, left)
            with limits.time_limit(seconds, message=message):
                return compute()
        except TimeLimitError as error:
            if message is None or str(error) != message:
                raise  # the command's own limit: no later part may start
            self.failures.append(Failure(part, message))
        except LagrangianError as error:
            self.failures.append(Failure(part, str(error)))
        except Exception as error:  # a bug or a SymPy limitation: report it, keep going
            self.failures.append(Failure(part, f"internal error: {type(error).__name__}: {error}"))
        return None


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
    with sized_to(size_limit):
        return _analyze(
            subject, about, parameters, inputs, project, independent, search_degree, search_seconds
        )


def _analyze(
    subject: Subject,
    about: Values | None,
    parameters: Values | None,
    inputs: Sequence[Any],
    project: bool,
    independent: Sequence[Any] | None,
    search_degree: int,
    search_seconds: float,
) -> AnalysisReport:
    if isinstance(search_degree, bool) or not isinstance(search_degree, int) or search_degree < 0:
        raise AnalysisError(f"search_degree must be a whole number >= 0, not {search_degree!r}")
    eom = equations_of(subject)
    substitutions(eom, parameters)  # wrong names and values are the caller's to fix, at once
    if about is not None:
        operating_state(eom, about)
    if eom.system.constraints:
        return constrained_report(
            eom, about, parameters, inputs, project, independent, search_degree, search_seconds
        )
    attempts = _Attempts()
    run = attempts.run
    cyclic = run("cyclic", lambda: cyclic_coordinates(eom, parameters)) or ()
    symmetries = run("symmetries", lambda: point_symmetries(eom)) or ()
    energy = run("energy", lambda: energy_conservation(eom))
    known = conserved_quantities(cyclic, energy, symmetries)
    search = None
    if search_degree > 0:
        search = run(
            "first_integrals",
            lambda: first_integrals(
                eom, parameters, [c.expression for c in known], search_degree, search_seconds
            ),
        )
    legendre = run("hamiltonian", lambda: hamiltonian(eom))
    canonical = (
        run("hamilton_equations", lambda: hamilton_equations(eom, legendre)) if legendre else None
    )
    found = run("equilibria", lambda: equilibria(eom, parameters))
    modes = None
    if found is not None:
        modes = run(
            "normal_modes", lambda: normal_modes(eom, first_stable(found), parameters=parameters)
        )
    linearization = None
    if about is not None:
        linearization = run("linearization", lambda: linearize(eom, about, inputs, parameters))
    n = len(eom.coordinates)
    return AnalysisReport(
        name=eom.name,
        dof=n,
        coordinates=tuple(eom.coordinates),
        momenta=run("momenta", lambda: conjugate_momenta(eom)),
        cyclic=tuple(cyclic),
        conserved=conserved_quantities(cyclic, energy, symmetries, search=search),
        searched=search.searched if search is not None else (),
        energy=energy,
        hamiltonian=legendre,
        hamilton_equations=canonical,
        equilibria=found,
        normal_modes=modes,
        linearization=linearization,
        failures=tuple(attempts.failures),
        configuration_dimension=n,
        independent_velocities=n,
        freedom=freedom_text(n, n, n),
    )


def _about_on_manifold(
    eom: EquationsOfMotion, about: Values, parameters: Values | None, project: bool
) -> dict[sp.Symbol, Any]:
    """The operating state, checked against the constraints (ConstraintError naming each
    one it misses, with its residual), or moved onto them when ``project``."""
    state = operating_state(eom, about)
    numbers = numeric_values(eom, parameters)
    if not project:
        fix = "pass project=True to move the state onto the constraints (project_state)"
        require_on_manifold(eom, state, numbers, fix)
        return state
    moved = project_state(eom.system, numeric_point(eom, state, numbers))
    return {s: moved[s] for s in (*eom.coordinates, *eom.velocities, eom.time)}


def constrained_report(
    eom: EquationsOfMotion,
    about: Values | None,
    parameters: Values | None,
    inputs: Sequence[Any],
    project: bool,
    independent: Sequence[Any] | None,
    search_degree: int = 2,
    search_seconds: float = SEARCH_SECONDS,
    *,
    time_limit: float | None = None,
) -> AnalysisReport:
    """Every part of :func:`analyze` on the constraint manifold (docs/architecture.md); the
    further first integrals on the reduced system when the holonomic constraints are solved
    in closed form, else on the constrained equations
    (:mod:`lagrangian.analysis.integrals.constrained`)."""
    attempts = _Attempts()
    run = attempts.run
    manifold = constraint_manifold(eom)  # inconsistent constraints: the error goes to the user
    assert manifold is not None  # a System with constraints has a manifold
    state = None if about is None else _about_on_manifold(eom, about, parameters, project)
    cyclic = run("cyclic", lambda: cyclic_coordinates(eom, parameters)) or ()
    symmetries = run("symmetries", lambda: point_symmetries(eom)) or ()
    energy = run("energy", lambda: energy_conservation(eom))
    jacobi = None
    if energy is not None and not energy.conserved:
        jacobi = run("jacobi", lambda: jacobi_integral(eom, energy, symmetries))
    steady = None
    if jacobi is not None:
        steady = run("steady_motions", lambda: steady_motions(eom, parameters, jacobi))
    found = run("equilibria", lambda: equilibria(eom, parameters))
    through = stable_state(eom, found, parameters)
    legendre = run("hamiltonian", lambda: reduced_legendre(eom, through))
    kept = kept_symmetries(symmetries, manifold)
    known = conserved_quantities(cyclic, energy, kept, jacobi)
    search = None
    if search_degree > 0:
        search = run(
            "first_integrals",
            lambda: constrained_first_integrals(
                eom,
                parameters,
                [c.expression for c in known],
                search_degree,
                search_seconds,
                through,
            ),
        )
    modes = None
    if found is not None:
        modes = run(
            "normal_modes", lambda: normal_modes(eom, first_stable(found), parameters=parameters)
        )
    linearization = None
    if state is not None:
        linearization = run(
            "linearization",
            lambda: linearize(eom, state, inputs, parameters, independent=independent),
        )
    dimension, velocities = manifold.configuration_dimension, manifold.independent_velocities
    return AnalysisReport(
        name=eom.name,
        dof=velocities,
        coordinates=tuple(eom.coordinates),
        momenta=run("momenta", lambda: conjugate_momenta(eom)),
        cyclic=tuple(cyclic),
        conserved=conserved_quantities(cyclic, energy, kept, jacobi, search),
        searched=search.searched if search is not None else (),
        energy=energy,
        hamiltonian=legendre[0] if legendre else None,
        hamilton_equations=legendre[1] if legendre else None,
        equilibria=found,
        normal_modes=modes,
        linearization=linearization,
        failures=tuple(attempts.failures),
        constraints=tuple(c.as_dict() for c in manifold.classification.constraints),
        configuration_dimension=dimension,
        independent_velocities=velocities,
        freedom=freedom_text(len(eom.coordinates), dimension, velocities)
        + "".join(f"; left out of this analysis: {why}" for why in manifold.left_out),
        steady_motions=steady,
    )
