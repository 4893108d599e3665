"""The derivation of each equation, step by step, as the notes write it (seed 000/001):

dL/dq_dot_j,  d/dt (dL/dq_dot_j),  dL/dq_j,  dF/dq_dot_j,  Q_j,
and the equation  d/dt (dL/dq_dot_j) - dL/dq_j + dF/dq_dot_j - Q_j = 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class CoordinateSteps:
    """The Euler–Lagrange derivation for one coordinate."""

    coordinate: sp.Symbol
    velocity: sp.Symbol
    dL_dvelocity: sp.Expr
    ddt_dL_dvelocity: sp.Expr
    dL_dcoordinate: sp.Expr
    dF_dvelocity: sp.Expr
    generalized_force: sp.Expr
    equation: sp.Expr

    @property
    def momentum(self) -> sp.Expr:
        """The conjugate momentum p_j = dL/dq_dot_j."""
        return self.dL_dvelocity
