"""The constraints layer: classify constraints, count the freedom they leave, enforce them by
multipliers or eliminate them, and find the forces they exert (Goldstein, Classical Mechanics,
3rd ed., §1.3 and §2.4).

- :func:`classify` — holonomic or not (integrability of velocity constraints, with the
  integrated form), scleronomic or rheonomic, redundant, degrees of freedom, 3N - k;
- :func:`constrained_equations` — [[M, -A^T], [A, 0]] [q_ddot; lambda] = [forcing; gamma],
  the multipliers, the augmented Lagrangian L + sum lambda_j h_j;
- :func:`particle_constraint_forces` — the Cartesian constraint force on each particle;
- :func:`reaction_wrenches` — the constraint wrench on each body in maximal coordinates;
- :func:`eliminate` — the System in minimal coordinates;
- :func:`project_state` — a state moved onto the constraints.

>>> import lagrangian as lg, sympy as sp
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)])
>>> classify(ring).dof
1
"""

from lagrangian.constraints.classify import (
    ConstraintClass,
    ConstraintReport,
    ParticleCount,
    classify,
)
from lagrangian.constraints.eliminate import eliminate
from lagrangian.constraints.forces import particle_constraint_forces
from lagrangian.constraints.multipliers import (
    ConstrainedEquations,
    constrained_equations,
    multiplier_names,
    multiplier_symbols,
)
from lagrangian.constraints.projection import project_state
from lagrangian.constraints.wrenches import ReactionWrench, reaction_wrenches

__all__ = [
    "ConstrainedEquations",
    "ConstraintClass",
    "ConstraintReport",
    "ParticleCount",
    "ReactionWrench",
    "classify",
    "constrained_equations",
    "eliminate",
    "multiplier_names",
    "multiplier_symbols",
    "particle_constraint_forces",
    "project_state",
    "reaction_wrenches",
]
