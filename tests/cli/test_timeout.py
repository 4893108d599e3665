"""``--timeout`` bounds any command's wall time: work that grows without end (an expression
SymPy cannot settle) stops with a message and exit 1, before or after the command name."""

import io

import pytest

from lagrangian.cli.main import main

# 150 links: a legitimate system whose derivation takes far longer than a second.
SLOW = "examples/n_link_pendulum:150"


@pytest.mark.parametrize(
    "argv", [["--timeout", "1", "derive", SLOW], ["derive", SLOW, "--timeout", "1"]]
)
def test_a_command_past_its_time_stops_with_a_message(argv, capsys):
    assert main(argv) == 1
    error = capsys.readouterr().err
    assert "stopped after --timeout 1 s" in error and "internal error" not in error


def test_a_timeout_that_is_not_positive_is_bad_input(capsys, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO("coordinates: [x]\nkinetic: x_dot**2\n"))
    assert main(["derive", "-", "--timeout", "0"]) == 2
    assert "--timeout" in capsys.readouterr().err


def test_a_command_within_its_time_is_unaffected(capsys, monkeypatch):
    model = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"
    monkeypatch.setattr("sys.stdin", io.StringIO(model))
    assert main(["derive", "-", "--timeout", "60"]) == 0
    assert "x + x_ddot = 0" in capsys.readouterr().out
