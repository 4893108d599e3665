"""No output of `lagrangian derive` drops a constraint: every constrained example through every
format, with and without --matrix."""

import json
from xml.dom import minidom

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.cli.commands import load_system
from lagrangian.cli.main import main
from lagrangian.render.latex import symbol_names
from lagrangian.render.mathml import Dotted

CARTESIAN_PENDULUM = """name: Cartesian pendulum
coordinates: [x, y]
parameters: {m: 1, g: 9.81, l: 1}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: x**2 + y**2 - l**2}
"""
CARTESIAN_DOUBLE_PENDULUM = """name: Cartesian double pendulum
coordinates: [x1, y1, x2, y2]
parameters: {m1: 1, m2: 1, g: 9.81, l1: 1, l2: 1}
kinetic: m1*(x1_dot**2 + y1_dot**2)/2 + m2*(x2_dot**2 + y2_dot**2)/2
potential: m1*g*y1 + m2*g*y2
constraints:
  - {holonomic: x1**2 + y1**2 - l1**2}
  - {holonomic: (x2 - x1)**2 + (y2 - y1)**2 - l2**2}
"""


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    folder = tmp_path_factory.mktemp("models")
    (folder / "pendulum.yaml").write_text(CARTESIAN_PENDULUM)
    (folder / "double.yaml").write_text(CARTESIAN_DOUBLE_PENDULUM)
    return [
        "rolling_disc",
        "cylinder_on_incline",
        str(folder / "pendulum.yaml"),
        str(folder / "double.yaml"),
    ]


def derive(capsys, *argv):
    code = main(["derive", *argv])
    out = capsys.readouterr().out
    assert code == 0
    return out


@pytest.mark.parametrize("matrix", [False, True])
@pytest.mark.parametrize("fmt", ["text", "latex", "mathml", "json"])
def test_every_format_keeps_every_constraint(models, capsys, fmt, matrix):
    for model in models:
        system = load_system(model)
        out = derive(capsys, model, "--format", fmt, *(["--matrix"] if matrix else []))
        m = len(system.constraints)
        if fmt == "json":
            document = json.loads(out)
            assert len(document["constrained_equations"]) == len(system.coordinates) + m
            assert f"lambda_{m}" in " ".join(document["constrained_equations"])
            continue
        if fmt == "text":
            shown = [str(c.expression) for c in system.constraints]
            multiplier = f"lambda_{m}"
        elif fmt == "latex":
            names = symbol_names(system.coordinates)
            shown = [sp.latex(c.expression, symbol_names=names) for c in system.constraints]
            multiplier = f"\\lambda_{{{m}}}"
            assert out.count("\\begin{align*}") == out.count("\\end{align*}")
            assert out.count("{") == out.count("}")
        else:
            dotted = Dotted(lg.derive(system))
            shown = [dotted(c.expression) for c in system.constraints]
            multiplier = "&#955;"
            for document in out.strip().splitlines():
                minidom.parseString(document)  # each line one well-formed <math> element
        for expression in shown:
            assert expression in out, (model, fmt, expression)
        assert multiplier in out, (model, fmt)
        if matrix and fmt != "text":
            assert out.count("matrix" if fmt == "latex" else "<mtable") >= 3
        if matrix and fmt == "text":
            assert "augmented form" in out


@pytest.mark.parametrize("language", ["c", "numpy", "matlab", "julia"])
def test_every_export_carries_the_constraints(models, capsys, language, tmp_path):
    for model in models:
        out = tmp_path / f"{language}-{abs(hash(model))}"
        out.mkdir()
        code = main(["export", model, "--language", language, "--out", str(out)])
        capsys.readouterr()
        assert code == 0, (model, language)
        text = "\n".join(path.read_text() for path in out.iterdir())
        for function in ("constraint_jacobian", "augmented_matrix", "multipliers"):
            assert function in text, (model, language, function)
        assert "baumgarte_alpha" in text


def test_a_unilateral_constraint_cannot_be_exported(tmp_path, capsys):
    model = tmp_path / "bead.yaml"
    model.write_text(
        CARTESIAN_PENDULUM.replace("{holonomic: x**2 + y**2 - l**2}", "{unilateral: 1 - y}")
    )
    code = main(["export", str(model), "--language", "c", "--out", str(tmp_path)])
    assert code == 2 and "unilateral" in capsys.readouterr().err
