"""The README is the front door: its Python tour runs as written, and its first lines are the
two commands (install + run an example; install test dependencies + run the suite)."""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_first_commands_are_install_and_run() -> None:
    blocks = re.findall(r"```bash\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert blocks[0].strip() == (
        "pip install . && lagrangian derive examples/double_pendulum --steps"
    )
    assert blocks[1].strip() == 'pip install -e ".[test]" && python -m pytest -q'


def test_the_python_tour_runs(tmp_path: Path, monkeypatch) -> None:
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    text = README.read_text(encoding="utf-8")
    (code,) = re.findall(r"```python\n(.*?)```", text, re.S)
    namespace: dict[str, object] = {}
    exec(compile(code, "README.md", "exec"), namespace)  # the README's own code, not user input
    assert (tmp_path / "traj.csv").exists() and (tmp_path / "traj.png").exists()
