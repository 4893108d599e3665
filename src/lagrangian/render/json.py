"""The machine-readable output contract (docs/architecture.md): ``lagrangian derive --format json``.

Every expression is a string SymPy can parse, written with the input's names
(``theta_dot``, ``theta_ddot``).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.derivation import EquationsOfMotion


def expression_string(expr: sp.Basic) -> str:
    """A SymPy-parseable string of ``expr``."""
    return sp.sstr(expr, order="none")


def _vector(matrix: sp.MatrixBase) -> list[str]:
    return [expression_string(e) for e in matrix]


def _matrix(matrix: sp.MatrixBase) -> list[list[str]]:
    return [
        [expression_string(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)
    ]


def eom_document(eom: EquationsOfMotion, *, steps: bool = False) -> dict[str, Any]:
    """The derive JSON object: coordinates, parameters, lagrangian, equations, mass_matrix,
    forcing, coriolis, gravity, generalized_forces, dissipation_forces, and more."""
    document: dict[str, Any] = {
        "name": eom.name,
        "coordinates": [q.name for q in eom.coordinates],
        "velocities": [v.name for v in eom.velocities],
        "accelerations": [a.name for a in eom.accelerations],
        "parameters": {p.name: value for p, value in eom.parameters.items()},
        "kinetic_energy": expression_string(eom.kinetic_energy),
        "potential_energy": expression_string(eom.potential_energy),
        "velocity_potential": expression_string(eom.velocity_potential),
        "dissipation_function": expression_string(eom.dissipation_function),
        "lagrangian": expression_string(eom.lagrangian),
        "equations": _vector(eom.equations),
        "mass_matrix": _matrix(eom.mass_matrix),
        "forcing": _vector(eom.forcing),
        "coriolis": _vector(eom.coriolis),
        "time_terms": _vector(eom.time_terms),
        "gravity": _vector(eom.gravity),
        "generalized_forces": _vector(eom.generalized_forces),
        "dissipation_forces": _vector(eom.dissipation_forces),
        "velocity_potential_forces": _vector(eom.velocity_potential_forces),
        "coordinate_orders": eom.orders_by_name(),
    }
    if steps:
        document["steps"] = [
            {
                "coordinate": s.coordinate.name,
                "dL_dvelocity": expression_string(s.dL_dvelocity),
                "ddt_dL_dvelocity": expression_string(s.ddt_dL_dvelocity),
                "dL_dcoordinate": expression_string(s.dL_dcoordinate),
                "dF_dvelocity": expression_string(s.dF_dvelocity),
                "generalized_force": expression_string(s.generalized_force),
                "equation": expression_string(s.equation),
            }
            for s in eom.steps
        ]
    return document


def constrained_document(equations: ConstrainedEquations) -> dict[str, Any]:
    """What constraints add to the derive JSON (docs/architecture.md): ``multipliers`` (their
    names), ``constraint_jacobian`` A, ``gamma`` (A q_ddot = gamma), the residuals with the
    constraint forces, d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q - A^T lambda (each = 0), and the
    augmented Lagrangian L + sum lambda_j h_j."""
    return {
        "constraints": [expression_string(c.expression) for c in equations.constraints],
        "multipliers": [lam.name for lam in equations.multipliers],
        "constraint_jacobian": _matrix(equations.constraint_jacobian),
        "gamma": _vector(equations.gamma),
        "constrained_equations": _vector(equations.equations),
        "augmented_lagrangian": expression_string(equations.augmented_lagrangian),
    }
