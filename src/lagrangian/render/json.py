"""The machine-readable output contract (docs/architecture.md): ``lagrangian derive --format json``.

Every expression is a string SymPy can parse, written with the input's names
(``theta_dot``, ``theta_ddot``).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.constraints.multipliers import UNSOLVED
from lagrangian.derivation import EquationsOfMotion
from lagrangian.render.text import SumPrinter


class ExpressionWriter:
    """The text of every expression of one JSON document (derive's, analyze's): ``sympy.sstr``
    with ``order="none"``, character for character, so that it parses back.

    The document's expressions share one printer, which writes each subexpression once
    (:class:`SumPrinter`: the velocities of a chain's Hamiltonian nest the same quotients many
    times), and one string per distinct expression: an equation is also the last step of its
    coordinate, M[i, j] is M[j, i], and the energy function is also the conserved h and T + V.

    >>> x, m = sp.symbols("x m")
    >>> text = ExpressionWriter()
    >>> text(m * x**2 / 2), text(sp.Integer(3) / 2)
    ('m*x**2/2', '3/2')
    """

    def __init__(self) -> None:
        self.printer = SumPrinter({"order": "none"})
        self.written: dict[sp.Basic, str] = {}

    def __call__(self, expr: sp.Basic) -> str:
        text = self.written.get(expr)
        if text is None:
            text = self.written[expr] = self.printer.doprint(expr)
        return text


def _vector(text: ExpressionWriter, matrix: sp.MatrixBase) -> list[str]:
    return [text(e) for e in matrix]


def _matrix(text: ExpressionWriter, matrix: sp.MatrixBase) -> list[list[str]]:
    return [[text(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]


def eom_document(eom: EquationsOfMotion, *, steps: bool = False) -> dict[str, Any]:
    """The derive JSON object: coordinates, parameters, lagrangian, equations, mass_matrix,
    forcing, coriolis, potential_forces (G = dV/dq; ``gravity`` is its old name, kept for one
    release), generalized_forces, dissipation_forces, and more."""
    text = ExpressionWriter()
    document: dict[str, Any] = {
        "name": eom.name,
        "coordinates": [q.name for q in eom.coordinates],
        "velocities": [v.name for v in eom.velocities],
        "accelerations": [a.name for a in eom.accelerations],
        "parameters": {p.name: value for p, value in eom.parameters.items()},
        "kinetic_energy": text(eom.kinetic_energy),
        "potential_energy": text(eom.potential_energy),
        "velocity_potential": text(eom.velocity_potential),
        "dissipation_function": text(eom.dissipation_function),
        "lagrangian": text(eom.lagrangian),
        "equations": _vector(text, eom.equations),
        "mass_matrix": _matrix(text, eom.mass_matrix),
        "forcing": _vector(text, eom.forcing),
        "coriolis": _vector(text, eom.coriolis),
        "time_terms": _vector(text, eom.time_terms),
        "potential_forces": _vector(text, eom.gravity),
        # The old name of potential_forces (which holds springs and capacitors too), kept
        # for one release.
        "gravity": _vector(text, eom.gravity),
        "generalized_forces": _vector(text, eom.generalized_forces),
        "dissipation_forces": _vector(text, eom.dissipation_forces),
        "velocity_potential_forces": _vector(text, eom.velocity_potential_forces),
        "coordinate_orders": eom.orders_by_name(),
    }
    if steps:
        document["steps"] = [
            {
                "coordinate": s.coordinate.name,
                "dL_dvelocity": text(s.dL_dvelocity),
                "ddt_dL_dvelocity": text(s.ddt_dL_dvelocity),
                "dL_dcoordinate": text(s.dL_dcoordinate),
                "dF_dvelocity": text(s.dF_dvelocity),
                "generalized_force": text(s.generalized_force),
                "equation": text(s.equation),
            }
            for s in eom.steps
        ]
    return document


def constrained_document(equations: ConstrainedEquations) -> dict[str, Any]:
    """What constraints add to the derive JSON (docs/architecture.md): ``constraints`` (each
    h, = 0, or >= 0 for a unilateral one), ``constraint_kinds`` (holonomic, velocity or
    unilateral, in the same order), ``multipliers`` (their names), ``constraint_jacobian`` A,
    ``gamma`` (A q_ddot = gamma), the residuals with the constraint forces,
    d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q - A^T lambda (each = 0), and the augmented
    Lagrangian L + sum lambda_j h_j."""
    text = ExpressionWriter()
    return {
        "constraints": [text(c.expression) for c in equations.constraints],
        "constraint_kinds": [c.kind for c in equations.constraints],
        "multipliers": [lam.name for lam in equations.multipliers],
        "constraint_jacobian": _matrix(text, equations.constraint_jacobian),
        "gamma": _vector(text, equations.gamma),
        "constrained_equations": _vector(text, equations.equations),
        "augmented_lagrangian": text(equations.augmented_lagrangian),
        "constraint_forces": _forces(text, equations),
    }


def _forces(text: ExpressionWriter, equations: ConstrainedEquations) -> dict[str, Any]:
    """The multipliers solved for the state, by name, or the reason they are not."""
    forces = equations.constraint_forces
    if forces is None:
        return {"solved": None, "reason": UNSOLVED}
    return {"solved": {lam.name: text(value) for lam, value in forces.items()}, "reason": ""}
