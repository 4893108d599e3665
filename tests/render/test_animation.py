"""Animations of simulated systems: what is drawn (rods found from constant distances), and
the files written (GIF, HTML, a still frame of the double pendulum)."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import pytest

import lagrangian as lg
from lagrangian.render.animation import animate, animation_frame, animation_html, rods

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
