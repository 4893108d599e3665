"""What a derivation shows, independent of the format: the rows of one coordinate's steps.

Both the text and the LaTeX renderers lay out these rows; only the labels differ.
"""

from __future__ import annotations

from enum import Enum

import sympy as sp

from lagrangian.derivation import CoordinateSteps, EquationsOfMotion


class Row(Enum):
    """One line of a coordinate's step-by-step derivation."""

    MOMENTUM = "dL/dq_dot"
    RATE = "d/dt dL/dq_dot"
    SLOPE = "dL/dq"
    FRICTION = "dF/dq_dot"
    FORCE = "Q"
    EQUATION = "equation"


def step_rows(steps: CoordinateSteps) -> list[tuple[Row, sp.Expr]]:
    """dL/dq_dot, d/dt(dL/dq_dot), dL/dq always; dF/dq_dot and Q_j when non-zero; then the
    equation d/dt(dL/dq_dot) - dL/dq + dF/dq_dot - Q_j (= 0)."""
    rows = [
        (Row.MOMENTUM, steps.dL_dvelocity),
        (Row.RATE, steps.ddt_dL_dvelocity),
        (Row.SLOPE, steps.dL_dcoordinate),
    ]
    if steps.dF_dvelocity != 0:
        rows.append((Row.FRICTION, steps.dF_dvelocity))
    if steps.generalized_force != 0:
        rows.append((Row.FORCE, steps.generalized_force))
    rows.append((Row.EQUATION, steps.equation))
    return rows


def energy_rows(eom: EquationsOfMotion) -> list[tuple[str, sp.Expr]]:
    """(label, expression): T, V, (U), L with its definition "T - V (- U)", (F); U and F only
    when the system has them."""
    rows = [("T", eom.kinetic_energy), ("V", eom.potential_energy)]
    definition = "T - V"
    if eom.velocity_potential != 0:
        rows.append(("U", eom.velocity_potential))
        definition += " - U"
    rows.append((f"L = {definition}", eom.lagrangian))
    if eom.dissipation_function != 0:
        rows.append(("F", eom.dissipation_function))
    return rows
