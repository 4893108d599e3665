"""lagrangian simulate: output names checked before any work, the CSV written first and every
file atomically, a failed or interrupted run keeping its rows (exit 1, or 130 after Ctrl-C),
and a summary line that reports drift only where the system conserves energy."""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from lagrangian.cli import simulate_command
from lagrangian.cli.main import main

RUNAWAY = """\
coordinates: [x]
kinetic: "x_dot**2/2"
potential: "-x**4"
initial: {x: 1.0, x_dot: 0.0}
simulate: {t_end: 5.0}
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """The exit code of ``lagrangian ARGV`` (returned, or given to SystemExit) and its
    output."""
    try:
        code = main(list(argv))
    except SystemExit as stop:
        code = int(stop.code or 0)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def ctrl_c_after(time: float) -> Callable[..., Callable[[float], None]]:
    """A stand-in for the command's progress bar: Ctrl-C once the run passes ``time``."""

    def bar(*args: object, **kwargs: object) -> Callable[[float], None]:
        def update(t: float) -> None:
            if t > time:
                raise KeyboardInterrupt

        return update

    return bar


def rows(path: Path) -> list[list[float]]:
    header, *lines = path.read_text().splitlines()
    assert header.startswith("t,")
    return [[float(v) for v in line.split(",")] for line in lines]


def test_a_failed_run_writes_the_rows_so_far_and_says_where_it_stopped(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    model, out, picture = tmp_path / "runaway.yaml", tmp_path / "runaway.csv", tmp_path / "p.png"
    model.write_text(RUNAWAY)  # x_ddot = 4 x**3 blows up near t = 0.93
    code, _, err = run(capsys, "simulate", str(model), "--out", str(out), "--plot", str(picture))
    assert code == 1 and "Traceback" not in err
    written = rows(out)
    last = written[-1][0]
    assert len(written) > 10 and 0.9 < last < 1.0
    assert f"rows, up to t = {last:.6g}, written to {out}" in err
    assert "Integration failed at t = " in err
    assert not picture.exists()  # no plot of a run that did not reach its end


def test_ctrl_c_writes_the_rows_so_far_and_exits_130(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(simulate_command, "progress_bar", ctrl_c_after(2.0))
    out = tmp_path / "swing.csv"
    code, _, err = run(capsys, "simulate", "examples/double_pendulum", "--out", str(out))
    assert code == 130 and err.startswith("lagrangian: Interrupted (Ctrl-C) at t = ")
    written = rows(out)
    assert 1.9 < written[-1][0] < 2.1 and len(written) > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == ["swing.csv"]  # no temporary left


def test_ctrl_c_on_standard_output_prints_the_rows_so_far(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(simulate_command, "progress_bar", ctrl_c_after(1.0))
    code, out, err = run(capsys, "simulate", "examples/simple_pendulum", "--samples", "101")
    assert code == 130 and "written to standard output" in err
    header, *lines = out.splitlines()
    assert header == "t,theta,theta_dot,energy" and 0 < len(lines) < 101


def test_ctrl_c_before_the_integration_writes_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def interrupted(reference: str) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(simulate_command, "load_system", interrupted)
    out = tmp_path / "never.csv"
    code, _, err = run(capsys, "simulate", "examples/simple_pendulum", "--out", str(out))
    assert code == 130 and err.startswith("lagrangian: Interrupted (Ctrl-C)")
    assert not out.exists()


@pytest.mark.parametrize(
    ("option", "name", "message"),
    [
        ("--plot", "picture.jpg", "is not a .png, .pdf or .svg file"),
        ("--animate", "movie.avi", "no animation format .avi"),
        ("--animate", "movie", "no animation format (none)"),
    ],
)
def test_output_names_are_checked_before_simulating(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    option: str,
    name: str,
    message: str,
) -> None:
    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("simulated before checking the output names")

    monkeypatch.setattr(simulate_command, "simulate", never)
    out = tmp_path / "run.csv"
    target = str(tmp_path / name)
    code, _, err = run(
        capsys, "simulate", "examples/simple_pendulum", "--out", str(out), option, target
    )
    assert code == 2 and message in err and not out.exists()


def test_an_mp4_without_ffmpeg_is_refused_before_simulating(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from lagrangian.render import frames_writer

    monkeypatch.setattr(frames_writer, "ffmpeg_path", lambda: None)
    monkeypatch.setattr(simulate_command, "simulate", None)  # calling it would fail the test
    code, _, err = run(
        capsys, "simulate", "examples/simple_pendulum", "--animate", str(tmp_path / "a.mp4")
    )
    assert code == 2 and "needs ffmpeg, which is not installed" in err


def test_the_csv_is_written_before_the_animation_and_files_appear_whole(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out, movie = tmp_path / "run.csv", tmp_path / "run.gif"
    seen: list[bool] = []

    def animation(system: object, trajectory: object, path: Path, **options: object) -> None:
        seen.append(out.exists())
        assert Path(path).suffix == ".gif" and Path(path) != movie  # a temporary beside it
        Path(path).write_bytes(b"GIF89a")

    monkeypatch.setattr(simulate_command, "write_animation", animation)
    code, _, err = run(
        capsys,
        "simulate",
        "examples/simple_pendulum",
        "--t-end",
        "0.5",
        "--out",
        str(out),
        "--animate",
        str(movie),
    )
    assert code == 0, err
    assert seen == [True] and movie.read_bytes() == b"GIF89a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv", "run.gif"]


def test_a_failing_animation_leaves_no_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    movie = tmp_path / "run.gif"

    def animation(system: object, trajectory: object, path: Path, **options: object) -> None:
        Path(path).write_bytes(b"GIF8")  # half a file, then the writer fails
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(simulate_command, "write_animation", animation)
    out = tmp_path / "run.csv"
    code, _, _ = run(
        capsys, "simulate", "examples/simple_pendulum", "--out", str(out), "--animate", str(movie)
    )
    assert code == 1 and sorted(p.name for p in tmp_path.iterdir()) == ["run.csv"]


def test_the_summary_says_why_energy_is_not_conserved(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "damped.csv"
    code, printed, _ = run(capsys, "simulate", "examples/mass_spring_damper", "--out", str(out))
    assert code == 0 and printed.strip().endswith("energy not conserved: dissipation")
    code, printed, _ = run(capsys, "simulate", "examples/double_pendulum", "--out", str(out))
    assert code == 0 and "max |dE/E0| = " in printed


def test_an_option_that_does_not_apply_is_refused_with_the_flag_to_change(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, _, err = run(
        capsys, "simulate", "examples/simple_pendulum", "--method", "RK4", "--rtol", "1e-9"
    )
    assert code == 2 and "--rtol: rtol steers the adaptive methods" in err
    assert "remove --rtol, or choose an adaptive method such as --method DOP853" in err


def test_rows_on_standard_output_come_with_the_summary_on_standard_error(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from lagrangian.cli.main import main

    assert main(["simulate", "examples/simple_pendulum", "--t-end", "1"]) == 0
    captured = capsys.readouterr()
    assert len(captured.out.splitlines()) == 1001  # a pipe gets every row
    assert "1000 samples written to standard output; max |dE/E0| = " in captured.err
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True, raising=False)
    assert main(["simulate", "examples/simple_pendulum", "--t-end", "1"]) == 0
    shown = capsys.readouterr().out.splitlines()
    assert len(shown) == 12 and "... 990 more rows: --out FILE writes them all" in shown[6]
