"""The web API words every fix in the names of its request: ``options.initial.x``,
``options.t_end``, ``options.method = "DOP853"``, never a flag or a Python keyword."""

from __future__ import annotations

import re
from typing import Any

from lagrangian import examples

NO_INITIAL = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"
OTHER_WORDS = re.compile(r"--\w|\b(t_span|initial|max_steps|method|rtol|atol)=")
ROD = """coordinates: [x, y]
parameters: {m: 1, g: 9.81, l: 1}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: x**2 + y**2 - l**2}
"""


def problems(client: Any, command: str, model: str, options: dict[str, Any]) -> list[Any]:
    answer = client.post(f"/api/{command}", json={"model": model, "options": options})
    assert answer.status_code == 422, answer.text
    found = answer.json()["problems"]
    assert not any(OTHER_WORDS.search(p["field"] + p["fix"]) for p in found), found
    return list(found)


def test_a_missing_initial_value_names_options_initial(client: Any) -> None:
    found = problems(client, "simulate", NO_INITIAL, {})
    fixes = " ".join(p["fix"] for p in found)
    assert "pass options.initial.x," in fixes and "pass options.initial.x_dot," in fixes
    assert "pass the end time, options.t_end," in fixes
    given = {"initial": {"x": 0.5, "x_dot": 0.0}, "t_end": 1.0, "samples": 5}
    answer = client.post("/api/simulate", json={"model": NO_INITIAL, "options": given})
    assert answer.status_code == 200, answer.text
    assert answer.json()["columns"]["x"][0] == 0.5


def test_an_option_that_does_not_apply_names_the_request_options(client: Any) -> None:
    options = {"method": "RK4", "rtol": 1e-6, "dt": 0.01, "t_end": 1.0}
    found = problems(client, "simulate", examples.model_text("simple_pendulum"), options)
    rtol = [p for p in found if p["field"] == "options.rtol"]
    assert rtol and rtol[0]["fix"] == (
        'remove options.rtol, or choose an adaptive method such as options.method = "DOP853"'
    )


def test_an_about_state_off_the_constraints_names_options_project(client: Any) -> None:
    found = problems(client, "analyze", ROD, {"about": {"x": 0.0, "y": -0.5}})
    assert any("pass options.project = true" in p["fix"] for p in found), found
    assert not any("project=True" in p["fix"] for p in found), found
