"""The gas of hard disks, built in Python to a size, in the playground: the examples menu lists
it with its size, the server writes its model file at the size asked (the same System the
Python builder makes), and its run's scene draws each disk at its radius where the run's own
columns put it, inside the box its parameters give, with every impact flashed at the first
frame after it."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import lagrangian as lg
from lagrangian import examples

#: The scene keeps 5 significant digits.
DIGITS = dict(rtol=2e-4, atol=2e-4)


def gas_model(client: Any, size: int | None = None) -> str:
    query = "" if size is None else f"?size={size}"
    answer = client.get(f"/api/examples/hard_disk_gas{query}")
    assert answer.status_code == 200, answer.text
    assert answer.json()["format"] == "yaml"
    model: str = answer.json()["model"]
    return model


def test_the_menu_lists_the_examples_built_to_a_size(client: Any) -> None:
    listed = {entry["name"]: entry for entry in client.get("/api/examples").json()["examples"]}
    assert listed["hard_disk_gas"]["size"] == {"counts": "disks", "default": 4, "largest": 25}
    assert listed["n_link_pendulum"]["size"]["counts"] == "links"
    assert "size" not in listed["double_pendulum"]


@pytest.mark.parametrize("size", [None, 1, 9])
def test_the_model_written_is_the_gas_the_python_builder_makes(client: Any, size: Any) -> None:
    read = lg.loads(gas_model(client, size))
    built = examples.hard_disk_gas(4 if size is None else size)
    assert read.coordinates == built.coordinates
    assert read.parameters == built.parameters and read.initial == built.initial
    assert [(c.name, c.expression, c.restitution) for c in read.constraints] == [
        (c.name, c.expression, c.restitution) for c in built.constraints
    ]
    assert [(p.name, tuple(p.position)) for p in read.particles] == [
        (p.name, tuple(p.position)) for p in built.particles
    ]


@pytest.mark.parametrize(
    ("query", "fix"),
    [
        ("hard_disk_gas?size=0", "from 1 to 25"),
        ("hard_disk_gas?size=four", "from 1 to 25"),
        ("hard_disk_gas?size=40", "hard_disk_gas:40"),
        ("double_pendulum?size=2", "leave out"),
    ],
)
def test_a_size_out_of_bounds_is_refused_by_name(client: Any, query: str, fix: str) -> None:
    answer = client.get(f"/api/examples/{query}")
    assert answer.status_code == 422
    problem = answer.json()["problems"][0]
    assert problem["field"] == "size" and fix in problem["fix"]


def test_the_gas_is_drawn_as_disks_in_its_box_and_flashes_its_impacts(client: Any) -> None:
    answer = client.post("/api/simulate", json={"model": gas_model(client, 9), "options": {}})
    assert answer.status_code == 200, answer.text
    document = answer.json()
    scene, rows, columns = document["scene"], document["rows"], document["columns"]
    (panel,) = scene["panels"]
    side = 1.0
    r = side / 3 / 5  # nine disks on a 3 x 3 lattice: a fifth of its spacing L / 3
    walls = [e for e in panel["elements"] if e["kind"] == "wall"]
    disks = [e for e in panel["elements"] if e["kind"] == "particle"]
    assert len(walls) == 4 and len(disks) == 9
    # the four walls are the sides of the box [0, L] x [0, L], each drawn once
    sides = sorted(tuple(np.round(np.asarray(w["shapes"][0]["points"]), 9).tolist()) for w in walls)
    expected = [((0, 0), (0, 1)), ((0, 0), (1, 0)), ((0, 1), (1, 1)), ((1, 0), (1, 1))]
    assert sorted(tuple(sorted(map(tuple, s))) for s in sides) == sorted(expected)
    for k, disk in enumerate(disks, start=1):
        circle, dot = disk["shapes"]
        assert circle["type"] == "circle" and disk["info"]["radius"] == pytest.approx(r, rel=1e-4)
        assert circle["radius"] == pytest.approx(r, rel=1e-4)
        centre = np.c_[np.asarray(columns[f"x{k}"])[rows], np.asarray(columns[f"y{k}"])[rows]]
        np.testing.assert_allclose(circle["centre"], centre, **DIGITS)
        np.testing.assert_allclose(dot["at"], centre, **DIGITS)
        drawn = np.asarray(circle["centre"])  # the whole disk inside the box at every frame
        assert np.all(drawn - r >= -1e-4) and np.all(drawn + r <= side + 1e-4)
    # every impact flashes the first frame at or after it, and the label names what struck
    impacts = document["summary"]["impacts"]
    times = np.asarray(scene["times"])
    flashed = {f["frame"]: f["label"] for f in scene["impacts"]}
    assert len(impacts) > 9
    for impact in impacts:
        frame = int(np.argmax(times >= impact["t"] - 1e-4))
        assert frame in flashed and "impact" in flashed[frame]
        named = flashed[frame].split(":", 1)[1]
        assert impact["constraints"][0] in named or "more" in named
