"""classify(): holonomic or not (with the integrated form of velocity constraints that are
holonomic in disguise), scleronomic or rheonomic, redundancy, inconsistency, and the counts
dof = n - r_h, independent velocities, and the notes' 3N - k (seed 000)."""

from __future__ import annotations

import itertools
import random

import pytest
import sympy as sp
from constraint_systems import (
    knife_edge,
    moving_pivot,
    pendulum,
    rolling_disc,
    rotating_hoop,
    rotating_wire,
)

import lagrangian as lg
from lagrangian.constraints import classify, project_state
from lagrangian.errors import ConstraintError

x, y, z, phi, r, l = sp.symbols("x y z phi r l")
x_dot, y_dot, z_dot, phi_dot = sp.symbols("x_dot y_dot z_dot phi_dot")


def velocity_only(coordinates: list[sp.Symbol], *expressions: sp.Expr, **kw) -> lg.System:
    return lg.System(
        coordinates=coordinates, constraints=[lg.VelocityConstraint(e) for e in expressions], **kw
    )


# -- holonomic constraints written in velocity form --------------------------------------


def _is_first_integral(h: sp.Expr, form: tuple[sp.Expr, ...], coordinates: list) -> bool:
    """dh is proportional to the constraint's form a.dq (every 2x2 minor vanishes)."""
    grad = [h.diff(q) for q in coordinates]
    return all(
        sp.simplify(grad[i] * form[j] - grad[j] * form[i]) == 0
        for i, j in itertools.combinations(range(len(coordinates)), 2)
    )


def test_x_x_dot_plus_y_y_dot_integrates_to_the_circle() -> None:
    (found,) = classify(velocity_only([x, y], x * x_dot + y * y_dot)).constraints
    assert found.holonomic and not found.rheonomic
    assert found.integrated is not None
    # h = (x^2 + y^2)/2 up to the constant fixed by the initial state
    assert sp.simplify(2 * found.integrated - (x**2 + y**2)).is_number
    assert "exact" in found.reason and "fixed by the initial state" in found.reason


def test_rolling_cylinder_down_an_incline_integrates_to_x_minus_r_phi() -> None:
    rolling = velocity_only([x, phi], x_dot - r * phi_dot, parameters={r: 0.2})
    report = classify(rolling)
    (found,) = report.constraints
    assert found.holonomic
    assert sp.simplify(found.integrated - (x - r * phi)).is_number
    assert (report.dof, report.independent_velocities) == (1, 1)


def test_an_integrating_factor_is_found_for_y_x_dot_minus_x_y_dot() -> None:
    (found,) = classify(velocity_only([x, y], y * x_dot - x * y_dot)).constraints
    # the ray through the origin: x/y (or y/x, the angle) is constant
    assert found.holonomic and found.integrating_factor not in (None, 1)
    assert _is_first_integral(found.integrated, (y, -x), [x, y])


def test_a_velocity_constraint_integrable_only_with_the_others_is_holonomic() -> None:
    # z_dot - y x_dot = 0 alone twists (omega ^ d omega = dz^dx^dy); with y_dot = 0 the pair is
    # integrable (y = c, z - c x = c'): Frobenius for the set.
    report = classify(velocity_only([x, y, z], z_dot - y * x_dot, y_dot))
    assert report.integrable_set is True
    assert [c.holonomic for c in report.constraints] == [True, True]
    assert "together" in report.constraints[0].reason
    assert report.dof == 1


# -- non-holonomic constraints ------------------------------------------------------------


def test_the_knife_edge_is_non_holonomic_with_the_frobenius_reason() -> None:
    report = classify(knife_edge())
    (blade,) = report.constraints
    assert (blade.kind, blade.holonomic, blade.rheonomic) == ("velocity", False, False)
    assert "non-holonomic" in blade.reason and "omega ^ d omega" in blade.reason
    assert "(-1) dx^dy^dphi" in blade.reason  # sin^2 + cos^2 simplified
    assert (report.dof, report.independent_velocities) == (3, 2)
    assert report.integrable_set is False


def test_the_rolling_disc_is_non_holonomic() -> None:
    report = classify(rolling_disc())
    assert [c.holonomic for c in report.constraints] == [False, False]
    assert all("non-holonomic" in c.reason for c in report.constraints)
    assert report.integrable_set is False and "d omega_1 ^ omega_1 ^ omega_2" in report.set_reason
    assert (report.dof, report.independent_velocities, report.generic_rank) == (4, 2, 2)


def test_a_rheonomic_velocity_constraint_is_non_holonomic() -> None:
    (found,) = classify(velocity_only([x, y], x_dot - lg.t * y_dot)).constraints
    assert found.rheonomic and not found.holonomic


def test_unilateral_constraints_are_non_holonomic_inequalities_and_remove_no_freedom() -> None:
    sphere = lg.System(
        coordinates=[x, y, z],
        parameters={l: 1.0},
        constraints=[lg.Unilateral(x**2 + y**2 + z**2 - l**2)],
    )
    report = classify(sphere)
    (found,) = report.constraints
    assert (found.kind, found.holonomic) == ("unilateral", False)
    assert "inequality" in found.reason
    assert report.dof == 3


# -- scleronomic and rheonomic ------------------------------------------------------------


def test_bead_on_a_rotating_hoop_is_rheonomic_where_the_plane_turns() -> None:
    report = classify(rotating_hoop())
    plane, hoop = report.constraints
    assert plane.rheonomic and "rheonomic" in plane.reason
    assert hoop.holonomic and not hoop.rheonomic and "scleronomic" in hoop.reason
    assert report.dof == 1 and str(report.particle_count) == "3N - k = 3*1 - 2 = 1"


def test_a_rotating_wire_and_a_driven_pivot_are_rheonomic() -> None:
    for system in (rotating_wire(), moving_pivot()):
        (found,) = classify(system).constraints
        assert found.holonomic and found.rheonomic


# -- counting: dof, independent velocities, 3N - k ----------------------------------------


def test_pendulum_counts() -> None:
    report = classify(pendulum())
    assert (report.dof, report.independent_velocities, report.generic_rank) == (1, 1, 1)
    assert str(report.particle_count) == "2N - k = 2*1 - 1 = 1"
    # The pendulum in theta has the rod built into its coordinates: the same count.
    assert str(classify(lg.examples.simple_pendulum()).particle_count) == "2N - k = 2*1 - 1 = 1"


def _rigid_points(count: int) -> lg.System:
    """count particles in space with every pairwise distance fixed (at the distances of a
    random reference configuration, so that the constraints are consistent)."""
    rng = random.Random(3)
    names = [sp.symbols(f"x{i} y{i} z{i}") for i in range(count)]
    reference = [[sp.Rational(rng.randint(-9, 9), 7) for _ in range(3)] for _ in range(count)]
    constraints = []
    for i, j in itertools.combinations(range(count), 2):
        d2 = sum((a - b) ** 2 for a, b in zip(reference[i], reference[j]))
        squared = sum((a - b) ** 2 for a, b in zip(names[i], names[j]))
        constraints.append(lg.Holonomic(squared - d2, name=f"d{i}{j}"))
    return lg.System(
        coordinates=[s for trio in names for s in trio],
        particles=[lg.Particle(f"p{i}", 1, names[i]) for i in range(count)],
        constraints=constraints,
    )


@pytest.mark.parametrize(
    ("count", "redundant"),
    [(3, 0), (4, 0), (5, 1)],  # 5 points, 10 distances: only 3*5 - 6 = 9 are independent
)
def test_a_rigid_body_of_points_has_six_degrees_of_freedom(count: int, redundant: int) -> None:
    report = classify(_rigid_points(count))
    assert report.dof == 6  # textbook: 3 translations, 3 rotations
    assert report.particle_count is not None
    assert str(report.particle_count) == f"3N - k = 3*{count} - {3 * count - 6} = 6"
    assert len(report.redundant) == redundant


def test_no_particle_count_when_coordinates_are_not_particle_freedoms() -> None:
    assert classify(knife_edge()).particle_count is None  # no particles at all
    assert classify(lg.examples.compound_pendulum()).particle_count is None  # a rigid body


# -- redundancy, inconsistency, ranks at a state ------------------------------------------


def test_two_identical_constraints_are_redundant_and_the_rank_says_so() -> None:
    twice = lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        constraints=[lg.Holonomic(x**2 + y**2 - l**2), lg.Holonomic(x**2 + y**2 - l**2)],
    )
    report = classify(twice)
    assert report.redundant == ("constraints[1]",)
    assert (report.generic_rank, report.dof) == (1, 1)
    assert "redundant" in report.constraints[1].reason


def test_rank_and_residuals_at_a_state() -> None:
    report = classify(pendulum(), state={"x": 0.0, "y": -0.7})
    assert report.state_rank == 1 and report.state_residuals == (pytest.approx(0.0),)
    # At the pivot the rod's gradient (2x, 2y) vanishes: the rank drops there.
    at_pivot = classify(pendulum(), state={"x": 0.0, "y": 0.0})
    assert at_pivot.state_rank == 0 and at_pivot.state_residuals == (pytest.approx(-0.49),)


def test_project_state_moves_a_state_onto_the_constraints() -> None:
    fixed = project_state(pendulum(), {"x": 0.3, "y": -1.0, "x_dot": 1.0, "y_dot": 2.0})
    values = {s.name: v for s, v in fixed.items()}
    assert values["x"] ** 2 + values["y"] ** 2 == pytest.approx(0.49)
    assert values["x"] * values["x_dot"] + values["y"] * values["y_dot"] == pytest.approx(
        0, abs=1e-12
    )


@pytest.mark.parametrize(
    ("constraints", "match"),
    [
        ([lg.Holonomic(x), lg.Holonomic(x - 1)], r"inconsistent: no configuration satisfies"),
        (
            [lg.Holonomic(x), lg.Holonomic(y), lg.Holonomic(x + y - 1)],
            r"more constraints \(3\) than coordinates \(2\)",
        ),
        (
            [lg.VelocityConstraint(x_dot), lg.VelocityConstraint(x_dot - 1)],
            r"x_dot - 1 = 0 contradicts constraints\[0\]",
        ),
        ([lg.Holonomic(x - lg.t), lg.VelocityConstraint(x_dot)], r"no velocity satisfies them"),
    ],
)
def test_inconsistent_constraints_are_refused_by_name(constraints: list, match: str) -> None:
    with pytest.raises(ConstraintError, match=match) as caught:
        classify(lg.System(coordinates=[x, y], constraints=constraints))
    assert all(p.field.startswith("constraints[") for p in caught.value.problems)


def test_the_report_as_plain_values() -> None:
    rolling = velocity_only([x, phi], x_dot - r * phi_dot, parameters={r: 0.2})
    (entry,) = [c.as_dict() for c in classify(rolling).constraints]
    assert entry["kind"] == "velocity" and entry["holonomic"] is True
    assert sp.sympify(entry["integrated"]) - (x - r * phi) == 0 or sp.sympify(
        entry["integrated"]
    ).equals(x - r * phi)
