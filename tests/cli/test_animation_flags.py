"""``simulate --animate FILE --frames N --fps F``: the animation's frames and playback rate,
and flags that cannot shape one refused before any work (exit 2), naming the flag."""

from pathlib import Path

import pytest
from PIL import Image

from lagrangian.cli.main import main


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_frames_and_fps_shape_the_gif(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    movie = tmp_path / "pendulum.gif"
    code, out, err = run(
        capsys, "simulate", "simple_pendulum", "--t-end", "2", "--out", str(tmp_path / "p.csv"),
        "--animate", str(movie), "--frames", "12", "--fps", "10",
    )  # fmt: skip
    assert code == 0, err
    with Image.open(movie) as picture:
        assert picture.n_frames == 12 and picture.info["duration"] == 100  # 1000 ms / 10
    assert f"animation written to {movie}" in out


def test_without_frames_the_motion_sets_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    movie = tmp_path / "pendulum.gif"
    argv = ["simulate", "simple_pendulum", "--t-end", "10", "--out", str(tmp_path / "p.csv")]
    code, _, err = run(capsys, *argv, "--animate", str(movie))
    assert code == 0, err
    with Image.open(movie) as picture:  # 9 turning points in 10 s (period 2.03 s): 10 each
        assert picture.n_frames == 90 and picture.info["duration"] == 40  # 25 frames/s


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--frames", "0"], "--frames: 0 frames — give 1 or more, e.g. --frames 100"),
        (["--fps", "0"], "--fps: 0 frames per second — give a positive rate, e.g. --fps 25"),
        (["--fps", "nan"], "--fps: nan frames per second"),
    ],
)
def test_bad_frames_and_fps_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], flags: list[str], message: str
) -> None:
    argv = ["simulate", "simple_pendulum", "--out", str(tmp_path / "p.csv")]
    code, _, err = run(capsys, *argv, "--animate", str(tmp_path / "p.gif"), *flags)
    assert code == 2 and message in err
    assert not (tmp_path / "p.csv").exists()  # refused before any work


def test_frames_without_animate_say_to_add_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, _, err = run(capsys, "simulate", "simple_pendulum", "--out", str(tmp_path / "p.csv"),
                       "--frames", "10")  # fmt: skip
    assert code == 2 and "--frames: only an animation has frames — add --animate FILE.gif" in err


def test_projection_chooses_the_view_of_a_3d_system(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from lagrangian.render.projection import PROJECTIONS

    views = {}
    for view in ("xy", "xz"):
        movie = tmp_path / f"top_{view}.gif"
        argv = ["simulate", "heavy_symmetric_top", "--t-end", "0.5", "--samples", "20"]
        argv += ["--out", str(tmp_path / "top.csv"), "--animate", str(movie), "--frames", "3"]
        code, _, err = run(capsys, *argv, "--projection", view)
        assert code == 0, err
        views[view] = movie.read_bytes()
    assert views["xy"] != views["xz"]
    # The command hands the view to the drawing (whose views are tested in tests/render).
    from lagrangian.cli import simulate_command

    asked: list[str] = []
    drawn = simulate_command.write_animation
    monkeypatch.setattr(
        simulate_command,
        "write_animation",
        lambda *a, **k: (asked.append(k["projection"]), drawn(*a, **k)),
    )
    code, _, err = run(capsys, *argv, "--projection", "isometric")
    assert code == 0 and asked == ["isometric"], err
    code, _, err = run(capsys, "simulate", "heavy_symmetric_top", "--projection", "zz",
                       "--animate", str(tmp_path / "x.gif"))  # fmt: skip
    assert code == 2 and "--projection: 'zz' — choose one of " + ", ".join(PROJECTIONS) in err
    # The help names the views there are (written out: the command line does not import
    # the render layer to start).
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    shown = " ".join(capsys.readouterr().out.split())
    listed = shown.split("--projection VIEW")[-1][:300]
    assert all(f" {view}" in listed for view in PROJECTIONS), listed
