"""analyze says the parameter values its statements are decided at: in text, LaTeX and
JSON, the values after --set, a parameter without a value said as such."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lagrangian.cli.main import main

SPRING = """\
coordinates: [x]
parameters: {m: 2, k: null}
kinetic: m*x_dot**2/2
potential: k*x**2/2
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_the_values_after_set_head_every_format(capsys: pytest.CaptureFixture[str]) -> None:
    pendulum = ("analyze", "examples/simple_pendulum", "--set", "m=2", "--format")
    text = run(capsys, *pendulum, "text")
    assert (
        text.splitlines()[1]
        == "at m = 2, g = 9.81, l = 1 (where the general case differs, it is said)"
    )
    latex = run(capsys, *pendulum, "latex")
    assert r"&\text{at}\ m = 2,\quad g = 9.81,\quad l = 1 \\" in latex
    document = json.loads(run(capsys, *pendulum, "json"))
    assert document["parameter_values"] == {"m": 2.0, "g": 9.81, "l": 1.0}


def test_a_parameter_without_a_value_is_said_so(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    model = tmp_path / "spring.yaml"
    model.write_text(SPRING)
    text = run(capsys, "analyze", str(model), "--format", "text")
    assert "at m = 2, k = no value" in text
    document = json.loads(run(capsys, "analyze", str(model), "--format", "json"))
    assert document["parameter_values"] == {"m": 2.0, "k": None}


@pytest.mark.parametrize("name", ["dumbbell", "heavy_symmetric_top", "series_rlc"])
def test_every_kind_of_system_says_its_values(
    capsys: pytest.CaptureFixture[str], name: str
) -> None:
    """A constrained, a 3-D and an electrical system: the values of the model file (read
    back from the System itself) head the text and LaTeX reports and fill the JSON field."""
    import lagrangian as lg

    given = {p.name: v for p, v in lg.examples.get(name)().parameters.items()}
    document = json.loads(run(capsys, "analyze", f"examples/{name}", "--format", "json"))
    assert document["parameter_values"] == pytest.approx(given)
    text = run(capsys, "analyze", f"examples/{name}", "--format", "text")
    line = text.splitlines()[1]
    assert line.startswith("at ") and line.endswith("(where the general case differs, it is said)")
    shown = dict(part.split(" = ") for part in line[3:].split(" (where")[0].split(", "))
    assert {k: float(v) for k, v in shown.items()} == pytest.approx(given)
    latex = run(capsys, "analyze", f"examples/{name}", "--format", "latex")
    assert latex.count(r",\quad ") >= len(given) - 1 and r"&\text{at}\ " in latex
