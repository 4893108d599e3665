"""simulate --initial NAME=VALUE and --keep-failed, analyze's format by where its output
goes, units in derive's JSON and on the pictures, and the progress bar of an animation."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import pytest

from lagrangian.cli.main import analysis_format, main

PENDULUM = """\
name: Pendulum with units
coordinates: [theta]
parameters: {m: 1.0, l: 0.5, g: 9.81}
units: {m: kg, l: m, theta: rad, g: m/s^2}
kinetic: m*l**2*theta_dot**2/2
potential: -m*g*l*cos(theta)
initial: {theta: 1.0, theta_dot: 0.0}
simulate: {t_end: 1}
"""

RUNAWAY = """\
coordinates: [x]
kinetic: "x_dot**2/2"
potential: "-x**4"
initial: {x: 1.0, x_dot: 0.0}
simulate: {t_end: 5.0}
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture
def pendulum(tmp_path: Path) -> Path:
    path = tmp_path / "pendulum.yaml"
    path.write_text(PENDULUM)
    return path


def test_initial_sets_coordinates_and_velocities(
    capsys: pytest.CaptureFixture[str], pendulum: Path
) -> None:
    argv = ["simulate", str(pendulum), "--samples", "3", "--initial", "theta=0.25"]
    code, out, err = run(capsys, *argv, "--initial", "theta_dot=-1.5")
    assert code == 0, err
    header, first, *_ = out.splitlines()
    assert header == "t,theta,theta_dot,energy"
    assert [float(v) for v in first.split(",")[:3]] == [0.0, 0.25, -1.5]


@pytest.mark.parametrize(
    ("item", "message"),
    [
        (
            "thetta=1",
            "'thetta' is not a coordinate or velocity of the system — did you mean 'theta'?",
        ),
        ("g=9.8", "'g' is a parameter — set it with --set g=VALUE"),
        ("theta=abc", "expected NAME=NUMBER — e.g. --initial theta=0.5"),
        ("theta", "expected NAME=NUMBER"),
        ("theta=nan", "expected NAME=NUMBER"),
    ],
)
def test_a_bad_initial_is_bad_input_naming_the_flag(
    capsys: pytest.CaptureFixture[str], pendulum: Path, item: str, message: str
) -> None:
    code, out, err = run(capsys, "simulate", str(pendulum), "--initial", item)
    assert code == 2 and out == ""
    assert f"--initial {item}: {message}" in err and "Traceback" not in err


def test_every_bad_initial_is_reported_at_once(
    capsys: pytest.CaptureFixture[str], pendulum: Path
) -> None:
    code, _, err = run(capsys, "simulate", str(pendulum), "--initial", "a=1", "--initial", "b=2")
    assert code == 2 and "(2 problems)" in err


def test_a_failed_run_draws_its_rows_only_with_keep_failed(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    model, out = tmp_path / "runaway.yaml", tmp_path / "runaway.csv"
    plot, movie = tmp_path / "runaway.png", tmp_path / "runaway.gif"
    model.write_text(RUNAWAY)  # x_ddot = 4 x**3 blows up near t = 0.93
    pictures = ["--plot", str(plot), "--animate", str(movie)]
    argv = ["simulate", str(model), "--samples", "51", "--out", str(out), *pictures]
    code, _, err = run(capsys, *argv)
    assert code == 1 and not plot.exists() and not movie.exists()
    assert "add --keep-failed for them" in err
    rows = out.read_text().splitlines()[1:]
    code, _, err = run(capsys, *argv, "--keep-failed")
    assert code == 1 and "Integration failed at t = " in err  # still a failure for scripts
    assert f"Plot written to {plot}. Animation written to {movie}." in err
    assert plot.read_bytes()[:4] == b"\x89PNG" and movie.read_bytes()[:3] == b"GIF"
    assert out.read_text().splitlines()[1:] == rows  # the same rows as without the flag
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "runaway.csv",
        "runaway.gif",
        "runaway.png",
        "runaway.yaml",
    ]


def test_keep_failed_without_pictures_changes_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    model = tmp_path / "runaway.yaml"
    model.write_text(RUNAWAY)
    code, out, err = run(capsys, "simulate", str(model), "--keep-failed")
    assert code == 1 and out.startswith("t,x,x_dot,energy") and "--keep-failed" not in err


def test_analyze_prints_json_to_a_pipe_and_text_to_a_terminal(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    code, out, _ = run(capsys, "analyze", "examples/simple_pendulum")
    assert code == 0 and json.loads(out)["dof"] == 1  # scripts keep reading JSON
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    code, out, _ = run(capsys, "analyze", "examples/simple_pendulum")
    assert code == 0 and out.startswith("simple_pendulum: 1 coordinate")
    code, out, _ = run(capsys, "analyze", "examples/simple_pendulum", "--format", "json")
    assert json.loads(out)["dof"] == 1  # asked for: JSON at a terminal too


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_analysis_format_follows_the_output() -> None:
    assert analysis_format(_Terminal()) == "text"
    assert analysis_format(io.StringIO()) == "json"
    closed = io.StringIO()
    closed.close()
    assert analysis_format(closed) == "json" and analysis_format(None) == "json"


def test_derive_json_gives_the_units_of_a_model_that_has_them(
    capsys: pytest.CaptureFixture[str], pendulum: Path
) -> None:
    code, out, _ = run(capsys, "derive", str(pendulum), "--format", "json")
    document = json.loads(out)
    assert code == 0
    assert document["units"] == {"m": "kg", "l": "m", "theta": "rad", "g": "m/s^2"}
    code, out, _ = run(capsys, "derive", "examples/simple_pendulum", "--format", "json")
    assert "units" not in json.loads(out)  # unchanged where the model has none


def test_a_bad_unit_is_bad_input(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(PENDULUM.replace("theta: rad", "omega: rad"))
    code, _, err = run(capsys, "derive", str(path))
    assert code == 2 and "units.omega (line 4, column 22): 'omega' is not a coordinate" in err


def test_the_csv_header_stays_the_names(capsys: pytest.CaptureFixture[str], pendulum: Path) -> None:
    code, out, _ = run(capsys, "simulate", str(pendulum), "--samples", "2")
    assert code == 0 and out.splitlines()[0] == "t,theta,theta_dot,energy"


def test_an_animation_shows_its_frames_on_a_progress_bar(
    capsys: pytest.CaptureFixture[str], pendulum: Path, tmp_path: Path
) -> None:
    movie = tmp_path / "pendulum.gif"
    argv = ["simulate", str(pendulum), "--samples", "8", "--out", str(tmp_path / "p.csv")]
    code, _, err = run(capsys, *argv, "--animate", str(movie))
    assert code == 0 and "frame" not in err  # standard error is not a terminal here
    code, _, err = run(capsys, *argv, "--animate", str(movie), "--progress")
    assert code == 0 and err.rstrip().endswith("100%  frame 8")
    assert "[###############...............]  50%  frame 4" in err
