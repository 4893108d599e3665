"""What an export adds for a system with holonomic or velocity constraints: the multiplier
form of :mod:`lagrangian.numerics.constrained`,

    [ M  -A^T ] [ q_ddot ]   [ forcing                      ]
    [ A    0  ] [ lambda ] = [ gamma - 2 alpha c - beta^2 h ],

as four more functions (the constraint Jacobian A, the right side of A q_ddot, and the
augmented matrix and vector), two more parameters (Baumgarte's alpha and beta, 0 by default:
the plain index-1 form) and an ``rhs`` that solves the augmented system, with a
``multipliers`` function for lambda.  Unilateral constraints (active only part of the time)
cannot be written as one right-hand side and are refused.
"""

from __future__ import annotations

import sympy as sp

from lagrangian.constraints import constrained_equations
from lagrangian.constraints.pfaffian import pfaffian_form
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import ModelError
from lagrangian.model.constraints import Unilateral, VelocityConstraint

#: Baumgarte's gains, appended to the parameters (default 0: no stabilization).
ALPHA, BETA = sp.symbols("baumgarte_alpha baumgarte_beta")

#: The equations of the header of a constrained export.
HEADER = [
    "With the constraints, in the multiplier form (lambda_j dh_j/dq is the force of",
    "constraint j; c = A qd + b, h the position residual of the holonomic rows):",
    "",
    "    M q_ddot - A^T lambda = forcing,   A q_ddot = gamma - 2 alpha c - beta^2 h",
    "",
    "alpha = baumgarte_alpha and beta = baumgarte_beta (last in p, default 0: no",
    "stabilization) pull a drift of the constraints back to zero.",
]


def multiplier_pieces(
    eom: EquationsOfMotion,
) -> tuple[dict[str, sp.Matrix], tuple[sp.Symbol, ...], tuple[str, ...]]:
    """(the functions' expressions by name, the extra parameters, the multipliers' names)."""
    constraints = eom.system.constraints
    for c in constraints:
        if isinstance(c, Unilateral):
            raise ModelError(
                f"Cannot export {eom.name or 'this system'}: the unilateral constraint "
                f"{c.expression} >= 0 is active only part of the time, so no one right-hand "
                "side describes the motion; simulate it with lagrangian itself."
            )
    equations = constrained_equations(eom, constraints)
    q = list(equations.coordinates)
    velocity_residuals = [pfaffian_form(c, q).velocity_expression for c in constraints]
    positions = [
        sp.Integer(0) if isinstance(c, VelocityConstraint) else c.expression for c in constraints
    ]
    stabilized = sp.Matrix(
        [
            g - 2 * ALPHA * c - BETA**2 * h
            for g, c, h in zip(equations.gamma, velocity_residuals, positions)
        ]
    )
    pieces = {
        "constraint_jacobian": sp.Matrix(equations.constraint_jacobian),
        "constraint_rhs": stabilized,
        "augmented_matrix": sp.Matrix(equations.augmented_matrix),
        "augmented_forcing": sp.Matrix(equations.forcing).col_join(stabilized),
    }
    names = tuple(s.name for s in equations.multipliers)
    return pieces, (ALPHA, BETA), names
