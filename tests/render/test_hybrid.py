"""derive writes a hybrid model's jumps in every format: the impacts on its unilateral
constraints (with their coefficients of restitution) and its transitions (guard, direction,
condition, reset), as the model file gives them."""

from __future__ import annotations

import json
import xml.dom.minidom

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.symbolic.expressions import parse_expression


def derived(capsys: pytest.CaptureFixture[str], name: str, fmt: str) -> str:
    main(["derive", f"examples/{name}", "--format", fmt])
    return capsys.readouterr().out


def test_the_walkers_heel_strike_in_json_is_the_models_reset(capsys) -> None:
    # the simplest walker's heel strike (Garcia et al. 1998, eq. 4), as its model file writes it
    theta, phi, theta_dot = sp.symbols("theta phi theta_dot")
    expected = {
        "theta": -theta,
        "phi": -2 * theta,
        "theta_dot": sp.cos(2 * theta) * theta_dot,
        "phi_dot": sp.cos(2 * theta) * (1 - sp.cos(2 * theta)) * theta_dot,
    }
    (strike,) = json.loads(derived(capsys, "simplest_walker", "json"))["transitions"]
    assert strike["name"] == "heel_strike" and strike["direction"] == "rising"
    assert strike["guard"] == "phi - 2*theta" and strike["when"] == "theta < 0"
    names = {s.name: s for s in (theta, phi, theta_dot, sp.Symbol("phi_dot"))}
    assert {
        key: sp.simplify(parse_expression(value, names, field=key) - expected[key]) == 0
        for key, value in strike["reset"].items()
    } == dict.fromkeys(expected, True)


def test_impacts_in_text_latex_and_json(capsys) -> None:
    text = derived(capsys, "newtons_cradle", "text")
    assert "  first: -x1 + x2 >= 0, e = 1\n  second: -x2 + x3 >= 0, e = 1" in text
    document = json.loads(derived(capsys, "bouncing_ball", "json"))
    assert document["restitution"] == {"floor": "e"} and "transitions" not in document
    latex = derived(capsys, "newtons_cradle", "latex")
    assert r"\text{first: }- x_{1} + x_{2} &\geq 0,\ e = 1" in latex


def test_the_mathml_of_a_transition_is_well_formed(capsys) -> None:
    mathml = derived(capsys, "simplest_walker", "mathml")
    for table in mathml.strip().splitlines():
        xml.dom.minidom.parseString(table)  # theta < 0 once came out as a bare "<"
    assert "<msup><mi>&#952;</mi><mo>+</mo></msup>" in mathml  # theta+ = -theta


def test_a_model_without_jumps_writes_none(capsys) -> None:
    assert "transitions" not in json.loads(derived(capsys, "double_pendulum", "json"))
    assert "Impacts" not in derived(capsys, "double_pendulum", "text")


def test_an_impact_not_allowed_is_said() -> None:
    from lagrangian.render.hybrid import hybrid_text

    y = sp.Symbol("y")
    system = lg.System(
        coordinates=[y],
        kinetic=sp.Symbol("y_dot") ** 2 / 2,
        potential=y,
        constraints=[lg.Unilateral(y, name="floor")],
    )
    assert "floor: y >= 0, no impact allowed" in hybrid_text(system)
