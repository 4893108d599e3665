"""The equations of a constrained system in LaTeX and MathML, as the plain text shows them:
the constraints, then the equations of motion with their multipliers (lambda_j dh_j/dq, or
lambda_j a_j for a velocity constraint, is the force of constraint j), and with ``matrix``
the augmented system the multipliers solve,

    [ M  -A^T ] [ q_ddot ]   [ forcing ]
    [ A    0  ] [ lambda ] = [ gamma   ].

Every format of ``lagrangian derive`` consumes the one
:class:`~lagrangian.constraints.ConstrainedEquations` value, so none can drop a constraint.

>>> import sympy as sp, lagrangian as lg
>>> from lagrangian.constraints import constrained_equations
>>> x, y, l = sp.symbols("x y l")
>>> pendulum = lg.System(coordinates=[x, y], parameters={l: 1.0},
...     kinetic=(sp.Symbol("x_dot")**2 + sp.Symbol("y_dot")**2) / 2, potential=y,
...     constraints=[lg.Holonomic(x**2 + y**2 - l**2)])
>>> equations = constrained_equations(lg.derive(pendulum), pendulum.constraints)
>>> r"\\lambda_{1}" in constrained_latex(equations)
True
"""

from __future__ import annotations

import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.constraints.multipliers import UNSOLVED
from lagrangian.model.constraints import Unilateral
from lagrangian.render.latex import KeptLatexPrinter, block, symbol_names
from lagrangian.render.mathml import Dotted, TableRow, mathml_table

#: The heading line (plain \\text, which KaTeX and MathJax both typeset; no \\intertext).
HEADING = (
    "&\\text{with the constraints (}\\lambda_j \\, \\partial h_j / \\partial q"
    "\\text{ is the force of constraint } j\\text{)}"
)


#: Below the constraints when one is unilateral: what the equations that follow assume.
IN_CONTACT = "while in contact: each unilateral constraint at 0, its multiplier >= 0"
IN_CONTACT_LATEX = (
    "&\\text{while in contact: each unilateral constraint at }0\\text{, its multiplier }\\geq 0"
)


def in_contact(equations: ConstrainedEquations) -> bool:
    """Whether the equations hold only in contact (a constraint is unilateral)."""
    return any(isinstance(c, Unilateral) for c in equations.constraints)


#: The line above the multipliers solved for the state.
FORCES_HEADING = "&\\text{constraint forces (each multiplier solved for the state)}"


def _relation(constraint: object) -> str:
    return "\\geq" if isinstance(constraint, Unilateral) else "="


def constrained_latex_lines(equations: ConstrainedEquations, matrix: bool = False) -> list[str]:
    """The aligned lines: a heading, each constraint, each equation with its multipliers,
    and with ``matrix`` the augmented system."""
    tex = KeptLatexPrinter({"symbol_names": symbol_names(equations.coordinates)}).doprint

    lines = [HEADING]
    lines += [f"{tex(c.expression)} &{_relation(c)} 0" for c in equations.constraints]
    if in_contact(equations):
        lines.append(IN_CONTACT_LATEX)
    n = len(equations.coordinates)
    lines += [f"{tex(e)} &= 0" for e in list(equations.equations)[:n]]
    forces = equations.constraint_forces
    lines.append(FORCES_HEADING)
    if forces is None:
        lines.append(f"&\\text{{{UNSOLVED}}}")
    else:
        lines += [f"{tex(lam)} &= {tex(value)}" for lam, value in forces.items()]
    if matrix:
        unknowns = sp.Matrix(equations.unknowns)
        lines.append(
            f"{tex(equations.augmented_matrix)} {tex(unknowns)} &= {tex(equations.augmented_rhs)}"
        )
    return lines


def constrained_latex(
    equations: ConstrainedEquations, matrix: bool = False, environment: str = "align*"
) -> str:
    """:func:`constrained_latex_lines` in one ``environment``."""
    return block(constrained_latex_lines(equations, matrix), environment)


def constrained_mathml_rows(
    equations: ConstrainedEquations, matrix: bool = False
) -> list[TableRow]:
    """The rows of the MathML table, as :func:`constrained_latex_lines` (headings and notes
    without a relation, a unilateral constraint with its >=)."""
    # Dotted reads the coordinates, velocities and accelerations only
    dotted = Dotted(equations)  # type: ignore[arg-type]
    heading = (
        "<mtext>with the constraints (&#955;<sub>j</sub> &#8706;h<sub>j</sub>/&#8706;q is the "
        "force of constraint j)</mtext>"
    )
    rows: list[TableRow] = [(heading, "", "")]
    for c in equations.constraints:
        relation = "&#8805;" if isinstance(c, Unilateral) else "="
        rows.append((dotted(c.expression), relation, "<mn>0</mn>"))
    if in_contact(equations):
        rows.append((f"<mtext>{IN_CONTACT.replace('>=', '&#8805;')}</mtext>", "", ""))
    n = len(equations.coordinates)
    rows += [(dotted(e), "<mn>0</mn>") for e in list(equations.equations)[:n]]
    forces = equations.constraint_forces
    rows.append(("<mtext>constraint forces (each multiplier solved for the state)</mtext>", "", ""))
    if forces is None:
        rows.append((f"<mtext>{UNSOLVED}</mtext>", "", ""))
    else:
        rows += [(dotted(lam), dotted(value)) for lam, value in forces.items()]
    if matrix:
        left = dotted(equations.augmented_matrix) + dotted(sp.Matrix(equations.unknowns))
        rows.append((left, dotted(equations.augmented_rhs)))
    return rows


def constrained_mathml(equations: ConstrainedEquations, matrix: bool = False) -> str:
    """The rows of :func:`constrained_mathml_rows` as one display-math table."""
    return mathml_table(constrained_mathml_rows(equations, matrix))
