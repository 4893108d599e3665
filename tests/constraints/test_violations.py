"""Which constraints a state misses, and by how much (the refusal of analyze --about), and the
substitution eliminate() makes, against hand values."""

from __future__ import annotations

import pytest
import sympy as sp
from constraint_systems import knife_edge, pendulum, pendulum_state, rotating_wire

import lagrangian as lg
from lagrangian.constraints import classify
from lagrangian.constraints.eliminate import elimination_rule
from lagrangian.constraints.projection import violations

x, y, l = sp.symbols("x y l")


def test_a_state_on_the_rod_violates_nothing() -> None:
    assert violations(pendulum(), pendulum_state(0.3, 1.2)) == ()


def test_off_the_rod_at_position_and_at_velocity_level() -> None:
    (found,) = violations(pendulum(), {"x": 0.0, "y": -1.0})
    assert (found.level, found.residual) == ("position", pytest.approx(1.0 - 0.49))
    assert found.label == "'rod' (constraints[0])"
    (found,) = violations(pendulum(), {"x": 0.0, "y": -0.7, "x_dot": 0.0, "y_dot": 2.0})
    assert (found.level, found.residual) == ("velocity", pytest.approx(2 * -0.7 * 2.0))
    problem = found.problem("add --project")
    assert problem.field == "'rod' (constraints[0])" and problem.fix == "add --project"
    assert "velocity level" in problem.message


def test_a_blade_is_violated_by_sliding_sideways() -> None:
    (found,) = violations(knife_edge(), {"x": 0, "y": 0, "phi": 0, "y_dot": 0.5})
    assert found.level == "velocity" and found.residual == pytest.approx(-0.5)


def test_a_moving_constraint_is_checked_at_the_given_time() -> None:
    # x sin(omega t) - y cos(omega t) = 0 with omega = 1.7: at t = 0 the wire is the x axis
    assert violations(rotating_wire(), {"t": 0.0, "x": 1.0, "y": 0.0, "x_dot": 0.0}) != ()
    on_wire = {"t": 0.0, "x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 1.7}
    assert violations(rotating_wire(), on_wire) == ()


def test_the_elimination_rule_solves_for_the_dependent_coordinates() -> None:
    system = pendulum().replace(initial={x: 0.0, y: -0.7})
    rule = elimination_rule(system, [x])
    assert sp.simplify(rule[y] + sp.sqrt(l**2 - x**2)) == 0
    with pytest.raises(lg.errors.ConstraintError, match="2 solution branches"):
        elimination_rule(pendulum(), [x])


def test_the_configuration_dimension_of_a_skate() -> None:
    report = classify(knife_edge())
    assert (report.configuration_dimension, report.independent_velocities) == (3, 2)
