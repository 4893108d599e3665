"""``lagrangian analyze`` of a cart-pole with its horizontal force F given as 0.0: the text and
the JSON decide at that value, as the Python report does
(tests/analysis/test_cart_pole_at_values.py): the hanging pole is stable, the upright one
unstable, both a family along the track x, and for F != 0 there is no rest."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lagrangian.cli.main import main

CART_POLE = """\
name: cart_pole
coordinates: [x, theta]
parameters: {M: 1.0, m: 0.1, l: 0.5, g: 9.81, F: 0.0}
particles:
  - {name: cart, mass: M, position: ["x", "0"]}
  - {name: bob, mass: m, position: ["x + l*sin(theta)", "-l*cos(theta)"]}
gravity: [0, -g]
generalized_forces: {x: F}
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture
def cart_pole(tmp_path: Path) -> str:
    path = tmp_path / "cart_pole.yaml"
    path.write_text(CART_POLE)
    return str(path)


def test_the_text_lists_the_hanging_and_the_upright_pole_at_f_zero(
    capsys: pytest.CaptureFixture[str], cart_pole: str
) -> None:
    code, out, err = run(capsys, "analyze", cart_pole, "--format", "text", "--search-degree", "0")
    assert code == 0, err
    rest = out.split("Equilibria:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert rest[0].startswith("  theta = 0, x free: stable (")
    assert rest[1].startswith("  theta = pi, x free: unstable (")
    assert all(line.endswith("exists when F = 0") for line in rest[:2])
    assert "for F ≠ 0: the static forces [F] do not depend on the coordinates: no rest" in rest[2]
    assert "momentum conserved when F = 0" in out
    assert "dh/dt = F*x_dot: conserved when F = 0, as here" in out
    assert "normal_modes" not in out  # nothing under "Not computed"


def test_the_json_gives_both_poles_with_their_condition_and_the_swing(
    capsys: pytest.CaptureFixture[str], cart_pole: str
) -> None:
    code, out, err = run(capsys, "analyze", cart_pole, "--format", "json", "--search-degree", "0")
    assert code == 0, err
    document = json.loads(out)
    found = [(e["state"], e["stable"], e["free"], e["condition"]) for e in document["equilibria"]]
    assert found == [
        ({"x": "x", "theta": "0"}, True, ["x"], "Eq(F, 0)"),
        ({"x": "x", "theta": "pi"}, False, ["x"], "Eq(F, 0)"),
    ]
    assert document["energy_conserved"] is True
    assert document["energy"]["condition"] == "Eq(F, 0)"
    assert document["cyclic_coordinates"][0]["condition"] == "Eq(F, 0)"
    assert document["normal_modes"]["about"] == {"x": "0", "theta": "0"}
    assert "normal_modes" not in document["failures"]


def test_a_force_set_on_the_command_line_leaves_the_cart_no_rest(
    capsys: pytest.CaptureFixture[str], cart_pole: str
) -> None:
    code, out, err = run(
        capsys, "analyze", cart_pole, "--format", "json", "--search-degree", "0", "--set", "F=2"
    )
    assert code == 0, err
    document = json.loads(out)
    assert document["equilibria"] == [] and document["energy_conserved"] is False
    assert document["cyclic_coordinates"][0]["conserved"] is False
    assert "No stable equilibrium" in document["failures"]["normal_modes"]
