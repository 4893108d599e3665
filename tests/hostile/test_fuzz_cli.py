"""Hypothesis fuzz of the command line's arguments: subcommands, options and values drawn
from what the parser knows and from what it should refuse, run in this process on a small
model.  Every run ends with exit 0, 1 or 2 and never with an internal error or an exception
out of ``main``; a failure (1) says what failed.  Every run is bounded by ``--timeout``.  A
small budget runs by default, a large one under ``-m slow``."""

from __future__ import annotations

import io
import tempfile

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lagrangian.cli.main import main

MODEL = (
    "coordinates: [x]\nparameters: {m: 1, k: 1}\nkinetic: m*x_dot**2/2\npotential: k*x**2/2\n"
    "initial: {x: 0.5, x_dot: 0}\nsimulate: {t_end: 1}\n"
)
FUZZ = settings(
    max_examples=25,
    deadline=None,  # no speed assertion
    derandomize=True,  # the same examples on every run: CI reproducible, a failure replayable
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
FUZZ_LONG = settings(FUZZ, max_examples=1500)

VALUES = [
    "1", "0", "-1", "2.5", "1e308", "1e-300", "nan", "inf", "-inf", "", " ", "abc", "2**70",
    "9" * 400, "x=1", "m=-1", "m=nan", "k=0", "x=1e200", "x_dot=3", "x=1,x_dot=2", "theta=1",
    "=", "m=", "=1", "m=1=2", "\x00", "m=\u00bd", "x=0.5,,", "m=1e309",
]  # fmt: skip
MODELS = ["-", "examples/simple_pendulum", "simple_pendulum", "n_link_pendulum:2",
          "n_link_pendulum:0", "n_link_pendulum:-3", "n_link_pendulum:1001", "no_such_example",
          "examples/../../etc/passwd", "/dev/null", ""]  # fmt: skip
OPTIONS = {
    "--format": ["text", "json", "latex", "mathml", "csv"],
    "--set": VALUES,
    "--about": VALUES,
    "--input": ["m", "k", "x", "zz", ""],
    "--search-degree": ["0", "1", "2", "-1", "x", "99999999999"],
    "--input-format": ["yaml", "toml", "json", "xml"],
    "--t-end": VALUES,
    "--method": ["RK45", "DOP853", "RK4", "Radau", "midpoint", "gauss4", "euler", "rk45", ""],
    "--rtol": VALUES,
    "--atol": VALUES,
    "--dt": VALUES,
    "--samples": ["0", "1", "2", "100", "-5", "1e7", "100000000", str(2**70), "x"],
    "--max-steps": ["0", "1", "10", "-1", "x"],
    "--max-wall-time": ["0", "0.001", "-1", "nan", "x"],
    "--phase": ["x", "y", ""],
    "--language": ["numpy", "c", "matlab", "julia", "fortran"],
    "--independent": ["x", "y", "", "x,x"],
    "--timeout": ["0", "-1", "nan", "x", "5"],
}
FLAGS = ["--steps", "--matrix", "--project", "--project-initial", "--debug", "--help", "-h"]
COMMANDS = ["derive", "analyze", "simulate", "export", "examples", "frobnicate", ""]


@st.composite
def command_lines(draw: st.DrawFn, folder: str) -> list[str]:
    argv = [draw(st.sampled_from(COMMANDS))]
    if argv[0] != "examples" or draw(st.booleans()):
        argv.append(draw(st.sampled_from(MODELS)))
    for _ in range(draw(st.integers(0, 5))):
        kind = draw(st.sampled_from(["option", "flag", "out", "junk"]))
        if kind == "option":
            name = draw(st.sampled_from(sorted(OPTIONS)))
            argv += [name, draw(st.sampled_from(OPTIONS[name]))]
        elif kind == "flag":
            argv.append(draw(st.sampled_from(FLAGS)))
        elif kind == "out":
            argv += ["--out", draw(st.sampled_from(["-", f"{folder}/out.csv", f"{folder}/a/b"]))]
        else:
            argv.append(draw(st.text(max_size=12)))
    if "--timeout" not in argv:
        argv += ["--timeout", "30"]  # bounds the run; exit 1 with a message past it
    return argv


def run(argv: list[str], capsys, monkeypatch) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO(MODEL))
    try:
        code = main(argv)
    except SystemExit as exit:  # argparse: --help (0), a usage error (2)
        code = exit.code
    error = capsys.readouterr().err
    assert code in (0, 1, 2), (argv, code, error)
    assert "internal error" not in error, (argv, error)
    if code == 1:
        assert error.strip(), argv


@pytest.fixture
def folder():
    with tempfile.TemporaryDirectory() as name:
        yield name


@FUZZ
@given(data=st.data())
def test_any_command_line_ends_with_a_plain_exit_code(data, folder, capsys, monkeypatch):
    run(data.draw(command_lines(folder)), capsys, monkeypatch)


@pytest.mark.slow
@FUZZ_LONG
@given(data=st.data())
def test_any_command_line_ends_with_a_plain_exit_code_long_run(data, folder, capsys, monkeypatch):
    run(data.draw(command_lines(folder)), capsys, monkeypatch)


def test_the_fuzzed_options_are_the_parsers_own(capsys):
    # The fuzz keeps up with the parser: every option it draws exists on some subcommand.
    help_text = ""
    for command in COMMANDS[:5]:
        with pytest.raises(SystemExit):
            main([command, "--help"])
        help_text += capsys.readouterr().out
    missing = [name for name in [*OPTIONS, *FLAGS[:-2]] if name not in help_text]
    assert missing == []
