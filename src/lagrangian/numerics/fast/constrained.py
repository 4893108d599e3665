"""The multiplier form of a constrained system as the C loop solves it (its expressions).

With the constraints differentiated to A q_ddot = gamma (:func:`lagrangian.constraints.
constrained_equations`), the accelerations and multipliers solve

    [ M  -A^T ] [ q_ddot ]   [ forcing                        ]
    [ A    0  ] [ lambda ] = [ gamma - 2 alpha c - beta^2 h   ]

(c = A q_dot + b the velocity residuals, h the position residuals of the holonomic rows, 0
for velocity rows; alpha = beta = 0 the plain index-1 form, alpha, beta > 0 Baumgarte's
stabilization, as :mod:`lagrangian.numerics.constrained` writes it).  The state is
x = [q; q_dot] and the unknowns z = [q_ddot; lambda] begin with the accelerations, so this is
a linear system the C loop solves as it solves the unconstrained state equations
(:mod:`lagrangian.numerics.fast.c_constrained` compiles it); the multipliers are solved for
at every step and not integrated.  alpha and beta are the last two parameters, so a new
stabilization needs no new compilation.

>>> import sympy as sp, lagrangian as lg
>>> from lagrangian.constraints import constrained_equations
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)],
...     particles=[lg.Particle("bead", 1, (x, y))])
>>> alpha, beta = sp.symbols(BAUMGARTE)
>>> matrix, vector = multiplier_system(constrained_equations(ring), alpha, beta)
>>> matrix.shape, vector.shape
((3, 3), (3, 1))
"""

from __future__ import annotations

import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.constraints.pfaffian import pfaffian_form
from lagrangian.model.constraints import VelocityConstraint

#: The names of Baumgarte's alpha and beta, appended to the parameters.
BAUMGARTE = ("baumgarte_alpha", "baumgarte_beta")


def multiplier_system(
    equations: ConstrainedEquations, alpha: sp.Symbol, beta: sp.Symbol
) -> tuple[sp.Matrix, sp.Matrix]:
    """(matrix, vector) of the multiplier form with Baumgarte's gains ``alpha``, ``beta``."""
    m = len(equations.multipliers)
    h, c = residual_expressions(equations)
    stabilization = [2 * alpha * c_j + beta**2 * h_j for h_j, c_j in zip(h, c)]
    jacobian = equations.constraint_jacobian
    matrix = sp.Matrix.vstack(
        sp.Matrix.hstack(equations.mass_matrix, -jacobian.T),
        sp.Matrix.hstack(jacobian, sp.zeros(m, m)),
    )
    vector = sp.Matrix.vstack(
        sp.Matrix(equations.forcing), equations.gamma - sp.Matrix(m, 1, stabilization)
    )
    return matrix, vector


def residual_expressions(equations: ConstrainedEquations) -> tuple[list[sp.Expr], list[sp.Expr]]:
    """(h, c): the position residual of every constraint (0 for a velocity constraint) and
    its velocity residual A q_dot + b."""
    h: list[sp.Expr] = []
    c: list[sp.Expr] = []
    for constraint in equations.constraints:
        c.append(pfaffian_form(constraint, equations.coordinates).velocity_expression)
        velocity = isinstance(constraint, VelocityConstraint)
        h.append(sp.S.Zero if velocity else constraint.expression)
    return h, c
