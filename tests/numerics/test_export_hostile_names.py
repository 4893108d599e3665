"""Names that try to escape into the exported code (a newline ending a comment, Julia's
string interpolation) are written as inert text in every language, and the code still runs."""

import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.numerics.export import export


def _hostile_system(sentinels):
    q = sp.Symbol(f"q\nrun(`touch {sentinels / 'julia'}`) # $(run(`touch {sentinels / 'j2'}`))")
    k = sp.Symbol(f"k\nsystem('touch {sentinels / 'matlab'}'); % \nimport os; os.mknod('x')")
    q_dot = sp.Symbol(q.name + "_dot")
    return lg.System(
        coordinates=[q],
        kinetic=q_dot**2 / 2,
        potential=k * q**2 / 2,
        parameters={k: 4.0},
        name="oscillator\nsystem('touch boom')",
    )


def _build(tmp_path):
    sentinels = tmp_path / "sentinels"
    sentinels.mkdir()
    try:
        system = _hostile_system(sentinels)
    except lg.LagrangianError:
        pytest.skip("the System refuses such names before any export")
    return lg.derive(system), sentinels


@pytest.mark.parametrize("language", ["numpy", "c", "matlab", "julia"])
def test_no_name_starts_a_line_of_code(language, tmp_path):
    eom, _ = _build(tmp_path)
    for text in export(eom, language).values():
        for line in text.splitlines():
            assert not line.lstrip().startswith(("run(", "system(", "import os")), line


def test_the_exported_code_runs_and_runs_nothing_else(tmp_path):
    eom, sentinels = _build(tmp_path)
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
        script = "disp(rhs(0, [1; 0], default_parameters()))\n"
        (tmp_path / "check.m").write_text(script)
        result = subprocess.run(
            ["octave-cli", "--quiet", "check.m"], cwd=tmp_path, capture_output=True, text=True
        )
        assert result.returncode == 0, result.stderr
    if shutil.which("julia"):
        ((jl_name, source),) = export(eom, "julia").items()
        (tmp_path / jl_name).write_text(source)
        subprocess.run(["julia", jl_name], cwd=tmp_path, capture_output=True, check=False)
    assert not list(sentinels.iterdir())  # nothing the names asked for was run
