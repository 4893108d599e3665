"""Every built-in example animates: particles and bodies in space, circuits as gauges."""

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.render.animation import animation_frame
from lagrangian.render.gauges import gauge_scene

matplotlib = pytest.importorskip("matplotlib")
image = pytest.importorskip("matplotlib.image")


@pytest.mark.parametrize("name", lg.examples.names())
def test_every_example_draws_a_frame(name, tmp_path):
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=0.2, samples=9)
    path = tmp_path / f"{name}.png"
    animation_frame(system, trajectory, path)
    pixels = image.imread(path)
    assert pixels.shape[0] > 100 and pixels.shape[1] > 100
    assert np.std(pixels[..., :3]) > 0.01  # something is drawn, not a blank canvas


def test_circuit_gauges_show_each_value_over_its_largest():
    system = lg.examples.series_rlc()
    trajectory = lg.simulate(system, t_span=1.0, samples=21)
    _, draw, _ = gauge_scene(system, trajectory, shown=list(range(21)))
    bars = draw(7)[:-1]
    q, current = trajectory["q"], trajectory["q_dot"]
    expected = [q[7] / np.abs(q).max(), current[7] / np.abs(current).max()]
    assert np.allclose([bar.get_width() for bar in bars], expected)


@pytest.mark.parametrize(
    ("suffix", "magic"), [(".png", b"\x89PNG"), (".pdf", b"%PDF"), (".svg", b"<?xml")]
)
def test_plots_are_written_in_the_format_asked(suffix, magic, tmp_path):
    from lagrangian.render.plots import save_plots

    trajectory = lg.simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=11)
    path = save_plots(trajectory, tmp_path / f"plot{suffix}")
    assert path.read_bytes().startswith(magic)
    with pytest.raises(ValueError, match=r"not '\.jpg'"):
        save_plots(trajectory, tmp_path / "plot.jpg")
