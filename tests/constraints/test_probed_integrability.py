"""Integrability decided at random points for forms too large for symbolic wedge products:
the same verdicts as the symbolic path on the textbook forms (the probed path forced on them
by a threshold of 0), and a bicycle's no-slip constraints classified in seconds."""

from __future__ import annotations

import pytest
import sympy as sp
from constraint_systems import knife_edge, rolling_disc

import lagrangian as lg
from lagrangian.constraints import classify, integrability

x, y, z = sp.symbols("x y z")
x_dot, y_dot, z_dot = sp.symbols("x_dot y_dot z_dot")


def velocity_only(coordinates: list[sp.Symbol], *expressions: sp.Expr) -> lg.System:
    return lg.System(
        coordinates=coordinates, constraints=[lg.VelocityConstraint(e) for e in expressions]
    )


@pytest.fixture
def probed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(integrability, "LARGE_COEFFICIENT", 0)


CASES = {
    "exact (the circle)": (velocity_only([x, y], x * x_dot + y * y_dot), [True], None),
    "with a factor (the ray)": (velocity_only([x, y], y * x_dot - x * y_dot), [True], None),
    "knife edge": (knife_edge(), [False], False),
    "rolling disc": (rolling_disc(), [False, False], False),
    "integrable only as a set": (
        velocity_only([x, y, z], z_dot - y * x_dot, y_dot),
        [True, True],
        True,
    ),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_the_probed_verdicts_are_the_symbolic_ones(case: str, probed: None) -> None:
    system, holonomic, integrable_set = CASES[case]
    report = classify(system)
    assert [c.holonomic for c in report.constraints] == holonomic
    assert report.integrable_set is integrable_set  # as tests/constraints/test_classify.py


def test_a_probed_twist_names_a_component(probed: None) -> None:
    (blade,) = classify(knife_edge()).constraints
    assert "non-holonomic" in blade.reason and "at a random point" in blade.reason
    assert "dx^dy^dphi" in blade.reason  # the only component of omega ^ d omega


@pytest.mark.slow
def test_the_bicycle_no_slip_constraints_are_non_holonomic() -> None:
    report = classify(lg.examples.whipple_bicycle())
    kinds = {c.name: (c.kind, c.holonomic) for c in report.constraints}
    assert sum(1 for kind, holonomic in kinds.values() if kind == "velocity") == 4
    assert not any(h for kind, h in kinds.values() if kind == "velocity")
    assert report.integrable_set is False
    assert (report.dof, report.independent_velocities) == (7, 3)
