"""MathML output: well-formed XML, dotted velocities, one row per step."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

import lagrangian as lg
from lagrangian.render import equations_mathml, steps_mathml

NS = "{http://www.w3.org/1998/Math/MathML}"


@pytest.mark.parametrize(
    "name",
    [
        "simple_pendulum",
        "double_pendulum",
        "rc_rl_circuit",
        "charged_particle_em",
        "mass_spring_damper",
    ],
)
def test_mathml_is_well_formed_with_one_row_per_equation(name: str) -> None:
    eom = lg.derive(lg.examples.get(name)())
    root = ET.fromstring(equations_mathml(eom))
    assert root.tag == f"{NS}math"
    assert len(root.findall(f".//{NS}mtr")) == len(eom.coordinates)
    steps = ET.fromstring(steps_mathml(eom))
    expected_rows = 1 + sum(
        4 + (s.dF_dvelocity != 0) + (s.generalized_force != 0) for s in eom.steps
    )
    assert len(steps.findall(f"{NS}mtable/{NS}mtr")) == expected_rows


def test_velocities_and_accelerations_are_dotted() -> None:
    text = equations_mathml(lg.derive(lg.examples.simple_pendulum()))
    assert '<mover accent="true"><mi>&#952;</mi><mo>&#168;</mo></mover>' in text  # θ̈
    assert "dot" not in text and "lgdotted" not in text
