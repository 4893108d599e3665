"""The analysis layer: what the equations of motion mean (docs/architecture.md;
Goldstein, Classical Mechanics, 3rd ed., ch. 2 and 8).

Conjugate momenta and cyclic coordinates, the energy function and when it is conserved or
equals T + V, the Hamiltonian and Hamilton's equations, equilibria and their stability,
linearization about any state, normal modes, and equivalent descriptions (L + dF/dt, point
transformations).  A constrained system is analyzed on its constraint manifold
(:mod:`lagrangian.analysis.manifold.constraint_manifold`): equilibria of the multiplier form,
linearization with
the dependent coordinates and speeds eliminated, the Hamiltonian in reduced coordinates, the
Jacobi integral and steady motions of constraints that move by a symmetry.  Every function
takes a System or its EquationsOfMotion and returns an immutable value; :func:`analyze`
bundles them.

>>> import lagrangian as lg
>>> from lagrangian.analysis import analyze
>>> analyze(lg.examples.simple_pendulum()).normal_modes.frequencies
(sqrt(g)/sqrt(l),)
"""

from lagrangian.analysis.energy import EnergyConservation, energy_conservation, energy_function
from lagrangian.analysis.equilibria import equilibria
from lagrangian.analysis.equivalence import (
    TotalDerivativeEquivalence,
    equivalent_under_total_derivative,
    point_transformation,
)
from lagrangian.analysis.hamiltonian import (
    HamiltonEquations,
    Hamiltonian,
    hamilton_equations,
    hamiltonian,
)
from lagrangian.analysis.integrals.noether import Symmetry, point_symmetries
from lagrangian.analysis.linearize import Linearization, linearize
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, constraint_manifold
from lagrangian.analysis.manifold.symmetries import JacobiIntegral, jacobi_integral
from lagrangian.analysis.modes import NormalModes, normal_modes
from lagrangian.analysis.momenta import (
    ConjugateMomenta,
    CyclicCoordinate,
    conjugate_momenta,
    cyclic_coordinates,
)
from lagrangian.analysis.reduced_hamiltonian import reduced_hamiltonian
from lagrangian.analysis.report import (
    AnalysisReport,
    ConservedQuantity,
    Failure,
    analyze,
    conserved_quantities,
)
from lagrangian.analysis.rest import Equilibria, Equilibrium
from lagrangian.analysis.steady_motions import SteadyMotions, steady_motions

__all__ = [
    "AnalysisReport",
    "ConjugateMomenta",
    "ConservedQuantity",
    "ConstraintManifold",
    "CyclicCoordinate",
    "EnergyConservation",
    "Equilibria",
    "Equilibrium",
    "Failure",
    "HamiltonEquations",
    "Hamiltonian",
    "JacobiIntegral",
    "Linearization",
    "NormalModes",
    "SteadyMotions",
    "Symmetry",
    "TotalDerivativeEquivalence",
    "analyze",
    "conjugate_momenta",
    "conserved_quantities",
    "constraint_manifold",
    "cyclic_coordinates",
    "energy_conservation",
    "energy_function",
    "equilibria",
    "equivalent_under_total_derivative",
    "hamilton_equations",
    "hamiltonian",
    "jacobi_integral",
    "linearize",
    "normal_modes",
    "point_symmetries",
    "point_transformation",
    "reduced_hamiltonian",
    "steady_motions",
]
