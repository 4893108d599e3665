"""The documented notebook (docs/tour.ipynb) runs as written, in a real Jupyter kernel, and each
result displays as typeset LaTeX or a picture, never as a raw repr."""

from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "docs" / "tour.ipynb"


@pytest.mark.slow
def test_the_tour_notebook_runs_and_every_result_is_displayed_richly():
    nbformat = pytest.importorskip("nbformat", reason="the notebook test needs nbformat")
    nbclient = pytest.importorskip("nbclient", reason="the notebook test needs nbclient")
    pytest.importorskip("ipykernel", reason="the notebook test needs ipykernel")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3").execute()
    outputs = [cell.outputs for cell in notebook.cells if cell.cell_type == "code"]
    assert not [o for cell in outputs for o in cell if o.output_type == "error"]
    shown = [o for cell in outputs for o in cell if o.output_type == "execute_result"]
    kinds = [set(o.data) for o in shown]
    # the system, the equations, the steps, the bare equation, the report: LaTeX
    assert sum("text/latex" in k for k in kinds) >= 5
    assert any("image/png" in k for k in kinds)  # the trajectory as a picture
    assert any("text/html" in k for k in kinds)  # the drift as a table
    (cell,) = [c for c in notebook.cells if c.source.startswith("eom.equations[0]")]
    bare = cell.outputs[0].data["text/latex"]
    assert "\\ddot{\\theta}" in bare and "ddot}" not in bare.replace("\\ddot{", "")
