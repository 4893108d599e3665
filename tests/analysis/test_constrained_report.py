"""analyze() on constrained systems: degrees of freedom, the Hamiltonian in reduced coordinates
(or why there is none), the --about state checked against the constraints, and the JSON.

References: a cylinder rolling down an incline (I = m r^2/2, x = r phi) has
T = 3/4 m x_dot^2, so H = p_x^2/(3 m) + m g (r cos(alpha) - x sin(alpha)); a pendulum of
length l in x alone (y = -sqrt(l^2 - x^2)) has p_x = m l^2 x_dot/(l^2 - x^2) and H equal to
its energy 1/2 m l^2 theta_dot^2 - m g l cos(theta) at x = l sin(theta); the rolling disc has
5 coordinates and 3 independent velocities (Bloch, Nonholonomic Mechanics and Control, §1.4).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import analyze
from lagrangian.errors import ConstraintError
from lagrangian.render.analysis_json import analysis_document

sys.path.insert(0, str(Path(__file__).parents[1] / "constraints"))
import constraint_systems as cs

x, m, g, l = sp.symbols("x m g l")


def test_the_rolling_disc_counts_three_degrees_of_freedom_in_five_coordinates() -> None:
    report = analyze(lg.examples.rolling_disc())
    assert (report.dof, report.configuration_dimension, report.independent_velocities) == (3, 5, 3)
    assert "3 independent velocities" in report.freedom and "dof = 3" in report.freedom
    assert report.hamiltonian is None
    assert "no Hamiltonian in the usual sense" in (report.failure("hamiltonian") or "")
    assert report.energy is not None and report.energy.conserved
    assert not any("internal error" in f.reason for f in report.failures)


def test_the_rolling_cylinder_has_a_hamiltonian_in_x() -> None:
    report = analyze(lg.examples.cylinder_on_incline())
    assert report.hamiltonian is not None and report.hamiltonian.coordinates == (x,)
    p_x, r, alpha = sp.symbols("p_x r alpha")
    expected = p_x**2 / (3 * m) + m * g * (r * sp.cos(alpha) - x * sp.sin(alpha))
    assert sp.simplify(report.hamiltonian.hamiltonian - expected) == 0
    assert report.hamiltonian.eliminated == {sp.Symbol("phi"): x / r}
    assert report.hamilton_equations is not None
    (rate,) = report.hamilton_equations.momentum_rates
    assert sp.simplify(rate - m * g * sp.sin(alpha)) == 0


def test_the_cartesian_pendulum_has_a_hamiltonian_in_x_on_the_lower_branch() -> None:
    report = analyze(cs.pendulum())
    legendre = report.hamiltonian
    assert legendre is not None and legendre.coordinates == (x,)
    y = sp.Symbol("y")
    assert sp.simplify(legendre.eliminated[y] + sp.sqrt(l**2 - x**2)) == 0
    angle, rate, mass, length = 0.4, 1.3, 1.3, 0.7
    x_value = length * math.sin(angle)
    x_dot = length * math.cos(angle) * rate
    p_value = mass * length**2 * x_dot / (length**2 - x_value**2)
    energy = mass * length**2 * rate**2 / 2 - mass * 9.81 * length * math.cos(angle)
    values = {"x": x_value, "p_x": p_value, "m": mass, "g": 9.81, "l": length}
    assert cs.numeric(legendre.hamiltonian, values) == pytest.approx(energy)


def test_an_about_state_off_the_constraints_is_refused_or_projected() -> None:
    with pytest.raises(ConstraintError, match=r"'rod' \(constraints\[0\]\).*project=True"):
        analyze(cs.pendulum(), about={"x": 0.1, "y": -0.5})
    report = analyze(cs.pendulum(), about={"x": 0.1, "y": -0.5}, project=True)
    linear = report.linearization
    assert linear is not None
    on_circle = float(linear.state[sp.Symbol("x")]) ** 2 + float(linear.state[sp.Symbol("y")]) ** 2
    assert on_circle == pytest.approx(0.49)


def test_the_json_of_a_constrained_report() -> None:
    report = analyze(lg.examples.rolling_disc(), about={"phi_dot": 5, "x_dot": 1.5})
    document = analysis_document(report)
    json.dumps(document)
    assert (document["dof"], document["configuration_dimension"]) == (3, 5)
    assert document["independent_velocities"] == 3
    assert document["cyclic"] == ["x", "y", "phi"]
    details = {c["coordinate"]: c for c in document["cyclic_coordinates"]}
    assert details["x"]["conserved"] is False and details["x"]["obstructions"] == ["constraint"]
    assert document["energy_conserved"] is True
    assert document["hamiltonian"] is None
    linear = document["linearization"]
    assert linear["eliminated"] == ["x_dot", "y_dot"]
    assert linear["growth_rates"] == [] and len(linear["frequencies"]) == 1
    assert set(linear["multipliers"]) == {"lambda_1", "lambda_2"}
    stable = [e for e in document["equilibria"] if e["stable"]]
    assert stable and all(set(e["multipliers"]) == {"lambda_1", "lambda_2"} for e in stable)


def test_a_unilateral_constraint_is_said_to_be_left_out() -> None:
    floor = lg.Unilateral(sp.Symbol("y") + 2, name="floor")
    system = cs.pendulum().replace(constraints=[*cs.pendulum().constraints, floor])
    report = analyze(system)
    assert "left out of this analysis: 'floor' (constraints[1]) unilateral" in report.freedom
    assert report.equilibria is not None and len(report.equilibria) == 2


def test_the_constraint_entries_are_frozen_classifications_with_the_same_json_keys() -> None:
    report = analyze(cs.pendulum(), search_degree=0)
    (rod,) = report.constraints
    assert (rod.kind, rod.holonomic, rod.rheonomic, rod.redundant) == (
        "holonomic",
        True,
        False,
        False,
    )
    with pytest.raises(AttributeError, match="cannot assign to field 'kind'"):
        rod.kind = "velocity"  # type: ignore[misc]
    (entry,) = analysis_document(report)["constraints"]
    assert list(entry) == [
        "name",
        "kind",
        "expression",
        "holonomic",
        "rheonomic",
        "redundant",
        "reason",
    ]
    assert entry["expression"] == str(rod.expression) and entry["reason"] == rod.reason
