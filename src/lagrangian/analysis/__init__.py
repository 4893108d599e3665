"""The analysis layer: what the equations of motion mean (docs/architecture.md, seed notes 000
and 002).

Conjugate momenta and cyclic coordinates, the energy function and when it is conserved or
equals T + V, the Hamiltonian and Hamilton's equations, equilibria and their stability,
linearization about any state, normal modes, and equivalent descriptions (L + dF/dt, point
transformations).  Every function takes a System or its EquationsOfMotion and returns an
immutable value; :func:`analyze` bundles them.

>>> import lagrangian as lg
>>> from lagrangian.analysis import analyze
>>> analyze(lg.examples.simple_pendulum()).normal_modes.frequencies
(sqrt(g)/sqrt(l),)
"""

from lagrangian.analysis.energy import EnergyConservation, energy_conservation, energy_function
from lagrangian.analysis.equilibria import Equilibria, Equilibrium, equilibria
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
from lagrangian.analysis.linearize import Linearization, linearize
from lagrangian.analysis.modes import NormalModes, normal_modes
from lagrangian.analysis.momenta import (
    ConjugateMomenta,
    CyclicCoordinate,
    conjugate_momenta,
    cyclic_coordinates,
)
from lagrangian.analysis.noether import Symmetry, point_symmetries
from lagrangian.analysis.report import (
    AnalysisReport,
    ConservedQuantity,
    Failure,
    analyze,
    conserved_quantities,
)

__all__ = [
    "AnalysisReport",
    "ConjugateMomenta",
    "ConservedQuantity",
    "CyclicCoordinate",
    "EnergyConservation",
    "Equilibria",
    "Equilibrium",
    "Failure",
    "HamiltonEquations",
    "Hamiltonian",
    "Linearization",
    "NormalModes",
    "Symmetry",
    "TotalDerivativeEquivalence",
    "analyze",
    "conjugate_momenta",
    "conserved_quantities",
    "cyclic_coordinates",
    "energy_conservation",
    "energy_function",
    "equilibria",
    "equivalent_under_total_derivative",
    "hamilton_equations",
    "hamiltonian",
    "linearize",
    "normal_modes",
    "point_symmetries",
    "point_transformation",
]
