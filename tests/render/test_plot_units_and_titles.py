"""Plots and animations for people: titled with the system's name, axes labelled with the
model's units (θ [rad], θ̇ [rad/s], t [s]), springs drawn to ends the parameters place,
3-D bodies with their body axes, and a progress callback while frames are written."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import lagrangian as lg
from lagrangian.io import loads
from lagrangian.render.animation import AXIS_COLORS, animate, animation_frame, animation_scene
from lagrangian.render.plots import (
    column_label,
    overview,
    per_time,
    plot_time_series,
    save_plots,
    time_label,
)

matplotlib.use("Agg")

PENDULUM = """\
name: Pendulum with units
coordinates: [theta]
parameters: {m: 1.0, l: 0.5, g: 9.81}
units: {m: kg, l: m, theta: rad, g: m/s^2}
kinetic: m*l**2*theta_dot**2/2
potential: -m*g*l*cos(theta)
initial: {theta: 0.5, theta_dot: 0.0}
"""

#: A bob on a spring anchored at (a, 0), a point the parameter a places.
ANCHORED = """\
name: Anchored spring
coordinates: [x, y]
parameters: {m: 1.0, k: 10.0, a: 2.0}
particles: [{name: bob, mass: m, position: [x, y]}]
springs: [{between: [[a, 0], bob], stiffness: k}]
initial: {x: 1.0, y: 0.5, x_dot: 0.0, y_dot: 0.0}
"""


def test_labels_say_names_as_letters_with_their_units() -> None:
    units = {"theta": "rad", "x": "m", "v": "m/s"}
    assert column_label("theta", units) == "θ [rad]"
    assert column_label("theta_dot", units) == "θ\u0307 [rad/s]"
    assert column_label("v_dot", units) == "v\u0307 [(m/s)/s]"
    assert column_label("theta2_dot") == "θ\u03072"  # no units: the name alone
    assert column_label("energy", units) == "energy"
    assert per_time("rad", "ms") == "rad/ms" and per_time("kg m", "s") == "(kg m)/s"
    assert (time_label(units), time_label({"t": "ms"}), time_label(None)) == (
        "t [s]",
        "t [ms]",
        "t",
    )


def test_a_panel_of_one_unit_says_it_once_on_its_axis() -> None:
    system = lg.examples.double_pendulum().replace(units={"theta": "rad", "phi": "rad"})
    trajectory = lg.simulate(system, t_span=0.5, samples=11)
    assert plot_time_series(trajectory, units=system.units).get_ylabel() == "θ, φ [rad]"
    mixed = plot_time_series(trajectory, ["theta", "phi_dot"], units=system.units)
    assert mixed.get_ylabel() == ""  # two units: each line's legend says its own
    assert [line.get_label() for line in mixed.get_lines()] == ["θ [rad]", "φ\u0307 [rad/s]"]


def test_the_overview_is_titled_with_the_system_and_labelled_with_its_units() -> None:
    system = loads(PENDULUM)
    trajectory = lg.simulate(system, t_span=1.0, samples=21)
    figure = overview(trajectory, system=system)
    assert figure.get_suptitle() == "Pendulum with units (RK45)"
    series, phase, energy = figure.axes
    assert (series.get_xlabel(), series.get_ylabel()) == ("t [s]", "θ [rad]")
    assert (phase.get_xlabel(), phase.get_ylabel()) == ("θ [rad]", "θ\u0307 [rad/s]")
    assert phase.get_title() == "Phase portrait of θ" and energy.get_xlabel() == "t [s]"
    untitled = overview(trajectory)  # without the system: no name, no units, no coordinates
    assert untitled.get_suptitle() == "Simulation (RK45)"
    assert untitled.axes[0].get_xlabel() == "t"


def test_save_plots_with_the_system_writes_the_picture(tmp_path: Path) -> None:
    system = loads(PENDULUM)
    trajectory = lg.simulate(system, t_span=1.0, samples=21)
    path = save_plots(trajectory, tmp_path / "pendulum.svg", system=system)
    text = path.read_text()
    assert "Pendulum with units" in text  # the SVG keeps its text as glyph comments


@pytest.mark.parametrize(
    ("name", "title"), [("double_pendulum", "double_pendulum"), ("series_rlc", "series_rlc")]
)
def test_animations_are_titled_with_the_system_name(name: str, title: str) -> None:
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=0.2, samples=5)
    figure, _, _ = animation_scene(system, trajectory, frames=3)
    assert figure.axes[0].get_title() == title


def _lines_at(system: lg.System, trajectory: lg.Trajectory, frame: int) -> list[np.ndarray]:
    """The data of every line of the animation at ``frame``: (points, 2 or 3) each."""
    figure, draw, _ = animation_scene(system, trajectory)
    axes = figure.axes[0]
    draw(frame)
    return [
        np.array(line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_xydata())
        for line in axes.get_lines()
    ]


def test_a_spring_anchored_where_parameters_say_is_drawn_from_there() -> None:
    system = loads(ANCHORED).with_parameters({"a": 3.0})
    trajectory = lg.simulate(system, t_span=0.5, samples=6)
    lines = _lines_at(system, trajectory, 5)
    expected = np.array([[3.0, 0.0], [trajectory["x"][5], trajectory["y"][5]]])  # (a, 0) -> bob
    assert any(line.shape == (2, 2) and np.allclose(line, expected) for line in lines)


def test_the_walls_of_the_one_dimensional_springs_are_drawn_at_their_parameter_positions() -> None:
    system = lg.examples.two_masses_three_springs()
    a = float(system.parameters[next(p for p in system.parameters if p.name == "a")])
    trajectory = lg.simulate(system, t_span=0.5, samples=6)
    lines = _lines_at(system, trajectory, 5)
    wall = np.array([[trajectory["x2"][5] + 2 * a, 0.0], [3 * a, 0.0]])  # mass2 -> wall at 3a
    assert any(line.shape == (2, 2) and np.allclose(line, wall) for line in lines)


def test_a_top_is_drawn_with_its_body_axes_turning_with_the_spin() -> None:
    system = lg.examples.heavy_symmetric_top()
    trajectory = lg.simulate(system, t_span=0.2, samples=11)
    figure, draw, _ = animation_scene(system, trajectory)
    axes = figure.axes[0]
    for frame in (0, 10):
        draw(frame)
        body = [line for line in axes.get_lines() if line.get_color() in _colors()]
        assert len(body) == 3
        tips = [
            np.array(line.get_data_3d())[:, 1] - np.array(line.get_data_3d())[:, 0] for line in body
        ]
        directions = np.array([tip / np.linalg.norm(tip) for tip in tips])
        np.testing.assert_allclose(directions @ directions.T, np.eye(3), atol=1e-9)
        phi, theta, psi = (trajectory[n][frame] for n in ("phi", "theta", "psi"))
        # Goldstein's ZXZ angles: the symmetry axis (body z) points from the tip to the centre
        symmetry = np.array(
            [np.sin(phi) * np.sin(theta), -np.cos(phi) * np.sin(theta), np.cos(theta)]
        )
        np.testing.assert_allclose(directions[2], symmetry, atol=1e-9)
        # the body x axis makes the angle psi with the line of nodes (cos phi, sin phi, 0)
        nodes = np.array([np.cos(phi), np.sin(phi), 0.0])
        assert directions[0] @ nodes == pytest.approx(np.cos(psi), abs=1e-9)


def _colors() -> set[str]:
    from matplotlib.colors import to_hex

    return {to_hex(c) for c in AXIS_COLORS} | set(AXIS_COLORS)


def test_the_body_axes_show_in_the_picture(tmp_path: Path) -> None:
    from matplotlib.colors import to_rgb
    from matplotlib.image import imread

    system = lg.examples.heavy_symmetric_top()
    trajectory = lg.simulate(system, t_span=0.2, samples=11)
    path = tmp_path / "top.png"
    animation_frame(system, trajectory, path)
    pixels = imread(path)[..., :3]
    for color in AXIS_COLORS:
        near = np.all(np.abs(pixels - np.array(to_rgb(color))) < 0.08, axis=-1)
        assert near.sum() > 20, color  # each axis is a visible line of its colour


def test_progress_is_told_after_every_frame_written(tmp_path: Path) -> None:
    system = lg.examples.simple_pendulum()
    trajectory = lg.simulate(system, t_span=1.0, samples=11)
    told: list[tuple[int, int]] = []
    animate(system, trajectory, tmp_path / "p.gif", frames=4, progress=lambda *a: told.append(a))
    assert told == [(1, 4), (2, 4), (3, 4), (4, 4)]
    told.clear()
    page = tmp_path / "p.html"
    animate(system, trajectory, page, frames=3, progress=lambda *a: told.append(a))
    assert told[-1] == (3, 3) and "<script" in page.read_text()
