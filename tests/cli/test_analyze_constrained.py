"""``lagrangian analyze`` on constrained models: --about checked against the constraints (exit
2 with the residual and the option that projects), --project, and --format text|latex|json."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

from lagrangian.cli.main import main

PENDULUM = """\
name: cartesian_pendulum
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, l: 1.0}
gravity: [0, -g]
particles:
  - {name: bob, mass: m, position: [x, y]}
constraints:
  - {holonomic: "x**2 + y**2 - l**2", name: rod}
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture
def pendulum(tmp_path: Path) -> str:
    path = tmp_path / "cartesian_pendulum.yaml"
    path.write_text(PENDULUM)
    return str(path)


def test_about_off_the_rod_exits_2_naming_the_constraint_and_the_fix(
    capsys: pytest.CaptureFixture[str], pendulum: str
) -> None:
    code, out, err = run(capsys, "analyze", pendulum, "--about", "x=0.6,y=-0.7")
    assert code == 2 and out == ""
    assert "'rod' (constraints[0])" in err and "position level" in err
    assert "-0.15" in err  # 0.36 + 0.49 - 1
    assert "--project" in err and "Traceback" not in err


def test_project_moves_the_state_onto_the_rod(
    capsys: pytest.CaptureFixture[str], pendulum: str
) -> None:
    code, out, err = run(capsys, "analyze", pendulum, "--about", "x=0,y=-0.9", "--project")
    assert code == 0, err
    linear = json.loads(out)["linearization"]
    assert float(sp.sympify(linear["state"]["y"])) == pytest.approx(-1.0)
    assert [float(sp.sympify(w)) for w in linear["frequencies"]] == pytest.approx([9.81**0.5])
    assert linear["eliminated"] == ["y", "y_dot"]


def test_the_rolling_disc_from_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "analyze", "examples/rolling_disc", "--about", "phi_dot=5")
    assert code == 2 and "velocity level" in err and "--project" in err
    code, out, err = run(
        capsys, "analyze", "examples/rolling_disc", "--about", "phi_dot=5,x_dot=1.5"
    )
    assert code == 0, err
    document = json.loads(out)
    assert (document["dof"], document["configuration_dimension"]) == (3, 5)
    assert document["linearization"]["growth_rates"] == []  # 5 rad/s > sqrt(g/(3 r)) = 3.3


def test_text_format_explains_the_degrees_of_freedom(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "analyze", "examples/rolling_disc", "--format", "text")
    assert code == 0, err
    first = out.splitlines()[0]
    assert first.startswith("rolling_disc: 5 coordinates")
    assert "3 independent velocities: dof = 3" in first
    assert "Cyclic coordinates" in out and "momentum not conserved (constraint)" in out
    assert "no Hamiltonian in the usual sense" in out


def test_latex_format(capsys: pytest.CaptureFixture[str], pendulum: str) -> None:
    code, out, err = run(capsys, "analyze", pendulum, "--format", "latex")
    assert code == 0, err
    assert out.startswith(r"\begin{align*}") and "H &=" in out and "(stable)" in out


def test_json_stays_the_default(capsys: pytest.CaptureFixture[str], pendulum: str) -> None:
    code, out, _ = run(capsys, "analyze", pendulum)
    assert code == 0 and json.loads(out)["dof"] == 1
    with pytest.raises(SystemExit, match="2"):  # argparse refuses it, exit code 2
        main(["analyze", pendulum, "--format", "yaml"])
    assert "invalid choice" in capsys.readouterr().err
