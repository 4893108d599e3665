"""The simulate command's flags for what the Python keywords do, and messages in flags."""

import pytest

from lagrangian.cli.main import main

CARTESIAN_PENDULUM = """name: Cartesian pendulum
coordinates: [x, y]
parameters: {m: 1, g: 9.81, l: 1}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: x**2 + y**2 - l**2}
initial: {x: 0.6, y: -0.9, x_dot: 0, y_dot: 0}
"""


def run(capsys, *argv):
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_project_initial_is_a_flag_and_the_message_names_it(tmp_path, capsys):
    model = tmp_path / "pendulum.yaml"
    model.write_text(CARTESIAN_PENDULUM)
    out = str(tmp_path / "run.csv")
    code, _, error = run(capsys, "simulate", str(model), "--t-end", "1", "--out", out)
    assert code == 2 and "pass --project-initial" in error and "project_state" not in error
    code, _, error = run(
        capsys, "simulate", str(model), "--t-end", "1", "--out", out, "--project-initial"
    )
    assert code == 0, error


def test_the_step_and_the_budget_flags(tmp_path, capsys):
    out = str(tmp_path / "run.csv")
    code, _, error = run(
        capsys, "simulate", "simple_pendulum", "--method", "RK4", "--dt", "1e-300", "--out", out
    )
    assert code == 2 and "--dt" in error and "--max-steps" in error
    code, _, error = run(
        capsys, "simulate", "simple_pendulum", "--t-end", "100", "--max-steps", "20", "--out", out
    )
    assert code == 1 and "written to" in error
    assert "the step budget of 20 steps is used up — pass --max-steps 200 to allow" in error
    code, _, _ = run(
        capsys, "simulate", "simple_pendulum", "--method", "RK4", "--dt", "0.01", "--out", out
    )
    assert code == 0


def test_phase_names_a_coordinate_of_the_plot(tmp_path, capsys):
    out, plot = str(tmp_path / "run.csv"), str(tmp_path / "plot.svg")
    code, _, error = run(
        capsys, "simulate", "double_pendulum", "--t-end", "1", "--out", out, "--phase", "psi"
    )
    assert code == 2 and "'psi' is not a coordinate" in error and "add --plot" in error
    code, _, error = run(
        capsys,
        "simulate",
        "double_pendulum",
        *("--t-end", "1", "--out", out, "--plot", plot, "--phase", "phi"),
    )
    assert code == 0, error
    assert (
        "φ" in (tmp_path / "plot.svg").read_text() or "phi" in (tmp_path / "plot.svg").read_text()
    )


def test_the_help_lists_every_method(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = capsys.readouterr().out
    for method in ("RK45", "DOP853", "Radau", "RK4", "variational"):
        assert method in text
