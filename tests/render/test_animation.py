"""Animations of simulated systems: what is drawn (rods found from constant distances), and
the files written (GIF, HTML, a still frame of the double pendulum)."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import pytest

import lagrangian as lg
from lagrangian.render.animation import animate, animation_frame, animation_html, rods
from lagrangian.render.frames_writer import ffmpeg_path

matplotlib.use("Agg")


def test_rods_are_the_links_of_fixed_length() -> None:
    assert rods(lg.examples.double_pendulum()) == [("origin", "bob1"), ("bob1", "bob2")]
    assert rods(lg.examples.spherical_pendulum()) == [("origin", "bob")]
    assert rods(lg.examples.two_masses_three_springs()) == []  # springs stretch


def test_gif_html_and_a_still_frame(tmp_path: Path) -> None:
    system = lg.examples.double_pendulum()
    trajectory = lg.simulate(system, t_span=3.0, samples=90)
    gif = tmp_path / "double_pendulum.gif"
    animate(system, trajectory, gif, frames=30)
    from PIL import Image

    with Image.open(gif) as picture:
        assert picture.format == "GIF" and picture.n_frames == 30
    frame = tmp_path / "double_pendulum_frame.png"
    animation_frame(system, trajectory, frame, time=1.5)
    assert frame.read_bytes()[:4] == b"\x89PNG" and frame.stat().st_size > 5000
    html = animation_html(system, trajectory, frames=10)
    assert "<script" in html and html._repr_html_() == str(html)  # Jupyter shows the player


@pytest.mark.parametrize("name", ["spherical_pendulum", "two_masses_three_springs"])
def test_three_d_and_one_d_systems_animate(tmp_path: Path, name: str) -> None:
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=1.0, samples=20)
    path = tmp_path / f"{name}.html"
    animate(system, trajectory, path, frames=5)
    assert path.stat().st_size > 1000


def test_cli_animate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from lagrangian.cli.main import main

    gif = tmp_path / "pendulum.gif"
    code = main(
        [
            "simulate",
            "examples/simple_pendulum",
            "--t-end",
            "1",
            "--samples",
            "10",
            "--out",
            str(tmp_path / "t.csv"),
            "--animate",
            str(gif),
        ]
    )
    assert code == 0 and gif.stat().st_size > 1000
    assert "animation written" in capsys.readouterr().out


def test_frames_and_fps_shape_the_gif_and_the_player(tmp_path: Path) -> None:
    from PIL import Image

    system = lg.examples.simple_pendulum()
    trajectory = lg.simulate(system, t_span=2.0, samples=201)
    gif = tmp_path / "p.gif"
    animate(system, trajectory, gif, frames=12, fps=10)
    with Image.open(gif) as picture:
        assert picture.n_frames == 12 and picture.info["duration"] == 100  # 1000 ms / 10
    page = tmp_path / "p.html"
    scene = animate(system, trajectory, page, frames=12, fps=10).scene
    text = page.read_text()
    assert '"fps":10.0' in text and text.count("<canvas") == 1
    assert len(scene.times) == 12 and len(text) < 30_000  # the numbers, not 12 pictures


def test_the_tour_html_is_compact() -> None:
    """The double pendulum over 20 s: the player and its numbers, a few tens of kilobytes
    (one PNG per frame made it 5 MB)."""
    system = lg.examples.double_pendulum()
    trajectory = lg.simulate(system, t_span=20.0, samples=1000)
    html = animation_html(system, trajectory)
    assert 10_000 < len(html) < 200_000


@pytest.mark.parametrize(
    ("options", "message"),
    [({"frames": 0}, r"frames: 0 is not a number of frames.*frames= a whole number"),
     ({"fps": -1.0}, r"fps: -1.0 is not a frame rate.*fps= a positive number")],
)  # fmt: skip
def test_bad_frames_or_fps_are_refused_naming_the_keyword(options, message) -> None:
    from lagrangian.errors import SimulationInputError

    system = lg.examples.simple_pendulum()
    trajectory = lg.simulate(system, t_span=0.2, samples=5)
    with pytest.raises(SimulationInputError, match=message):
        animate(system, trajectory, **options)


def test_an_animation_shows_as_its_player_in_jupyter() -> None:
    system = lg.examples.simple_pendulum()
    animation = animate(system, lg.simulate(system, t_span=0.2, samples=5), frames=3)
    assert "<canvas" in animation._repr_html_()


@pytest.mark.skipif(ffmpeg_path() is None, reason="ffmpeg is not installed")
def test_an_mp4_is_written_through_ffmpeg(tmp_path: Path) -> None:
    system = lg.examples.simple_pendulum()
    movie = tmp_path / "p.mp4"
    animate(system, lg.simulate(system, t_span=0.5, samples=11), movie, frames=5)
    assert movie.read_bytes()[4:8] == b"ftyp"
