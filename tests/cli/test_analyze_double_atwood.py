"""A double Atwood machine (a standard exercise: Goldstein, Classical Mechanics, ch. 1;
Taylor, Classical Mechanics, ch. 7): m1 hangs from a fixed pulley against a light pulley holding m2
and m3.  Its static forces are constants, g (m1 - m2 - m3) and g (m2 - m3): with the masses
balanced (m1 = m2 + m3 and m2 = m3, here m1 = 2, m2 = m3 = 1) every configuration is at rest,
a neutral family; with any other masses there is no rest at all.  ``analyze`` says so at the
values given, names the relations between the masses (not only their values), and says what
holds for other masses."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lagrangian.cli.main import main

DOUBLE_ATWOOD = """\
name: double Atwood machine
coordinates: [x, y]
parameters: {m1: 3.0, m2: 1.0, m3: 2.0, g: 9.81, l1: 2.0, l2: 1.0}
particles:
  - {name: A, mass: m1, position: ["0", "-x"]}
  - {name: B, mass: m2, position: ["1", "-(l1 - x + y)"]}
  - {name: C, mass: m3, position: ["1.2", "-(l1 - x + l2 - y)"]}
gravity: [0, -g]
"""


@pytest.fixture
def model(tmp_path: Path) -> str:
    path = tmp_path / "double_atwood.yaml"
    path.write_text(DOUBLE_ATWOOD)
    return str(path)


def analyze(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(["analyze", *argv]) == 0
    return capsys.readouterr().out


def test_balanced_masses_rest_everywhere_as_a_neutral_family(
    model: str, capsys: pytest.CaptureFixture[str]
) -> None:
    balanced = ("--set", "m1=2", "--set", "m3=1")
    text = analyze(capsys, model, *balanced, "--format", "text")
    assert "every configuration (x, y free): neutral" in text
    assert "exists when m2 = m3, m1 = m2 + m3" in text
    assert "for m2 ≠ m3 or m1 ≠ m2 + m3: the static forces" in text and "no rest" in text
    assert "9.81000000000000" not in text
    document = json.loads(analyze(capsys, model, *balanced, "--format", "json"))
    (family,) = document["equilibria"]
    assert family["free"] == ["x", "y"] and family["stable"] is None
    latex = analyze(capsys, model, *balanced, "--format", "latex")
    assert r"x,\ y\ \text{free}\ \text{(neutral)}" in latex


def test_unbalanced_masses_never_rest(model: str, capsys: pytest.CaptureFixture[str]) -> None:
    text = analyze(capsys, model, "--format", "text")
    assert "do not depend on the coordinates: no rest" in text
    assert json.loads(analyze(capsys, model, "--format", "json"))["equilibria"] == []
