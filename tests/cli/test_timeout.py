"""``--timeout`` bounds any command's wall time: work that grows without end (an expression
SymPy cannot settle) stops with a message and exit 1, before or after the command name."""

import io
import time

import pytest

from lagrangian.cli.main import LONG_RUNNING, main, time_limit
from lagrangian.errors import TimeLimitError

# 200 links (the largest the command line builds): a legitimate system whose derivation and
# printing take several seconds.
SLOW = "examples/n_link_pendulum:200"


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


def test_an_error_the_interruption_turned_into_is_still_the_timeout(capsys, monkeypatch):
    """The timer's exception can land in C code that reports another error instead (SymPy's
    cache: "SystemError: ... returned a result with an exception set"): past the deadline,
    that error is the timeout's, not an internal error."""

    def interrupted(args):
        try:
            time.sleep(5)  # the timer fires here
        except Exception as error:
            raise SystemError("returned a result with an exception set") from error
        return ""

    monkeypatch.setattr("lagrangian.cli.main.run", interrupted)
    assert main(["--timeout", "0.2", "derive", "simple_pendulum"]) == 1
    error = capsys.readouterr().err
    assert "stopped after --timeout 0.2 s" in error and "internal error" not in error


@pytest.mark.parametrize("command", LONG_RUNNING)
def test_a_long_running_command_has_no_command_time_limit(command, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_TIME_LIMIT", "0.1")
    with time_limit(None, command):
        time.sleep(0.3)  # past the environment's limit: serve and sweep run on
    stopped = pytest.raises(TimeLimitError, match=r"the command stopped .* --timeout SECONDS")
    with stopped, time_limit(None, "derive"):
        time.sleep(0.3)


def test_an_explicit_timeout_still_bounds_a_long_running_command():
    stopped = pytest.raises(TimeLimitError, match=r"stopped after --timeout 0\.1 s")
    with stopped, time_limit(0.1, "sweep"):
        time.sleep(0.5)
