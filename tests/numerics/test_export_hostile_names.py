"""Names that try to escape into exported code (a newline ending a comment, Julia's string
interpolation) are refused by the System; and should one reach an exporter anyway, it is
written as inert text in every language, and the code still runs."""

import dataclasses
import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.numerics import export as export_package
from lagrangian.numerics.export import c_code, export, julia, matlab, numpy_module
from lagrangian.numerics.export.common import plan_export


def _hostile_names(sentinels):
    coordinate = f"q\nrun(`touch {sentinels / 'julia'}`) # $(run(`touch {sentinels / 'j2'}`))"
    parameter = f"k\nsystem('touch {sentinels / 'matlab'}'); % \nimport os; os.mknod('x')"
    return coordinate, parameter


def test_the_system_refuses_names_that_are_not_identifiers(tmp_path):
    coordinate, parameter = _hostile_names(tmp_path)
    q, k = sp.Symbol(coordinate), sp.Symbol(parameter)
    with pytest.raises(ModelError, match="is not a name"):
        lg.System(
            coordinates=[q],
            kinetic=sp.Symbol(coordinate + "_dot") ** 2 / 2,
            potential=k * q**2 / 2,
            parameters={k: 4.0},
        )


@pytest.fixture
def hostile_export(tmp_path, monkeypatch):
    """Every exporter given a plan whose names are hostile (as if a System had let them in)."""
    sentinels = tmp_path / "sentinels"
    sentinels.mkdir()
    coordinate, parameter = _hostile_names(sentinels)

    def hostile_plan(*args, **kwargs):
        plan = plan_export(*args, **kwargs)
        return dataclasses.replace(
            plan,
            title="oscillator\nsystem('touch boom')",
            coordinates=(coordinate,),
            parameters=((parameter, 4.0),),
        )

    for module in (c_code, julia, matlab, numpy_module):
        monkeypatch.setattr(module, "plan_export", hostile_plan)
    k, q = sp.symbols("k q")
    system = lg.System(
        coordinates=[q],
        kinetic=sp.Symbol("q_dot") ** 2 / 2,
        potential=k * q**2 / 2,
        parameters={k: 4.0},
    )
    return lg.derive(system), sentinels


@pytest.mark.parametrize("language", ["numpy", "c", "matlab", "julia"])
def test_no_name_starts_a_line_of_code(hostile_export, language):
    eom, _ = hostile_export
    for text in export_package.export(eom, language).values():
        for line in text.splitlines():
            assert not line.lstrip().startswith(("run(", "system(", "import os")), line


def test_the_exported_code_runs_and_runs_nothing_else(hostile_export, tmp_path):
    eom, sentinels = hostile_export
    ((name, text),) = export(eom, "numpy").items()
    path = tmp_path / name
    path.write_text(text)
    spec = importlib.util.spec_from_file_location("hostile", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.rhs(0.0, np.array([1.0, 0.0]), np.array([4.0]))[1] == pytest.approx(-4.0)
    if shutil.which("octave-cli"):
        for file_name, source in export(eom, "matlab").items():
            (tmp_path / file_name).write_text(source)
        (tmp_path / "check.m").write_text("disp(rhs(0, [1; 0], default_parameters()))\n")
        result = subprocess.run(
            ["octave-cli", "--quiet", "check.m"], cwd=tmp_path, capture_output=True, text=True
        )
        assert result.returncode == 0, result.stderr
    if shutil.which("julia"):
        ((jl_name, source),) = export(eom, "julia").items()
        (tmp_path / jl_name).write_text(source)
        subprocess.run(["julia", jl_name], cwd=tmp_path, capture_output=True, check=False)
    assert not list(sentinels.iterdir())  # nothing the names asked for was run
