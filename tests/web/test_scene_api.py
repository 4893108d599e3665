"""The playground's simulate answer carries the run's scene: the command line's animations'
own description (``Scene.to_dict()``), each frame one sample of the run (``rows``).  The
bodies are checked where the physics puts them, from the answer's own columns and the
model's closed forms (a pendulum's bob, a compound pendulum's disc turning with its angle, a
top's symmetry axis and spin, a rolling disc's contact point on the floor, a circuit's mesh
currents and capacitor charges), not from the library's drawing code."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import lagrangian as lg
from lagrangian import examples
from lagrangian.render.scene import scene_of
from lagrangian.render.timing import MAX_FRAMES

#: The scene keeps 5 significant digits.
DIGITS = dict(rtol=2e-4, atol=2e-4)
#: The isometric view (azimuth -60 degrees, elevation 30 degrees, z up), written out here:
#: right = (-sin a, cos a, 0), up = (-sin e cos a, -sin e sin a, cos e).
A, E = np.radians(-60.0), np.radians(30.0)
ISOMETRIC = np.array(
    [[-np.sin(A), np.cos(A), 0.0], [-np.sin(E) * np.cos(A), -np.sin(E) * np.sin(A), np.cos(E)]]
)


def simulate(client: Any, name: str, **options: Any) -> dict[str, Any]:
    model = examples.model_text(name)
    answer = client.post("/api/simulate", json={"model": model, "options": options})
    assert answer.status_code == 200, answer.text
    document: dict[str, Any] = answer.json()
    return document


def element(document: dict[str, Any], kind: str, name: str | None = None) -> dict[str, Any]:
    """The first element of ``kind`` (named ``name``) in any panel."""
    for panel in document["scene"]["panels"]:
        for item in panel["elements"]:
            if item["kind"] == kind and name in (None, item["name"]):
                return dict(item)
    raise AssertionError(f"no {kind} {name or ''} in the scene")


def at_rows(document: dict[str, Any], name: str) -> np.ndarray:
    """A column of the run at the samples the scene's frames show."""
    return np.asarray(document["columns"][name], dtype=float)[document["rows"]]


def test_the_frames_are_samples_of_the_run_and_the_scene_is_the_command_lines(
    client: Any,
) -> None:
    document = simulate(client, "double_pendulum")
    scene, rows, t = document["scene"], document["rows"], document["columns"]["t"]
    assert scene["format"] == "lagrangian-scene" and scene["version"] == 1
    assert len(t) == 1000 and len(rows) == MAX_FRAMES == len(scene["times"])
    assert rows[0] == 0 and rows[-1] == len(t) - 1 and all(np.diff(rows) > 0)
    assert max(np.diff(rows)) - min(np.diff(rows)) <= 1  # evenly spread
    np.testing.assert_allclose(scene["times"], np.asarray(t)[rows], **DIGITS)
    # the same description the command line's animations draw, for the same run
    system = lg.examples.double_pendulum()
    run = lg.simulate(system, t_span=system.simulation["t_end"], samples=1000)
    assert scene == scene_of(system, run, rows=rows).to_dict()


def test_a_planar_chain_bodies_rods_and_a_turning_disc(client: Any) -> None:
    document = simulate(client, "double_pendulum", set=["l1=1.5", "l2=0.5"])
    kinds = [e["kind"] for e in document["scene"]["panels"][0]["elements"]]
    assert kinds == ["rod", "rod", "particle", "particle"]
    theta, phi = at_rows(document, "theta"), at_rows(document, "phi")
    bob1 = np.c_[1.5 * np.sin(theta), -1.5 * np.cos(theta)]
    bob2 = bob1 + np.c_[0.5 * np.sin(phi), -0.5 * np.cos(phi)]
    np.testing.assert_allclose(element(document, "particle", "bob1")["shapes"][0]["at"], bob1,
                               **DIGITS)  # fmt: skip
    np.testing.assert_allclose(element(document, "particle", "bob2")["shapes"][0]["at"], bob2,
                               **DIGITS)  # fmt: skip
    # each rod with its length, that length at every frame
    for rod, length in zip(
        [e for e in document["scene"]["panels"][0]["elements"] if e["kind"] == "rod"],
        (1.5, 0.5),
        strict=True,
    ):
        assert rod["info"]["length"] == length
        ends = np.asarray(rod["shapes"][0]["points"])
        np.testing.assert_allclose(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1), length,
                                   **DIGITS)  # fmt: skip
    # a compound pendulum: its disc (the uniform disc of the same m and I_c, r = sqrt(2 I / m))
    # at (l sin theta, -l cos theta), its radius line turning with theta
    document = simulate(client, "compound_pendulum")
    disc = element(document, "disc")
    radius = np.sqrt(2 * 0.08333333333333333 / 1.0)
    assert disc["info"]["radius"] == pytest.approx(radius, rel=1e-4)
    theta = at_rows(document, "theta")
    centre = np.c_[0.5 * np.sin(theta), -0.5 * np.cos(theta)]
    dot = next(s for s in disc["shapes"] if s["type"] == "dot")
    np.testing.assert_allclose(dot["at"], centre, **DIGITS)
    spoke = next(s for s in disc["shapes"] if s["type"] == "line" and len(s["points"][0]) == 2)
    ends = np.asarray(spoke["points"])
    np.testing.assert_allclose(ends[:, 0], centre, **DIGITS)
    np.testing.assert_allclose(ends[:, 1] - ends[:, 0], radius * np.c_[np.cos(theta),
                               np.sin(theta)], **DIGITS)  # fmt: skip


def test_a_spring_is_a_coil_between_its_ends(client: Any) -> None:
    document = simulate(client, "mass_spring_damper")
    spring = element(document, "spring")
    assert spring["info"]["stiffness"] == "K" and spring["info"]["rest_length"] == 0.0
    coil = np.asarray(spring["shapes"][0]["points"])  # frames, points, 2
    assert coil.shape[1] > 10  # turns, not a bar
    height = 1.0 + at_rows(document, "x")  # the mass hangs at h + x below the anchor at h
    np.testing.assert_allclose(coil[:, -1, 1], height, **DIGITS)
    np.testing.assert_allclose(coil[:, 0, 1], 1.0, **DIGITS)


def test_a_top_is_a_body_with_its_axes_turning_with_the_euler_angles(client: Any) -> None:
    document = simulate(client, "heavy_symmetric_top")
    assert "isometric" in document["scene"]["panels"][0]["title"]
    body, axes = element(document, "body", "top"), element(document, "body_axes", "top")
    assert body["info"]["shape"] == "cylinder"
    phi, theta, psi = (at_rows(document, name) for name in ("phi", "theta", "psi"))
    # ZXZ: R = Rz(phi) Rx(theta) Rz(psi); its third column is the symmetry axis, the centre
    # sits at l along it, its first column turns with the spin psi
    e3 = np.c_[np.sin(phi) * np.sin(theta), -np.cos(phi) * np.sin(theta), np.cos(theta)]
    e1 = np.c_[
        np.cos(phi) * np.cos(psi) - np.sin(phi) * np.cos(theta) * np.sin(psi),
        np.sin(phi) * np.cos(psi) + np.cos(phi) * np.cos(theta) * np.sin(psi),
        np.sin(theta) * np.sin(psi),
    ]
    dot = next(s for s in body["shapes"] if s["type"] == "dot")
    np.testing.assert_allclose(dot["at"], 0.1 * e3 @ ISOMETRIC.T, **DIGITS)
    red, _, blue = (np.asarray(s["points"]) for s in axes["shapes"])
    assert [s["color"] for s in axes["shapes"]] == ["#d62728", "#2ca02c", "#1f77b4"]
    length = np.linalg.norm((blue[0, 1] - blue[0, 0]) / np.linalg.norm(ISOMETRIC @ e3[0]))
    np.testing.assert_allclose(blue[:, 1] - blue[:, 0], length * e3 @ ISOMETRIC.T, rtol=1e-3,
                               atol=1e-3 * length)  # fmt: skip
    np.testing.assert_allclose(red[:, 1] - red[:, 0], length * e1 @ ISOMETRIC.T, rtol=1e-3,
                               atol=1e-3 * length)  # fmt: skip
    assert np.ptp(psi) > 2 * np.pi  # the spin is seen: the red axis goes round


def test_a_rolling_disc_is_a_disc_on_the_floor_it_rolls_on(client: Any) -> None:
    document = simulate(client, "rolling_disc")  # two velocity constraints: rolling
    body = element(document, "body", "disc")
    assert body["info"] == {"shape": "disc", "radius": 0.3}
    x, y, psi, theta = (at_rows(document, name) for name in ("x", "y", "psi", "theta"))
    centre = np.c_[x + 0.3 * np.sin(psi) * np.sin(theta), y - 0.3 * np.cos(psi) * np.sin(theta),
                   0.3 * np.cos(theta)]  # fmt: skip
    dot = next(s for s in body["shapes"] if s["type"] == "dot")
    np.testing.assert_allclose(dot["at"], centre @ ISOMETRIC.T, **DIGITS)
    # the rim is a circle of radius r about the centre, in the disc's plane: every rim point
    # r from the centre in space; seen isometric, no farther than r from the centre's image
    rim = np.asarray(body["shapes"][0]["points"])
    offsets = np.linalg.norm(rim - np.asarray(dot["at"])[:, None, :], axis=2)
    assert offsets.max() <= 0.3 * (1 + 1e-3) and offsets.max(axis=1).min() >= 0.3 * 0.95
    ground = element(document, "ground", "disc")
    assert ground["info"]["curve"] == "plane" and abs(ground["info"]["height"]) < 1e-9
    track = next(s for s in ground["shapes"] if s["type"] == "dot")
    contact = np.c_[x, y, np.zeros_like(x)]  # the contact point (x, y) on the floor z = 0
    np.testing.assert_allclose(track["at"], contact @ ISOMETRIC.T, **DIGITS)


def test_an_impact_flashes_the_frame_of_its_sample(client: Any) -> None:
    document = simulate(client, "bouncing_ball")
    impacts = document["summary"]["impacts"]
    flashed = document["scene"]["impacts"]
    assert impacts and flashed
    times = np.asarray(document["columns"]["t"])[document["rows"]]
    for flash in flashed:  # the first frame at or after an impact of the run
        k = flash["frame"]
        struck = [i["t"] for i in impacts if (k == 0 or times[k - 1] < i["t"]) and
                  i["t"] <= times[k] + 1e-9]  # fmt: skip
        assert struck, (k, times[k])
        # the bounces near rest come several a frame: the label counts them
        many = f"{len(struck)} impacts: floor"
        assert flash["label"] == ("impact: floor" if len(struck) == 1 else many)


@pytest.mark.parametrize("name", ["two_mesh_circuit", "series_rlc"])
def test_a_circuit_is_its_schematic_with_its_mesh_currents(client: Any, name: str) -> None:
    document = simulate(client, name)
    kinds = {e["kind"] for e in document["scene"]["panels"][0]["elements"]}
    assert {"inductor", "capacitor", "resistor", "source", "current"} <= kinds
    meshes = [q for q in ("q", "q1", "q2") if q in document["columns"]]
    for mesh in meshes:
        arrow = element(document, "current", f"{mesh}_dot")
        current = at_rows(document, f"{mesh}_dot")
        largest = np.abs(np.asarray(document["columns"][f"{mesh}_dot"])[document["rows"]]).max()
        shaft = np.asarray(arrow["shapes"][0]["points"])  # its length 2.4 at the largest
        np.testing.assert_allclose(shaft[:, 1, 0] - shaft[:, 0, 0], 2.4 * current / largest,
                                   **DIGITS)  # fmt: skip
        words = arrow["shapes"][2]["text"]
        assert words == [f"i = {value:.3g}" for value in current]
        # the capacitor on this mesh alone holds its charge: written under its capacitance
        capacitor = next(
            e
            for panel in document["scene"]["panels"]
            for e in panel["elements"]
            if e["kind"] == "capacitor" and e["info"]["branch"] == mesh
        )
        charge = next(s for s in capacitor["shapes"] if s["type"] == "text" and s["moving"])
        assert charge["text"] == [f"q = {value:.3g}" for value in at_rows(document, mesh)]


def test_one_drawing_code_for_the_page_and_the_html_animations(client: Any) -> None:
    from lagrangian.render.scene_player import drawing_script, scene_html

    served = client.get("/static/scene_player.js")
    assert served.status_code == 200 and "javascript" in served.headers["content-type"]
    assert served.text == drawing_script() and "LagrangianScene" in served.text
    page = client.get("/").text
    assert page.index("/static/scene_player.js") < page.index("/static/app.js")
    system = lg.examples.simple_pendulum()
    html = scene_html(scene_of(system, lg.simulate(system, t_span=1.0, samples=11), frames=4))
    assert drawing_script() in html  # inlined: the HTML file stands alone
