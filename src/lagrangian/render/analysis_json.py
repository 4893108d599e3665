"""``lagrangian analyze --format json``: the machine-readable output contract
(docs/architecture.md).

Keys: ``dof`` (the independent velocities, n minus every equality constraint),
``configuration_dimension`` (n minus the holonomic ones), ``independent_velocities`` and
``freedom`` (the two explained), ``parameter_values`` (each parameter and the value every
statement is decided at: a number, an expression of other parameters, or null),
``constraints`` (each classified: kind, holonomic, rheonomic, ...), ``momenta`` (coordinate
name -> p), ``cyclic`` (the names of the coordinates
absent from L and F; ``cyclic_coordinates`` has each with its momentum, whether it is
conserved, what changes it and the condition), ``conserved`` (the expressions conserved at
the parameter values given; ``conserved_quantities`` all of them with their reasons, origin,
``conditions`` (relations between parameters such as ``Eq(k1, k2)``, empty when always
conserved) and ``holds`` (whether the values given meet the conditions)), ``energy_function``,
``energy_conserved``, ``hamiltonian``, ``equilibria`` (each with ``state`` and ``stable``),
``equilibria_count`` (how many there are: more than listed when static equations that
separate have too many combinations of roots to list) and ``equilibria_reason`` (how they
were found),
``normal_modes`` (frequencies and shapes about a stable equilibrium), ``steady_motions`` (for
constraints that move by a symmetry: each configuration at t = 0 with its velocities and its
stability relative to them) and, when the report
was made about an operating point, ``linearization`` (``A``, ``B``, ``eigenvalues``,
``frequencies``, ``growth_rates``).  Details (reasons, conditions, dh/dt, Hamilton's
equations) and ``failures`` (part -> reason) come alongside.  Every expression is a string
SymPy can parse; a part that could not be computed is null.

>>> import json, lagrangian as lg
>>> from lagrangian.analysis import analyze
>>> document = analysis_document(analyze(lg.examples.simple_pendulum()))
>>> document["momenta"], document["normal_modes"]["frequencies"]
({'theta': 'm*theta_dot*l**2'}, ['sqrt(g)/sqrt(l)'])
>>> _ = json.dumps(document)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import sympy as sp

from lagrangian.analysis import (
    AnalysisReport,
    CyclicCoordinate,
    EnergyConservation,
    Equilibrium,
    HamiltonEquations,
    Linearization,
    NormalModes,
)
from lagrangian.analysis.manifold.constraint_forces import ConstraintForces
from lagrangian.analysis.steady_motions import SteadyMotions
from lagrangian.render.json import ExpressionWriter
from lagrangian.symbolic.conversion import to_sympy


def _strings(text: ExpressionWriter, values: Iterable[Any]) -> list[str]:
    return [text(to_sympy(v)) for v in values]


def _matrix(text: ExpressionWriter, matrix: sp.MatrixBase) -> list[list[str]]:
    return [_strings(text, matrix.row(i)) for i in range(matrix.rows)]


def _state(text: ExpressionWriter, state: Mapping[sp.Symbol, Any]) -> dict[str, str]:
    return {s.name: text(to_sympy(v)) for s, v in state.items()}


def _strings_by_name(text: ExpressionWriter, values: Mapping[str, Any]) -> dict[str, str]:
    return {name: text(to_sympy(v)) for name, v in values.items()}


def _flag(value: Any) -> bool | None:
    return None if value is None else bool(value)


def _energy(text: ExpressionWriter, energy: EnergyConservation) -> dict[str, Any]:
    return {
        "reason": energy.reason,
        "rate": text(energy.rate),
        "constraint_power": text(energy.constraint_power),
        "total_energy": text(energy.total_energy),
        "equals_total_energy": bool(energy.equals_total_energy),
        "total_energy_reason": energy.total_energy_reason,
        "condition": text(energy.condition),
    }


def _equilibrium(text: ExpressionWriter, equilibrium: Equilibrium) -> dict[str, Any]:
    condition = equilibrium.stability_condition
    return {
        "state": _state(text, equilibrium.state),
        "stable": _flag(equilibrium.stable),
        "reason": equilibrium.reason,
        "condition": text(equilibrium.condition),
        "exists": _flag(equilibrium.exists),
        "stability_condition": None if condition is None else text(condition),
        "free": [q.name for q in equilibrium.free],
        "exact": bool(equilibrium.exact),
        "multipliers": _state(text, equilibrium.multipliers),
        "stiffness": _matrix(text, equilibrium.stiffness),
        "stiffness_coordinates": [q.name for q in equilibrium.stiffness_coordinates],
    }


def _modes(text: ExpressionWriter, modes: NormalModes) -> dict[str, Any]:
    return {
        "about": _state(text, modes.about),
        "frequencies": _strings(text, modes.frequencies),
        "squared_frequencies": _strings(text, modes.squared_frequencies),
        "shapes": [_strings(text, shape) for shape in modes.shapes],
        "symbolic": bool(modes.symbolic),
        "reason": modes.reason,
    }


def _canonical(text: ExpressionWriter, canonical: HamiltonEquations) -> dict[str, dict[str, str]]:
    """q_dot = dH/dp keyed by coordinate, p_dot keyed by momentum name."""
    return {
        "coordinate_rates": dict(
            zip([q.name for q in canonical.coordinates], _strings(text, canonical.coordinate_rates))
        ),
        "momentum_rates": dict(
            zip([p.name for p in canonical.momenta], _strings(text, canonical.momentum_rates))
        ),
    }


def _linearization(text: ExpressionWriter, linear: Linearization) -> dict[str, Any]:
    return {
        "state": _state(text, linear.state),
        "state_vector": [s.name for s in linear.state_vector],
        "inputs": [u.name for u in linear.inputs],
        "A": _matrix(text, linear.A),
        "A_at_values": None if linear.A_at_values is None else _matrix(text, linear.A_at_values),
        "B": _matrix(text, linear.B),
        "eigenvalues": _strings(text, linear.eigenvalues),
        "frequencies": _strings(text, linear.frequencies),
        "growth_rates": _strings(text, linear.growth_rates),
        "is_solution": bool(linear.is_solution),
        "note": linear.note,
        "eliminated": [s.name for s in linear.dependent],
        "multipliers": _state(text, linear.multipliers),
    }


def _steady(text: ExpressionWriter, found: SteadyMotions) -> dict[str, Any]:
    """Each steady motion: its configuration at t = 0 and velocities, stability relative to
    the moving constraints; the effective potential and the rate of the symmetry."""
    return {
        "motions": [
            {**_equilibrium(text, e), "velocities": _state(text, v)}
            for e, v in zip(found.motions, found.velocities)
        ],
        "effective_potential": text(found.effective_potential),
        "rate": text(found.rate),
        "symmetry": found.symmetry,
        "method": found.method,
        "reason": found.reason,
    }


def _cyclic(text: ExpressionWriter, cyclic: CyclicCoordinate) -> dict[str, Any]:
    return {
        "coordinate": cyclic.coordinate.name,
        "momentum": text(cyclic.momentum),
        "conserved": bool(cyclic.conserved),
        "obstructions": list(cyclic.obstructions),
        "condition": text(cyclic.condition),
        "reason": cyclic.reason,
    }


def _value(text: ExpressionWriter, value: sp.Expr | None) -> float | str | None:
    """A parameter's value: a number, an expression of other parameters, or None."""
    if value is None:
        return None
    return float(value) if value.is_number else text(value)


def analysis_document(report: AnalysisReport) -> dict[str, Any]:
    """The analyze JSON object (see the module docstring) of ``report``."""
    energy, legendre, canonical = report.energy, report.hamiltonian, report.hamilton_equations
    text = ExpressionWriter()
    document: dict[str, Any] = {
        "name": report.name,
        "dof": report.dof,
        "configuration_dimension": report.configuration_dimension,
        "independent_velocities": report.independent_velocities,
        "freedom": report.freedom,
        "coordinates": [q.name for q in report.coordinates],
        "parameter_values": {p.name: _value(text, v) for p, v in report.parameter_values},
        "constraints": [c.as_dict() for c in report.constraints],
        "momenta": None
        if report.momenta is None
        else _strings_by_name(text, report.momenta.by_name()),
        "cyclic": [c.coordinate.name for c in report.cyclic],
        "cyclic_coordinates": [_cyclic(text, c) for c in report.cyclic],
        "conserved": [text(c.expression) for c in report.conserved if c.holds],
        "conserved_quantities": [
            {
                "name": c.name,
                "expression": text(c.expression),
                "reason": c.reason,
                "condition": text(c.condition),
                "conditions": _strings(text, c.conditions),
                "holds": bool(c.holds),
                "origin": c.origin,
                "explicit_time": c.explicit_time,
            }
            for c in report.conserved
        ],
        "energy_function": None if energy is None else text(energy.energy_function),
        "energy_conserved": None if energy is None else bool(energy.conserved),
        "energy": None if energy is None else _energy(text, energy),
        "hamiltonian": None if legendre is None else text(legendre.hamiltonian),
        "hamiltonian_coordinates": None
        if legendre is None
        else [q.name for q in legendre.coordinates],
        "eliminated": None if legendre is None else _state(text, legendre.eliminated),
        "hamilton_equations": None if canonical is None else _canonical(text, canonical),
        "equilibria": None
        if report.equilibria is None
        else [_equilibrium(text, e) for e in report.equilibria],
        "equilibria_count": None
        if report.equilibria is None
        else (report.equilibria.count or len(report.equilibria.equilibria)),
        "equilibria_reason": None if report.equilibria is None else report.equilibria.reason,
        "normal_modes": None if report.normal_modes is None else _modes(text, report.normal_modes),
        "steady_motions": None
        if report.steady_motions is None
        else _steady(text, report.steady_motions),
        "first_integral_search": list(report.searched),
        "failures": {f.part: f.reason for f in report.failures},
        "symbols": _symbols(report),
    }
    if report.constraint_forces is not None:
        document["constraint_forces"] = _constraint_forces(text, report.constraint_forces)
    if report.linearization is not None or report.failure("linearization"):
        linear = report.linearization
        document["linearization"] = None if linear is None else _linearization(text, linear)
    return document


def _symbols(report: AnalysisReport) -> dict[str, Any]:
    """The names the report introduces (textbook's unless the model has them)."""
    names = report.names
    return {
        "energy_function": names.energy,
        "hamiltonian": names.hamiltonian,
        "frequency": names.frequency,
        "effective_potential": names.effective_potential,
        "momenta": {q.name: names.momentum(q) for q in report.coordinates},
    }


def _constraint_forces(text: ExpressionWriter, forces: ConstraintForces) -> dict[str, Any]:
    """As ``derive``'s JSON: the multipliers solved by name, or the reason they are not."""
    solved = forces.solved
    by_name = None if solved is None else {lam.name: text(v) for lam, v in solved.items()}
    return {"solved": by_name, "reason": forces.reason}
