"""A fix names the option to set as a value (the keyword and the value it suggests), and each
interface words it its own way: Python's keyword, the command line's flag, the web API's
``options.NAME``."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.cli.wording import COMMAND_LINE
from lagrangian.errors import Fix, Problem, Setting, SimulationInputError, Wording
from lagrangian.web.wording import WEB

PYTHON = Wording()
ROOM = Fix("use a larger {0.name}, or pass {1}", (Setting("dt"), Setting("max_steps")))


@pytest.mark.parametrize(
    ("wording", "expected"),
    [
        (PYTHON, "use a larger dt, or pass max_steps=..."),
        (COMMAND_LINE, "use a larger --dt, or pass --max-steps"),
        (WEB, "use a larger options.dt, or pass options.max_steps"),
    ],
)
def test_one_fix_in_the_words_of_each_interface(wording: Wording, expected: str) -> None:
    assert ROOM.worded(wording) == expected


@pytest.mark.parametrize(
    ("setting", "python", "command_line", "web"),
    [
        (Setting("project_initial", True), "project_initial=True", "--project-initial", None),
        (Setting("method", "DOP853"), "method='DOP853'", "--method DOP853", None),
        (Setting("initial", entry="x"), "initial={'x': ...}", "--initial x=VALUE", None),
        (Setting("t_span"), "t_span=...", "--t-end", "options.t_end"),
        (Setting("parameters", entry="k"), "parameters={'k': ...}", "--set k=VALUE", None),
    ],
)
def test_a_setting_keeps_its_keyword_and_value(
    setting: Setting, python: str, command_line: str, web: str | None
) -> None:
    assert str(setting) == python == PYTHON.setting(setting)
    assert COMMAND_LINE.setting(setting) == command_line
    assert WEB.setting(Setting("project_initial", True)) == "options.project_initial = true"
    if web is not None:
        assert WEB.setting(setting) == web


def test_a_worded_error_keeps_its_class_summary_and_other_fields() -> None:
    problems = [Problem("rtol", "too small", ROOM), Problem("'rod' (constraints[0])", "off")]
    error = SimulationInputError("Cannot simulate", problems)
    worded = error.worded(COMMAND_LINE)
    assert type(worded) is SimulationInputError and worded.exit_code == 2
    assert [p.field for p in worded.problems] == ["--rtol", "'rod' (constraints[0])"]
    assert str(worded).startswith("Cannot simulate\n")
    assert "pass --max-steps" in str(worded) and "max_steps=" not in str(worded)
    assert "pass max_steps=..." in str(error)  # the error itself speaks Python


def test_python_fixes_name_the_keywords() -> None:
    pendulum = lg.examples.simple_pendulum()
    with pytest.raises(
        SimulationInputError, match=r"remove rtol, or choose an adaptive method such as "
    ) as caught:
        lg.simulate(pendulum, {"theta": 0.1}, 1.0, method="RK4", dt=0.01, rtol=1e-6)
    assert "method='DOP853'" in str(caught.value)
    x = lg.loads("coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n")
    with pytest.raises(SimulationInputError, match=r"pass initial=\{'x': \.\.\.\}"):
        lg.simulate(x, {"x_dot": 0.0}, 1.0)
    with pytest.raises(SimulationInputError, match=r"no end time — pass the end time, t_span="):
        lg.simulate(x, {"x": 0.0, "x_dot": 0.0})


def test_fixes_added_to_text_and_to_each_other_keep_their_own_settings() -> None:
    said = "budget {spent} — " + ROOM + "; or " + Fix("{0.name} {0}", (Setting("method", "RK4"),))
    assert str(said) == (
        "budget {spent} — use a larger dt, or pass max_steps=...; or method method='RK4'"
    )
    assert said.worded(COMMAND_LINE) == (
        "budget {spent} — use a larger --dt, or pass --max-steps; or --method --method RK4"
    )


def test_a_failed_runs_message_is_worded_by_each_interface() -> None:
    pendulum = lg.examples.simple_pendulum()
    run = lg.simulate(pendulum, {"theta": 1.0}, 100.0, max_steps=50, raise_on_failure=False)
    fix = "the step budget of 50 steps is used up — pass {} to allow more steps."
    assert run.message.endswith(fix.format("max_steps=500"))
    assert run.worded_message(COMMAND_LINE).endswith(fix.format("--max-steps 500"))
    assert run.worded_message(WEB).endswith(fix.format("options.max_steps = 500"))
    assert run.worded_message(PYTHON) == run.message
