"""docs/animations.md runs as written: its Python block and its commands."""

import re
import shlex
from pathlib import Path

import pytest

from lagrangian.cli.main import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "animations.md"


def _blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)


def test_the_python_block_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (code,) = _blocks("python")
    exec(compile(code, str(DOC), "exec"), {})  # the document's own code, not user input
    assert (tmp_path / "spring.gif").stat().st_size > 1000
    assert (tmp_path / "spring.png").read_bytes()[:4] == b"\x89PNG"


def test_the_commands_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    (console,) = _blocks("console")
    commands = [line.removeprefix("$ ") for line in console.splitlines() if line.startswith("$")]
    assert len(commands) == 2
    for command in commands:
        argv = shlex.split(command)
        assert argv[0] == "lagrangian"
        assert main(argv[1:]) == 0, capsys.readouterr().err
    assert (tmp_path / "traj.gif").exists() and (tmp_path / "traj.html").exists()
