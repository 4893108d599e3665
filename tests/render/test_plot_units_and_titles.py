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
from lagrangian.render.animation import AXIS_COLORS, animate, animation_frame
from lagrangian.render.plots import (
    column_label,
    overview,
    per_time,
    plot_time_series,
    save_plots,
    time_label,
)
from lagrangian.render.projection import projection_matrix
from lagrangian.render.scene import Scene, scene_of, shapes_of
from lagrangian.render.scene_draw import SceneFigure

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


def test_the_overview_is_titled_with_the_system_and_labelled_with_its_units(
    tmp_path: Path,
) -> None:
    system = loads(PENDULUM)
    trajectory = lg.simulate(system, t_span=1.0, samples=21)
    figure = overview(trajectory, system=system)
    assert figure.get_suptitle() == "Pendulum with units (RK45)"
    series, phase, energy = figure.axes
    assert (series.get_xlabel(), series.get_ylabel()) == ("t [s]", "θ [rad]")
    assert (phase.get_xlabel(), phase.get_ylabel()) == ("θ [rad]", "θ\u0307 [rad/s]")
    assert phase.get_title() == "Phase portrait of θ" and energy.get_xlabel() == "t [s]"
    # Without the system (as Jupyter shows a Trajectory): the name and units it keeps.
    kept = overview(trajectory)
    assert kept.get_suptitle() == "Pendulum with units (RK45)"
    assert (kept.axes[1].get_xlabel(), kept.axes[0].get_xlabel()) == ("θ [rad]", "t [s]")
    assert repr(trajectory).startswith("Trajectory(Pendulum with units: theta; 21 rows")
    # A Trajectory read back from its CSV file knows neither.
    path = Path(tmp_path) / "pendulum.csv"
    trajectory.to_csv(path)
    untitled = overview(lg.Trajectory.from_csv(path))
    assert untitled.get_suptitle().startswith("Simulation")
    assert untitled.axes[0].get_xlabel() == "t"


def test_save_plots_with_the_system_writes_the_picture(tmp_path: Path) -> None:
    system = loads(PENDULUM)
    trajectory = lg.simulate(system, t_span=1.0, samples=21)
    path = save_plots(trajectory, tmp_path / "pendulum.svg", system=system)
    text = path.read_text()
    assert "Pendulum with units" in text  # the SVG keeps its text as glyph comments


@pytest.mark.parametrize(
    ("name", "title"), [("double_pendulum", "double_pendulum"), ("series_rlc", "circuit")]
)
def test_animations_are_titled_with_the_system_name(name: str, title: str) -> None:
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=0.2, samples=5)
    scene = scene_of(system, trajectory, frames=3)
    assert scene.name == name and scene.panels[0].title == title
    assert SceneFigure(scene).axes[0].get_title() == title


def _link_ends(scene: Scene, kind: str, frame: int) -> list[np.ndarray]:
    """The two ends of every spring (or damper) of the scene at ``frame``, (2, 2) each."""
    return [np.asarray(e.info["ends"])[frame] for e in scene.elements(kind)]


def test_a_spring_anchored_where_parameters_say_is_drawn_from_there() -> None:
    system = loads(ANCHORED).with_parameters({"a": 3.0})
    trajectory = lg.simulate(system, t_span=0.5, samples=6)
    scene = scene_of(system, trajectory)
    expected = np.array([[3.0, 0.0], [trajectory["x"][5], trajectory["y"][5]]])  # (a, 0) -> bob
    assert any(np.allclose(ends, expected) for ends in _link_ends(scene, "spring", 5))
    coil = np.asarray(shapes_of(scene, "spring")[0].at("points", 5))
    assert np.allclose(coil[0], expected[0]) and np.allclose(coil[-1], expected[1])


def test_the_walls_of_the_one_dimensional_springs_are_drawn_at_their_parameter_positions() -> None:
    system = lg.examples.two_masses_three_springs()
    a = float(system.parameters[next(p for p in system.parameters if p.name == "a")])
    trajectory = lg.simulate(system, t_span=0.5, samples=6)
    scene = scene_of(system, trajectory)
    wall = np.array([[trajectory["x2"][5] + 2 * a, 0.0], [3 * a, 0.0]])  # mass2 -> wall at 3a
    assert any(np.allclose(ends, wall) for ends in _link_ends(scene, "spring", 5))
    assert [e.info["rest_length"] for e in scene.elements("spring")] == [a, a, a]


def test_a_top_is_drawn_with_its_body_axes_turning_with_the_spin() -> None:
    system = lg.examples.heavy_symmetric_top()
    trajectory = lg.simulate(system, t_span=0.2, samples=11)
    view = projection_matrix("isometric")
    scene = scene_of(system, trajectory, projection="isometric")
    (top,) = scene.elements("body_axes")
    axes = list(top.shapes)
    assert [s.style["color"] for s in axes] == list(AXIS_COLORS)
    for frame in (0, 10):
        drawn = np.array([np.diff(np.asarray(s.at("points", frame)), axis=0)[0] for s in axes])
        phi, theta, psi = (trajectory[n][frame] for n in ("phi", "theta", "psi"))
        # Goldstein's ZXZ angles: the symmetry axis (body z) points from the tip to the centre
        symmetry = np.array(
            [np.sin(phi) * np.sin(theta), -np.cos(phi) * np.sin(theta), np.cos(theta)]
        )
        # the body x axis: the line of nodes (cos phi, sin phi, 0) turned by psi about body z
        nodes = np.array([np.cos(phi), np.sin(phi), 0.0])
        body_x = np.cos(psi) * nodes + np.sin(psi) * np.cross(symmetry, nodes)
        length = np.linalg.norm(drawn[0] - 0) / np.linalg.norm(view @ body_x)
        np.testing.assert_allclose(drawn[2], length * (view @ symmetry), atol=1e-9)
        np.testing.assert_allclose(drawn[0], length * (view @ body_x), atol=1e-9)


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


@pytest.mark.parametrize("name", ["charged_particle_em", "series_rlc", "moving_pivot_pendulum"])
def test_panel_titles_stay_inside_their_panels(name: str) -> None:
    """A long reason the energy is not conserved is wrapped onto lines as wide as its panel,
    not run off the figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    system = lg.examples.get(name)()
    figure = overview(lg.simulate(system, t_span=0.2, samples=9), system=system)
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    renderer = canvas.get_renderer()
    for axes in figure.axes:
        title = axes.title.get_window_extent(renderer)
        panel = axes.get_window_extent(renderer)
        assert figure.bbox.x0 <= title.x0 and title.x1 <= figure.bbox.x1
        assert title.width <= panel.width * 1.05, axes.get_title()
    energy = figure.axes[-1].get_title()
    assert "not conserved" in energy.replace("\n", " ")  # wrapped, every word kept
