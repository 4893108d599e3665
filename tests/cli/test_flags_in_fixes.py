"""The command line words every fix in its flags: ``--initial x=VALUE``, ``--t-end``,
``--method DOP853``, never a Python keyword."""

from __future__ import annotations

import io
import re

import pytest

from lagrangian.cli.main import main

NO_INITIAL = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"
PYTHON_KEYWORD = re.compile(r"\b(t_span|initial|max_steps|method|rtol)=")


def run(capsys: pytest.CaptureFixture[str], monkeypatch, argv: list[str]) -> tuple[int, str]:
    monkeypatch.setattr("sys.stdin", io.StringIO(NO_INITIAL))
    code = main(argv)
    return code, capsys.readouterr().err


def test_a_missing_initial_value_and_end_time_are_flags(capsys, monkeypatch) -> None:
    code, err = run(capsys, monkeypatch, ["simulate", "-", "--out", "-"])
    assert code == 2, err
    assert "pass --initial x=VALUE" in err and "pass --initial x_dot=VALUE" in err
    assert "pass the end time, --t-end, or give the model one" in err
    assert not PYTHON_KEYWORD.search(err), err


def test_an_option_that_does_not_apply_names_the_flags(capsys, monkeypatch) -> None:
    argv = ["simulate", "simple_pendulum", "--method", "RK4", "--atol", "1e-9", "--out", "-"]
    code, err = run(capsys, monkeypatch, argv)
    assert code == 2, err
    assert "--atol: atol steers the adaptive methods" in err
    assert "remove --atol, or choose an adaptive method such as --method DOP853" in err


def test_a_bad_set_and_about_name_their_flags(capsys, monkeypatch) -> None:
    code, err = run(capsys, monkeypatch, ["derive", "simple_pendulum", "--set", "m=abc"])
    assert code == 2 and "--set m=abc: expected NAME=NUMBER — e.g. --set m=0.5" in err, err
    code, err = run(capsys, monkeypatch, ["analyze", "simple_pendulum", "--about", "theta"])
    assert code == 2 and "--about theta: expected NAME=NUMBER" in err, err
    assert "e.g. --about theta=0.5,phi_dot=2" in err


@pytest.mark.parametrize(
    ("flags", "said"),
    [
        (
            ["--t-end", "100", "--max-steps", "50"],
            "the step budget of 50 steps is used up — pass --max-steps 500 to allow more steps.",
        ),
        (
            ["--t-end", "1000", "--max-wall-time", "1e-9"],
            "s is used up after 1 steps — pass a larger --max-wall-time.",
        ),
    ],
)
def test_a_run_over_its_budget_names_the_flag(capsys, tmp_path, flags, said) -> None:
    out = tmp_path / "run.csv"
    argv = ["simulate", "examples/simple_pendulum", *flags, "--out", str(out)]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 1, err
    assert said in err and "rows, up to t =" in err, err
    assert "max_steps" not in err and "max_wall_time" not in err, err
    assert out.exists()  # the rows computed before the budget ran out
