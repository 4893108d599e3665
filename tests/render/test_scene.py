"""The scene of a system, checked against the geometry worked by hand: a bead's hoop turning
with the hoop, a parabola wire, an Atwood machine's string keeping its length, the incline a
cylinder rolls on, the floor a disc rolls on, a circuit's currents and shared branch, the
motion of coordinates without geometry, impacts flashed, and the frames chosen from the
motion's time scale."""

from __future__ import annotations

import json

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.io import loads
from lagrangian.render.scene import Shape, scene_of, shapes_of
from lagrangian.render.scene_draw import SceneFigure
from lagrangian.render.timing import (
    MAX_FRAMES,
    MIN_FRAMES,
    frame_count,
    frame_states,
    spread_rows,
)

#: A bead on a hoop of radius R turning at omega about the vertical z axis (Goldstein 2.6).
HOOP = """\
name: bead on a rotating hoop
coordinates: [theta]
parameters: {m: 1.0, R: 0.5, omega: 3.0, g: 9.81}
gravity: [0, 0, -g]
particles:
- {name: bead, mass: m, position: ["R*sin(theta)*cos(omega*t)", "R*sin(theta)*sin(omega*t)",
                                   "-R*cos(theta)"]}
initial: {theta: 0.4, theta_dot: 0.0}
"""

#: A bead on the wire y = a x^2.
PARABOLA = """\
name: bead on a parabola
coordinates: [x]
parameters: {m: 1.0, a: 2.0, g: 9.81}
gravity: [0, -g]
particles: [{name: bead, mass: m, position: [x, a*x**2]}]
initial: {x: 0.5, x_dot: 0.0}
"""


def _run(system: lg.System, t_end: float = 1.0, samples: int = 41) -> lg.Trajectory:
    return lg.simulate(system, t_span=t_end, samples=samples)


def test_a_bead_on_a_turning_hoop_is_drawn_on_the_hoop_as_it_turns() -> None:
    system = loads(HOOP)
    trajectory = _run(system)
    scene = scene_of(system, trajectory, frames=12, projection="xy")  # seen from above
    (wire,) = scene.elements("wire")
    assert wire.info == {"curve": "circle", "moving": True}
    assert "rod" not in scene.panels[0].kinds()  # the hoop holds the bead, no rod
    R, omega = 0.5, 3.0
    for frame in (0, 5, 11):
        hoop = np.asarray(wire.shapes[0].at("points", frame))
        along = np.array([np.cos(omega * scene.times[frame]), np.sin(omega * scene.times[frame])])
        # from above, the hoop is its diameter along (cos wt, sin wt), of length 2R
        np.testing.assert_allclose(hoop @ np.array([-along[1], along[0]]), 0.0, atol=1e-9)
        assert np.ptp(hoop @ along) == pytest.approx(2 * R, rel=1e-3)
        (bead,) = shapes_of(scene, "particle")
        at = np.asarray(bead.at("at", frame))
        assert abs(at @ np.array([-along[1], along[0]])) < 1e-9  # the bead is on it


def test_a_bead_on_a_parabola_runs_on_the_parabola_drawn() -> None:
    system = loads(PARABOLA)
    scene = scene_of(system, _run(system), frames=10)
    (wire,) = scene.elements("wire")
    assert wire.info["curve"] == "parabola" and not wire.info["moving"]
    points = np.asarray(wire.shapes[0].data["points"])
    np.testing.assert_allclose(points[:, 1], 2.0 * points[:, 0] ** 2, atol=1e-12)
    assert points[:, 0].min() < -0.5 and points[:, 0].max() > 0.5  # beyond the run's swing


def test_a_pendulum_gets_a_rod_not_a_hoop() -> None:
    system = lg.examples.simple_pendulum()
    scene = scene_of(system, _run(system), frames=5)
    assert scene.panels[0].kinds() == ["rod", "particle"]
    assert scene.elements("rod")[0].info["length"] == pytest.approx(1.0)


def test_an_atwood_string_keeps_its_length_over_the_pulley() -> None:
    system = lg.examples.atwood_machine()  # masses at x = -R, R; heights -y and y - l
    trajectory = _run(system, t_end=0.5)
    scene = scene_of(system, trajectory, frames=8)
    (pulley,) = scene.elements("pulley")
    (string,) = scene.elements("string")
    R, l = 0.1, 2.0
    assert pulley.info["radius"] == pytest.approx(R)
    lengths = [
        np.linalg.norm(np.diff(np.asarray(string.shapes[0].at("points", k)), axis=0), axis=1).sum()
        for k in range(scene.frames)
    ]
    # two hanging parts (h + y) + (h - y + l) and the half turn pi R, whatever y is
    np.testing.assert_allclose(lengths, lengths[0], rtol=1e-3)  # the arc is 16 chords
    rim = pulley.shapes[0]
    height = rim.data["centre"][1]
    assert lengths[0] == pytest.approx(2 * height + l + np.pi * R, rel=2e-3)
    ends = np.asarray(string.shapes[0].at("points", 3))
    y = np.interp(scene.times[3], trajectory.t, trajectory["y"])
    np.testing.assert_allclose(ends[[0, -1]], [[-R, -y], [R, y - l]], atol=1e-9)


def test_a_pulley_body_takes_the_radius_of_its_strings() -> None:
    system = lg.examples.atwood_machine_with_pulley()
    scene = scene_of(system, _run(system, t_end=0.5), frames=8)
    (pulley,) = scene.elements("pulley")
    assert pulley.name == "pulley" and pulley.info["radius"] == pytest.approx(0.1)


def test_a_cylinder_rolls_on_the_incline_drawn_under_it() -> None:
    system = lg.examples.cylinder_on_incline()
    trajectory = _run(system)
    scene = scene_of(system, trajectory, frames=10)
    assert scene.panels[0].title.endswith("(xz view)")  # the plane it moves in
    (ground,) = scene.elements("ground")
    a, b = np.asarray(ground.shapes[0].data["points"])
    alpha, r = 0.3, 0.1
    assert np.arctan2(b[1] - a[1], b[0] - a[0]) == pytest.approx(-alpha)
    (body,) = scene.elements("body")
    centre = np.asarray(body.shapes[-1].data["at"])  # the centre's dot, every frame
    unit = (b - a) / np.linalg.norm(b - a)
    offset = centre - a
    distance = np.abs(unit[0] * offset[:, 1] - unit[1] * offset[:, 0])
    np.testing.assert_allclose(distance, r, rtol=1e-9)  # touching it all the way


def test_a_rolling_disc_touches_the_floor_drawn_under_it() -> None:
    system = lg.examples.rolling_disc()
    scene = scene_of(system, _run(system, samples=21), frames=10)
    (ground,) = scene.elements("ground")
    assert ground.info["curve"] == "plane" and ground.info["height"] == pytest.approx(0, abs=1e-9)


def test_a_circuit_shows_its_currents_and_its_shared_branch() -> None:
    system = lg.examples.two_mesh_circuit()
    trajectory = _run(system, t_end=0.02)
    scene = scene_of(system, trajectory, frames=10)
    shared = next(e for e in scene.elements("inductor") if e.info["branch"] == "q1_dot - q2_dot")
    xs = np.concatenate([np.asarray(s.data["points"])[:, 0] for s in shared.shapes
                         if s.type == "line"])  # fmt: skip
    np.testing.assert_allclose(xs, 4.0, atol=0.5)  # on the edge both loops share
    for current in scene.elements("current"):
        arrow = current.shapes[0]
        values = np.interp(scene.times, trajectory.t, trajectory[current.name])
        lengths = [np.diff(np.asarray(arrow.at("points", k))[:, 0])[0] for k in range(10)]
        np.testing.assert_allclose(lengths, 2.4 * values / np.abs(values).max(), atol=1e-9)
        assert current.shapes[2].at("text", 9) == f"i = {values[9]:.3g}"


@pytest.mark.parametrize(
    ("name", "panel"),
    [("henon_heiles", "configuration space"), ("newtons_cradle", "coordinates / largest")],
)
def test_a_model_of_energies_alone_is_drawn_as_its_moving_coordinates(name, panel) -> None:
    system = lg.examples.get(name)()
    trajectory = _run(system, t_end=0.5)
    scene = scene_of(system, trajectory, frames=6)
    (only,) = scene.panels
    assert only.title.startswith(panel)
    names = list(trajectory.coordinates)
    values = np.stack([np.interp(scene.times, trajectory.t, trajectory[n]) for n in names], 1)
    moving = [s for s in shapes_of(scene, "coordinates") if s.moving]
    if len(names) == 2:
        np.testing.assert_allclose(np.asarray(moving[0].data["at"]), values, atol=1e-12)
    else:
        bars = [np.asarray(s.data["points"])[:, 1, 0] for s in moving if s.style["width"] == 8.0]
        largest = np.abs(values).max(axis=0)
        largest[largest == 0] = 1.0  # a coordinate at rest: its bar stays at 0
        np.testing.assert_allclose(np.stack(bars, 1), values / largest, atol=1e-12)


def test_an_impact_flashes_its_frame() -> None:
    system = lg.examples.bouncing_ball()
    trajectory = lg.simulate(system, t_span=1.0, samples=101)
    assert trajectory.impacts  # it lands at t = sqrt(2 h / g) = 0.4515 s
    scene = scene_of(system, trajectory, frames=40)
    ((frame, label),) = scene.impacts
    assert label == "impact: floor"
    assert scene.times[frame - 1] < np.sqrt(2 / 9.81) <= scene.times[frame]
    figure = SceneFigure(scene, panel_pixels=200)
    red = [np.all(np.abs(figure.pixels(k).astype(int) - [214, 39, 40]) < 30, axis=-1).sum()
           for k in (frame - 2, frame)]  # fmt: skip
    assert red[0] == 0 and red[1] > 200  # a red border at the impact, none before


def test_the_frames_follow_the_motion_and_interpolate_the_run() -> None:
    from scipy.special import ellipk

    for length in (0.25, 1.0):
        pendulum = lg.examples.simple_pendulum().with_parameters({"l": length})
        theta0 = float(pendulum.initial[next(iter(pendulum.initial))])
        # the exact period T = 4 sqrt(l/g) K(sin^2(theta0/2)); turning every T/2 after rest
        period = 4 * np.sqrt(length / 9.81) * ellipk(np.sin(theta0 / 2) ** 2)
        turns = int(10.0 // (period / 2))
        assert frame_count(_run(pendulum, 10.0, 1001)) == max(10 * turns, MIN_FRAMES)
    free = loads(PARABOLA.replace("a: 2.0", "a: 0.0").replace("g: 9.81", "g: 0.0"))
    moving = lg.simulate(free, t_span=1.0, samples=11, initial={"x": 0.0, "x_dot": 1.0})
    assert frame_count(moving) == MIN_FRAMES  # a motion that never turns
    trajectory = _run(lg.examples.simple_pendulum(), 2.0, 21)
    states = frame_states(trajectory, 7)
    np.testing.assert_allclose(states.t, np.linspace(0.0, 2.0, 7))
    np.testing.assert_allclose(
        states.column("theta"), np.interp(states.t, trajectory.t, trajectory["theta"])
    )


def test_frames_at_the_runs_own_samples_show_those_samples() -> None:
    system = lg.examples.double_pendulum()
    trajectory = _run(system, 3.0, 1000)
    rows = spread_rows(len(trajectory.t))
    assert len(rows) == MAX_FRAMES and rows[0] == 0 and rows[-1] == 999
    assert set(np.diff(rows)) <= {3, 4}  # 999 / 299 apart, evenly
    scene = scene_of(system, trajectory, rows=rows)
    np.testing.assert_array_equal(scene.times, trajectory.t[rows])  # no interpolation
    theta = trajectory["theta"][rows]
    bob = np.asarray(next(iter(shapes_of(scene, "particle"))).data["at"])
    np.testing.assert_allclose(bob, np.c_[np.sin(theta), -np.cos(theta)], atol=1e-12)
    assert spread_rows(7, 300).tolist() == list(range(7))
    with pytest.raises(ValueError, match="frames or rows, not both"):
        scene_of(system, trajectory, frames=10, rows=rows)
    with pytest.raises(ValueError, match="rows must be increasing"):
        scene_of(system, trajectory, rows=[3, 2])
    with pytest.raises(ValueError, match=r"rows must lie in 0\.\.999"):
        scene_of(system, trajectory, rows=[0, 1000])


def test_a_capacitor_shows_its_charge() -> None:
    system = lg.examples.two_mesh_circuit()
    trajectory = _run(system, t_end=0.02)
    scene = scene_of(system, trajectory, rows=spread_rows(len(trajectory.t), 25))
    for capacitor in scene.elements("capacitor"):  # C1 holds q1, C2 holds q2
        charge = trajectory[capacitor.info["branch"]][spread_rows(len(trajectory.t), 25)]
        words = next(s for s in capacitor.shapes if s.type == "text" and s.moving_keys)
        assert list(words.data["text"]) == [f"q = {value:.3g}" for value in charge]


def test_numbers_keep_five_significant_digits_as_printf_rounds_them() -> None:
    rng = np.random.default_rng(7)
    values = rng.normal(size=(4000, 2)) * 10.0 ** rng.integers(-30, 30, size=(4000, 2))
    values[:4] = [[0.0, np.nan], [np.inf, 1e-320], [9.99995, 0.5], [-12345.5, 1.5e300]]
    shown = Shape("line", {"points": values}).to_dict()["points"]
    expected = [[float(f"{v:.5g}") if np.isfinite(v) else 0.0 for v in row] for row in values]
    assert shown == expected


def test_the_scene_is_plain_json_in_its_documented_format() -> None:
    system = lg.examples.double_pendulum()
    scene = scene_of(system, _run(system), frames=6, fps=12)
    document = json.loads(scene.to_json())
    assert (document["format"], document["version"], document["fps"]) == ("lagrangian-scene", 1, 12)
    assert len(document["times"]) == 6 and document["impacts"] == []
    (panel,) = document["panels"]
    assert [e["kind"] for e in panel["elements"]] == ["rod", "rod", "particle", "particle"]
    rod = panel["elements"][0]["shapes"][0]
    assert rod["type"] == "line" and rod["moving"] == ["points"]
    assert np.asarray(rod["points"]).shape == (6, 2, 2)


def test_an_unknown_projection_is_refused_with_the_choices() -> None:
    system = lg.examples.heavy_symmetric_top()
    with pytest.raises(SimulationInputError, match=r"'side' is not a projection.*isometric"):
        scene_of(system, _run(system, 0.1, 5), projection="side")


def test_meshes_coupled_only_by_a_mutual_inductance_are_two_closed_loops() -> None:
    system = lg.examples.servo_system()
    scene = scene_of(system, _run(system, t_end=0.01, samples=11), frames=5)
    circuit = scene.panels[0]
    sides = set()
    for element in circuit.elements:
        for shape in element.shapes:
            if element.kind != "mutual" and shape.type == "line":
                points = np.asarray(shape.data["points"])
                if np.ptp(points[:, 0]) < 1e-12 and np.ptp(points[:, 1]) > 0:
                    sides.add(round(float(points[0, 0]), 6))
    assert sides == {0.0, 3.6, 4.4, 8.0}  # each loop has both its sides, apart
    (mutual,) = scene.elements("mutual")
    assert mutual.info["value"] == "LM*cos(q3)"
    assert [p.kinds() for p in scene.panels][1] == ["coordinates"]  # the rotor angle q3
