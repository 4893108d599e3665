"""The names ``lagrangian analyze`` introduces never collide with the model's.

A bead on a hoop spinning at ``omega`` about its vertical diameter (Taylor, Classical
Mechanics, example 7.6 and §5 on small oscillations): off-centre equilibria at
cos(theta) = g / (R omega^2) for omega^2 > g/R, oscillating there at the frequency
Omega = sqrt(omega^2 - g^2 / (R^2 omega^2)).  The model's omega is the spin; the frequency
must not be written ``omega = ...omega...``.  Likewise a height called ``h`` pushes the
energy function off ``h``, and a parameter ``p_theta`` the momentum off ``p_theta``.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

from lagrangian.cli.main import main

HOOP = """\
name: bead on a spinning hoop
coordinates: [theta]
parameters: {m: 1.0, R: 1.0, g: 9.81, omega: 5.0}
kinetic: m*R**2*(theta_dot**2 + omega**2*sin(theta)**2)/2
potential: -m*g*R*cos(theta)
"""


def analyze(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, form: str) -> str:
    path = tmp_path / "model.yaml"
    path.write_text(text)
    assert main(["analyze", str(path), "--format", form]) == 0
    return capsys.readouterr().out


def test_the_frequency_of_a_hoop_spinning_at_omega_is_called_omega_capital(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = analyze(tmp_path, capsys, HOOP, "text")
    assert "Omega = sqrt(R**2*omega**4 - g**2)/(R*omega)" in text
    assert "\n  omega = " not in text and "det(K - Omega^2 M)" in text
    latex = analyze(tmp_path, capsys, HOOP, "latex")
    assert r"\Omega &\in" in latex and r"\omega &\in" not in latex
    document = json.loads(analyze(tmp_path, capsys, HOOP, "json"))
    assert document["symbols"]["frequency"] == "Omega"
    (frequency,) = document["normal_modes"]["frequencies"]
    R, g, omega = sp.symbols("R g omega", positive=True)
    expected = sp.sqrt(omega**2 - g**2 / (R**2 * omega**2))  # the textbook's frequency
    value = sp.sympify(frequency, locals={"R": R, "g": g, "omega": omega})
    assert sp.simplify(value - expected) == 0


def test_a_height_h_and_a_parameter_p_theta_push_the_energy_and_momentum_names_aside(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    model = HOOP.replace("omega", "h").replace("g: 9.81", "g: 9.81, p_theta: 0.0")
    model = model.replace("potential: -m*g*R*cos(theta)", "potential: -m*g*R*cos(theta) + p_theta")
    text = analyze(tmp_path, capsys, model, "text")
    assert "h_1 = " in text and "dh_1/dt = 0" in text and "\n  h = " not in text
    assert "P_theta = R**2*m*theta_dot" in text
    assert "P_theta**2/(2*R**2*m)" in text  # the Hamiltonian in the renamed momentum
    document = json.loads(analyze(tmp_path, capsys, model, "json"))
    assert document["symbols"]["energy_function"] == "h_1"
    assert document["symbols"]["momenta"] == {"theta": "P_theta"}
    names = [c["name"] for c in document["conserved_quantities"]]
    assert "h_1" in names and "h" not in names


def test_a_model_without_collisions_keeps_the_textbook_names(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    model = HOOP.replace("omega", "w")
    document = json.loads(analyze(tmp_path, capsys, model, "json"))
    assert document["symbols"] == {
        "energy_function": "h",
        "hamiltonian": "H",
        "frequency": "omega",
        "effective_potential": "V_eff",
        "momenta": {"theta": "p_theta"},
    }
