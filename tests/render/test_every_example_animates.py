"""Every built-in example animates: its scene holds the elements of its model (checked by
the scene's primitives), a frame shows them (checked by the pixels where the scene puts
them), and a short GIF and the HTML player are written."""

import json

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.render.animation import animate
from lagrangian.render.scene import Scene
from lagrangian.render.scene_draw import SceneFigure

#: What each example's scene must hold besides its points: kinds of element by example.
EXPECTED = {
    "asymmetric_body": {"body", "body_axes"},
    "atwood_machine": {"pulley", "string", "particle"},
    "atwood_machine_with_pulley": {"pulley", "string", "particle"},
    "bouncing_ball": {"coordinates"},
    "capacitor_microphone": {"spring", "damper", "particle", "capacitor", "resistor",
                             "inductor", "source", "current"},
    "compound_pendulum": {"rod", "disc"},
    "cylinder_on_incline": {"ground", "body", "body_axes"},
    "double_pendulum": {"rod", "particle"},
    "heavy_symmetric_top": {"rod", "body", "body_axes"},
    "henon_heiles": {"coordinates"},
    "mass_on_spring": {"coordinates"},
    "mass_spring_damper": {"spring", "damper", "particle"},
    "moving_pivot_pendulum": {"rod", "particle"},
    "newtons_cradle": {"coordinates"},
    "physical_pendulum_3d": {"rod", "body", "body_axes"},
    "quartic_lagrangian": {"coordinates"},
    "simplest_walker": {"coordinates"},
    "rc_rl_circuit": {"resistor", "inductor", "capacitor", "source", "current"},
    "rolling_coin": {"ground", "body", "body_axes"},
    "rolling_disc": {"ground", "body", "body_axes"},
    "series_rlc": {"resistor", "inductor", "capacitor", "source", "current"},
    "servo_system": {"inductor", "mutual", "resistor", "source", "current", "coordinates"},
    "simple_pendulum": {"rod", "particle"},
    "spherical_pendulum": {"rod", "particle"},
    "two_masses_three_springs": {"spring", "particle"},
    "two_mesh_circuit": {"resistor", "inductor", "capacitor", "source", "current"},
}  # fmt: skip


def _scene_pixels(scene: Scene, frame: int) -> tuple[SceneFigure, np.ndarray]:
    figure = SceneFigure(scene, panel_pixels=200)
    return figure, figure.pixels(frame)


def _drawn_at(figure: SceneFigure, pixels: np.ndarray, panel: int, points: np.ndarray) -> float:
    """The share of ``points`` (data units of ``panel``) with ink within 2 pixels."""
    display = figure.axes[panel].transData.transform(np.asarray(points, dtype=float))
    height = pixels.shape[0]
    inked = 0
    for x, y in display:
        row, column = round(height - y), round(x)
        patch = pixels[max(row - 2, 0) : row + 3, max(column - 2, 0) : column + 3]
        inked += bool(patch.size and patch.min() < 200)
    return inked / len(display)


#: One example of each kind runs in the default suite (planar, 3-D, rolling, holonomic
#: constraint, impacts, circuit, electromechanical, coordinates only); the others with the
#: slow tests (each example costs a derivation, a run and a GIF).
EVERY_KIND = {
    "double_pendulum",
    "heavy_symmetric_top",
    "rolling_disc",
    "atwood_machine",
    "bouncing_ball",
    "series_rlc",
    "servo_system",
    "henon_heiles",
}
EXAMPLES = [
    name if name in EVERY_KIND else pytest.param(name, marks=pytest.mark.slow)
    for name in lg.examples.names()
]


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_is_drawn_with_its_elements(name, tmp_path):
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=0.2, samples=9)
    animation = animate(system, trajectory, tmp_path / f"{name}.gif", frames=3)
    scene = animation.scene
    kinds = {element.kind for panel in scene.panels for element in panel.elements}
    assert EXPECTED.get(name, {"particle"}) <= kinds, kinds
    document = json.loads(scene.to_json())  # plain JSON, every moving key given per frame
    for panel in document["panels"]:
        for element in panel["elements"]:
            for shape in element["shapes"]:
                for key in shape["moving"]:
                    assert len(shape[key]) == scene.frames
    figure, pixels = _scene_pixels(scene, 2)
    assert np.std(pixels) > 5  # something is drawn, not a blank canvas
    for k, panel in enumerate(scene.panels):  # every line of every element is where it is put
        for element in panel.elements:
            for shape in element.shapes:
                if shape.type == "line":
                    points = np.asarray(shape.at("points", 2))
                    assert _drawn_at(figure, pixels, k, points) >= 0.8, (element.kind, shape)
    from PIL import Image

    with Image.open(tmp_path / f"{name}.gif") as picture:
        assert picture.n_frames == 3
    page = tmp_path / f"{name}.html"
    animation.save(page)
    assert "lagrangian-scene" in page.read_text()


def test_a_spring_is_a_coil_and_a_disc_shows_its_radius_line():
    """The pixels of the spring's zigzag corners, off the straight line between its ends, are
    inked; the disc's radius line points where the angle theta turns it."""
    system = lg.examples.mass_spring_damper()
    trajectory = lg.simulate(system, t_span=1.0, samples=41)
    scene = animate(system, trajectory, frames=10).scene
    (spring,) = scene.elements("spring")
    coil = np.asarray(spring.shapes[0].at("points", 4))
    a, b = coil[0], coil[-1]
    across = coil[2:-2] - a - np.outer((coil[2:-2] - a) @ (b - a), b - a) / ((b - a) @ (b - a))
    figure, pixels = _scene_pixels(scene, 4)
    scale = figure.axes[0].transData.transform([[0, 0], [1, 0]])
    off_line = np.linalg.norm(across, axis=1) * abs(scale[1, 0] - scale[0, 0])
    assert off_line.min() > 3  # corners are pixels away from a straight spring
    assert _drawn_at(figure, pixels, 0, coil[2:-2]) == 1.0

    system = lg.examples.compound_pendulum()
    trajectory = lg.simulate(system, t_span=1.0, samples=41)
    scene = animate(system, trajectory, frames=10).scene
    (disc,) = scene.elements("disc")
    m, inertia, length = 1.0, 1 / 12, 0.5
    radius = np.sqrt(2 * inertia / m)  # the uniform disc of the body's mass and inertia
    assert disc.info["radius"] == pytest.approx(radius)
    spoke = next(s for s in disc.shapes if s.style["color"] == "#ff7f0e")
    for frame in (0, 6):
        theta = np.interp(scene.times[frame], trajectory.t, trajectory["theta"])
        centre, tip = np.asarray(spoke.at("points", frame))
        np.testing.assert_allclose(centre, [length * np.sin(theta), -length * np.cos(theta)],
                                   atol=1e-9)  # fmt: skip
        np.testing.assert_allclose(tip - centre, radius * np.array([np.cos(theta), np.sin(theta)]),
                                   atol=1e-9)  # fmt: skip
        figure, pixels = _scene_pixels(scene, frame)
        tip_pixel = figure.axes[0].transData.transform([0.8 * tip + 0.2 * centre])[0]
        row, column = round(pixels.shape[0] - tip_pixel[1]), round(tip_pixel[0])
        patch = pixels[row - 2 : row + 3, column - 2 : column + 3].reshape(-1, 3).astype(int)
        orange = np.abs(patch - [255, 127, 14]).max(axis=1) < 60
        assert orange.any()  # the radius line is drawn in its colour where it points
