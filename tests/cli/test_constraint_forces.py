"""``lagrangian derive`` gives each multiplier solved for the state, in every format.

A uniform cylinder rolling without slipping down an incline of angle alpha (Goldstein,
Classical Mechanics, §2.4 works the hoop; for a uniform cylinder the same steps give): it
accelerates at 2 g sin(alpha) / 3 and friction holds it back with m g sin(alpha) / 3; the
multiplier of x - r phi = 0 is that force (its sign: lambda dh/dx = lambda on x).  A ball
resting on the floor y >= 0 presses with its weight: lambda = m g.  A rolling coin (five
coordinates, dense M) is left to the augmented system and says so.
"""

from __future__ import annotations

import json

import pytest
import sympy as sp

from lagrangian.cli.main import main


def derive(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(["derive", *argv]) == 0
    return capsys.readouterr().out


def test_the_friction_on_a_rolling_cylinder_is_a_third_of_its_weight_along_the_slope(
    capsys: pytest.CaptureFixture[str],
) -> None:
    text = derive(capsys, "cylinder_on_incline")
    assert "Constraint forces (each multiplier solved for the state):" in text
    assert "  lambda_1 = -g*m*sin(alpha)/3" in text
    document = json.loads(derive(capsys, "cylinder_on_incline", "--format", "json"))
    solved = document["constraint_forces"]["solved"]
    m, g, alpha = sp.symbols("m g alpha")
    assert sp.simplify(sp.sympify(solved["lambda_1"]) + m * g * sp.sin(alpha) / 3) == 0
    latex = derive(capsys, "cylinder_on_incline", "--format", "latex")
    assert r"\lambda_{1} &= - \frac{g m \sin{\left(\alpha \right)}}{3}" in latex


def test_a_ball_at_rest_on_the_floor_presses_with_its_weight(
    capsys: pytest.CaptureFixture[str],
) -> None:
    document = json.loads(derive(capsys, "bouncing_ball", "--format", "json"))
    assert document["constraint_forces"]["solved"] == {"lambda_1": "g*m"}


def test_a_rolling_coin_says_why_its_forces_are_not_solved(
    capsys: pytest.CaptureFixture[str],
) -> None:
    text = derive(capsys, "rolling_coin")
    assert "not solved symbolically" in text
    document = json.loads(derive(capsys, "rolling_coin", "--format", "json"))
    assert document["constraint_forces"]["solved"] is None
    assert "augmented system" in document["constraint_forces"]["reason"]


def test_analyze_gives_the_same_friction_in_text_latex_and_json(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["analyze", "cylinder_on_incline", "--format", "text"]) == 0
    text = capsys.readouterr().out
    assert "Constraint forces (each multiplier solved for the state):\n" in text
    assert "  lambda_1 = -g*m*sin(alpha)/3\n" in text
    assert main(["analyze", "cylinder_on_incline", "--format", "latex"]) == 0
    assert r"\lambda_{1} &= - \frac{g m \sin{\left(\alpha \right)}}{3}" in capsys.readouterr().out
    assert main(["analyze", "cylinder_on_incline", "--format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["constraint_forces"] == {
        "solved": {"lambda_1": "-g*m*sin(alpha)/3"},
        "reason": "",
    }
    assert main(["analyze", "double_pendulum", "--format", "json"]) == 0
    assert "constraint_forces" not in json.loads(capsys.readouterr().out)  # no constraints
