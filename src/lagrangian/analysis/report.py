"""``analyze``: every analysis of a system in one report, robust part by part.

Each part (momenta, cyclic coordinates, energy, Hamiltonian, equilibria, normal modes,
linearization) is computed on its own; a part that cannot be done for this system (a
singular Legendre transform, no stable equilibrium, ...) is recorded in ``failures`` with
its reason instead of stopping the report.

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

from lagrangian.analysis.arguments import Subject, Values, equations_of
from lagrangian.analysis.energy import EnergyConservation, energy_conservation
from lagrangian.analysis.equilibria import Equilibria, equilibria
from lagrangian.analysis.hamiltonian import (
    HamiltonEquations,
    Hamiltonian,
    hamilton_equations,
    hamiltonian,
)
from lagrangian.analysis.linearize import Linearization, linearize
from lagrangian.analysis.modes import NormalModes, first_stable, normal_modes
from lagrangian.analysis.momenta import (
    ConjugateMomenta,
    CyclicCoordinate,
    conjugate_momenta,
    cyclic_coordinates,
)
from lagrangian.analysis.noether import Symmetry, point_symmetries
from lagrangian.constraints import classify
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import LagrangianError
from lagrangian.model import System

T = TypeVar("T")


@dataclass(frozen=True)
class ConservedQuantity:
    """A constant of the motion: its name (``p_phi``, ``h``), expression and why."""

    name: str
    expression: sp.Expr
    reason: str


@dataclass(frozen=True)
class Failure:
    """A part of the report that could not be computed for this system, and why."""

    part: str
    reason: str


@dataclass(frozen=True)
class AnalysisReport:
    """Everything :func:`analyze` found; parts that failed are None and listed in
    ``failures``.  ``constraints`` holds the classification of each constraint (as_dict)."""

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

    def failure(self, part: str) -> str | None:
        """Why ``part`` failed, or None when it did not."""
        return next((f.reason for f in self.failures if f.part == part), None)


def conserved_quantities(
    cyclic: Sequence[CyclicCoordinate],
    energy: EnergyConservation | None,
    symmetries: Sequence[Symmetry] = (),
) -> tuple[ConservedQuantity, ...]:
    """The momenta of cyclic coordinates, the Noether charges of the other point symmetries,
    and h when it is conserved."""
    found = [ConservedQuantity(f"p_{c.coordinate.name}", c.momentum, c.reason) for c in cyclic]
    known = [c.momentum for c in cyclic]
    for symmetry in symmetries:
        if any(sp.simplify(symmetry.conserved / p).is_number for p in known if p != 0):
            continue  # the momentum of a cyclic coordinate, found again
        found.append(
            ConservedQuantity(
                f"noether_{len(found) + 1}",
                symmetry.conserved,
                f"Noether: L is invariant under the {symmetry.description}",
            )
        )
    if energy is not None and energy.conserved:
        found.append(ConservedQuantity("h", energy.energy_function, energy.reason))
    return tuple(found)


class _Attempts:
    """Runs the parts, keeping each failure's reason."""

    def __init__(self) -> None:
        self.failures: list[Failure] = []

    def run(self, part: str, compute: Callable[[], T]) -> T | None:
        try:
            return compute()
        except LagrangianError as error:
            self.failures.append(Failure(part, str(error)))
        except Exception as error:  # a bug or a SymPy limitation: report it, keep going
            self.failures.append(Failure(part, f"internal error: {type(error).__name__}: {error}"))
        return None


CONSTRAINED = (
    "not yet computed for a constrained system; eliminate the holonomic constraints first "
    "(lagrangian.constraints.eliminate) to analyze the reduced system"
)


def _constrained_report(system: System, eom: EquationsOfMotion) -> AnalysisReport:
    """Classification, degrees of freedom and momenta; the parts that would ignore the
    constraints are reported as not computed (never silently wrong)."""
    attempts = _Attempts()
    report = attempts.run("constraints", lambda: classify(system))
    for part in ("energy", "hamiltonian", "equilibria", "normal_modes", "linearization"):
        attempts.failures.append(Failure(part, CONSTRAINED))
    return AnalysisReport(
        name=eom.name,
        dof=report.dof if report is not None else len(eom.coordinates),
        coordinates=tuple(eom.coordinates),
        momenta=attempts.run("momenta", lambda: conjugate_momenta(eom)),
        cyclic=(),
        conserved=(),
        energy=None,
        hamiltonian=None,
        hamilton_equations=None,
        equilibria=None,
        normal_modes=None,
        linearization=None,
        failures=tuple(attempts.failures),
        constraints=tuple(c.as_dict() for c in report.constraints) if report else (),
    )


def analyze(
    subject: Subject,
    about: Values | None = None,
    parameters: Values | None = None,
    inputs: Sequence[Any] = (),
) -> AnalysisReport:
    """Momenta, cyclic coordinates, conserved quantities, energy function, Hamiltonian and
    Hamilton's equations, equilibria, normal modes, and (with ``about``) the linearization.

    ``parameters`` are substitutions (numbers or expressions) applied first; ``about`` is a
    state (coordinate and ``NAME_dot`` values, the rest 0); ``inputs`` are parameters taken
    as inputs u of the linearization.
    """
    eom = equations_of(subject)
    if eom.system.constraints:
        return _constrained_report(eom.system, eom)
    attempts = _Attempts()
    run = attempts.run
    cyclic = run("cyclic", lambda: cyclic_coordinates(eom)) or ()
    symmetries = run("symmetries", lambda: point_symmetries(eom)) or ()
    energy = run("energy", lambda: energy_conservation(eom))
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
    return AnalysisReport(
        name=eom.name,
        dof=len(eom.coordinates),
        coordinates=tuple(eom.coordinates),
        momenta=run("momenta", lambda: conjugate_momenta(eom)),
        cyclic=tuple(cyclic),
        conserved=conserved_quantities(cyclic, energy, symmetries),
        energy=energy,
        hamiltonian=legendre,
        hamilton_equations=canonical,
        equilibria=found,
        normal_modes=modes,
        linearization=linearization,
        failures=tuple(attempts.failures),
    )
