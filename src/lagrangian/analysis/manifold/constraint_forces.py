"""The constraint forces of a constrained system, each multiplier solved for the state.

The multiplier lambda_j of constraint j, times dh_j/dq (or a_j), is the generalized force the
constraint exerts; solved from the augmented system [M, -A^T; A, 0] [q_ddot; lambda] =
[forcing; gamma] it is a function of the state and time (a uniform cylinder rolling down an
incline: friction lambda = -m g sin(alpha) / 3).  The solution is the one ``derive`` prints
(:attr:`lagrangian.constraints.ConstrainedEquations.constraint_forces`), for the constraints
the analysis keeps.

>>> import lagrangian as lg
>>> from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
>>> system = lg.examples.cylinder_on_incline()
>>> eom = lg.derive(system)
>>> constraint_forces(eom, constraint_manifold(eom)).solved
{lambda_1: -g*m*sin(alpha)/3}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold
from lagrangian.constraints import constrained_equations
from lagrangian.constraints.multipliers import UNSOLVED
from lagrangian.derivation import EquationsOfMotion


@dataclass(frozen=True)
class ConstraintForces:
    """The multipliers solved (None: left to the augmented system, ``reason`` says why)."""

    solved: Mapping[sp.Symbol, sp.Expr] | None
    reason: str = ""


def constraint_forces(eom: EquationsOfMotion, manifold: ConstraintManifold) -> ConstraintForces:
    """The multipliers of the constraints the analysis keeps, solved for the state."""
    forces = constrained_equations(eom, manifold.constraints).constraint_forces
    if forces is None:
        return ConstraintForces(None, UNSOLVED)
    return ConstraintForces(dict(forces))
