"""The JSON API answers what the command line prints (shared/DESIGN.md), with every problem
of a bad request listed at its place."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

import lagrangian as lg
from lagrangian import examples
from lagrangian.cli import commands

DOUBLE = examples.model_text("double_pendulum")
SIMPLE = examples.model_text("simple_pendulum")


def test_the_examples_menu_lists_every_example(client: Any) -> None:
    listed = client.get("/api/examples").json()["examples"]
    names = [entry["name"] for entry in listed]
    assert names == [*examples.names(), *examples.BENCHMARKS]  # those built in Python too
    answer = client.get("/api/examples/series_rlc").json()
    assert answer["model"] == examples.model_text("series_rlc")
    assert answer["format"] == "yaml" and answer["description"] == examples.describe("series_rlc")


def test_an_unknown_example_is_404(client: Any) -> None:
    answer = client.get("/api/examples/no_such_thing")
    assert answer.status_code == 404
    assert answer.json()["problems"][0]["field"] == "name"


def test_derive_answers_the_cli_json(client: Any) -> None:
    answer = client.post("/api/derive", json={"model": DOUBLE, "options": {"set": {"m1": 2}}})
    assert answer.status_code == 200
    document = answer.json()
    cli = json.loads(
        commands.derive_command(
            "examples/double_pendulum", fmt="json", steps=True, matrix=False, settings=["m1=2"]
        )
    )
    latex = document.pop("latex")
    assert document.pop("initial") == {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
    assert document == cli
    assert r"\frac{d}{dt}" in latex and r"\ddot{\theta}" in latex


def test_derive_with_constraints_adds_the_multipliers(client: Any) -> None:
    model = examples.model_text("atwood_machine")
    document = client.post("/api/derive", json={"model": model}).json()
    cli = json.loads(
        commands.derive_command(
            "examples/atwood_machine", fmt="json", steps=True, matrix=False, settings=[]
        )
    )
    document.pop("latex"), document.pop("initial")
    assert document == cli


def test_analyze_answers_the_cli_json(client: Any) -> None:
    model = examples.model_text("spherical_pendulum")
    options = {"about": {"theta": 0.5, "phi_dot": 2.0}}
    document = client.post("/api/analyze", json={"model": model, "options": options}).json()
    cli = json.loads(
        commands.analyze_command(
            "examples/spherical_pendulum", about="theta=0.5,phi_dot=2", inputs=[], settings=[]
        )
    )
    for key in ("dof", "momenta", "conserved", "hamiltonian", "equilibria", "linearization"):
        assert document[key] == cli[key], key
    assert "p_{\\phi}" in document["latex"]


def test_simulate_gives_the_columns_of_the_csv_and_the_scene(client: Any) -> None:
    options = {"t_end": 2.0, "samples": 41, "set": ["l=2"]}
    answer = client.post("/api/simulate", json={"model": SIMPLE, "options": options})
    assert answer.status_code == 200
    document = answer.json()
    reference = lg.simulate(
        lg.examples.simple_pendulum(), t_span=2.0, samples=41, parameters={"l": 2.0}
    )
    columns = document["columns"]
    assert list(columns) == list(reference.names)
    for name in reference.names:
        np.testing.assert_allclose(columns[name], reference[name], rtol=1e-12, atol=1e-12)
    summary = document["summary"]
    assert summary["status"] == "success" and summary["samples"] == 41
    assert summary["parameters"]["l"] == 2.0 and summary["drift"]["energy_relative"] < 1e-4
    # the bob at (l sin theta, -l cos theta) at each frame's sample: the closed form, not the
    # library's code (the scene keeps 5 significant digits)
    assert document["rows"] == list(range(41))  # few samples: every one is a frame
    theta = np.array(columns["theta"])
    elements = document["scene"]["panels"][0]["elements"]
    assert [e["kind"] for e in elements] == ["rod", "particle"]
    bob = np.array(elements[1]["shapes"][0]["at"])
    np.testing.assert_allclose(bob, np.c_[2 * np.sin(theta), -2 * np.cos(theta)], atol=1e-4)
    assert elements[0]["info"]["length"] == 2.0


@pytest.mark.parametrize(
    ("text", "fmt"),
    [
        ('coordinates = ["x"]\nkinetic = "x_dot**2/2"\npotential = "x**2/2"\n', "toml"),
        ('{"coordinates": ["x"], "kinetic": "x_dot**2/2", "potential": "x**2/2"}', "json"),
    ],
)
def test_toml_and_json_models(client: Any, text: str, fmt: str) -> None:
    document = client.post("/api/derive", json={"model": text, "format": fmt}).json()
    assert document["equations"] == ["x + x_ddot"]


def test_a_bad_model_is_422_with_its_line_and_column(client: Any) -> None:
    model = "coordinates: [x]\nparameters: {k: 1}\npotential: k*x**\n"
    answer = client.post("/api/derive", json={"model": model})
    assert answer.status_code == 422
    (problem,) = answer.json()["problems"]
    assert set(problem) == {"field", "line", "column", "message", "fix"}
    assert (problem["field"], problem["line"]) == ("potential", 3)
    assert problem["column"] >= 12 and problem["fix"]


def test_every_problem_of_the_request_at_once(client: Any) -> None:
    body = {"model": "", "format": "xml", "options": {"t_end": "long", "colour": 1}, "x": 1}
    answer = client.post("/api/simulate", json=body)
    assert answer.status_code == 422
    fields = sorted(problem["field"] for problem in answer.json()["problems"])
    assert fields == ["format", "model", "options.colour", "options.t_end", "x"]


def test_a_failed_simulation_is_422(client: Any) -> None:
    options = {"method": "RK99"}
    answer = client.post("/api/simulate", json={"model": SIMPLE, "options": options})
    assert answer.status_code == 422
    problems = answer.json()["problems"]
    assert any(p["field"] == "options.method" for p in problems), problems
    assert not any("--" in p["field"] + p["fix"] for p in problems), problems


def test_an_oversized_body_is_413(client: Any) -> None:
    model = "coordinates: [x]\nkinetic: x_dot**2/2\n" + "# padding\n" * 25_000
    answer = client.post("/api/derive", json={"model": model})
    assert answer.status_code == 413
    assert "kB" in answer.json()["problems"][0]["message"]


def test_a_body_that_is_not_json(client: Any) -> None:
    assert client.post("/api/derive", content=b"coordinates: [x]").status_code == 415
    headers = {"Content-Type": "application/json"}
    answer = client.post("/api/derive", content=b"{not json", headers=headers)
    assert answer.status_code == 400 and answer.json()["problems"][0]["field"] == "body"


def test_an_unknown_command_is_404(client: Any) -> None:
    answer = client.post("/api/integrate", json={"model": SIMPLE})
    assert answer.status_code == 404 and "/api/export" in answer.json()["problems"][0]["fix"]


def test_the_page_and_its_assets_are_served_locally(client: Any) -> None:
    page = client.get("/")
    assert page.status_code == 200
    for testid in ("editor", "derive-button", "analyze-button", "simulate-button"):
        assert f'data-testid="{testid}"' in page.text
    for testid in ("equations", "canvas", "errors"):
        assert f'data-testid="{testid}"' in page.text
    assert "default-src 'self'" in page.headers["content-security-policy"]
    assert "http" not in page.text.replace('lang="en"', "")  # no asset from elsewhere
    for asset in (
        "app.js",
        "equations.js",
        "style.css",
        "katex/katex.min.js",
        "katex/katex.min.css",
    ):
        assert client.get(f"/static/{asset}").status_code == 200
    font = client.get("/static/katex/fonts/KaTeX_Main-Regular.woff2")
    assert font.status_code == 200 and font.content[:4] == b"wOF2"


def test_analyze_takes_the_search_degree_of_the_command_line(client: Any) -> None:
    model = examples.model_text("atwood_machine")
    searched = client.post("/api/analyze", json={"model": model}).json()
    # the Atwood machine's time-dependent momentum (m1 + m2) y_dot - g (m1 - m2) t
    assert "point symmetry" in {q["origin"] for q in searched["conserved_quantities"]}
    off = {"model": model, "options": {"search_degree": 0}}
    document = client.post("/api/analyze", json=off).json()
    assert document["first_integral_search"] == []
    assert [q["origin"] for q in document["conserved_quantities"]] == ["energy"]
    bad = client.post("/api/analyze", json={"model": model, "options": {"search_degree": 9}})
    assert bad.status_code == 422 and "search_degree" in bad.text


def _module_from(tmp_path: Any, name: str, text: str) -> Any:
    import importlib.util

    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    spec = importlib.util.spec_from_file_location(path.stem, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_export_answers_the_generated_code(client: Any, tmp_path: Any) -> None:
    answer = client.post(
        "/api/export", json={"model": SIMPLE, "options": {"set": {"l": 2}, "language": "numpy"}}
    )
    assert answer.status_code == 200
    files = answer.json()["files"]
    assert list(files) == ["simple_pendulum.py"]
    module = _module_from(tmp_path, "simple_pendulum.py", files["simple_pendulum.py"])
    p = dict(zip(module.PARAMETERS, module.DEFAULTS, strict=True))
    assert p["l"] == 2.0  # the setting is in the code's defaults
    theta = 0.7  # the pendulum's theta_ddot = -(g/l) sin(theta)
    rates = module.rhs(0.0, [theta, 0.3], list(p.values()))
    assert rates == pytest.approx([0.3, -p["g"] / p["l"] * np.sin(theta)], rel=1e-12)


@pytest.mark.parametrize(
    ("example", "language", "suffixes"),
    [("atwood_machine", "c", {".c", ".h"}), ("series_rlc", "julia", {".jl"})],
)
def test_export_of_a_constrained_system_and_of_a_circuit(
    client: Any, example: str, language: str, suffixes: set[str]
) -> None:
    model = examples.model_text(example)
    options = {"language": language}
    files = client.post("/api/export", json={"model": model, "options": options}).json()["files"]
    from lagrangian.numerics.export import export

    assert files == export(lg.loads(model), language)
    assert {name[name.rindex(".") :] for name in files} == suffixes


def test_export_refuses_an_unknown_language(client: Any) -> None:
    options = {"language": "fortran"}
    answer = client.post("/api/export", json={"model": SIMPLE, "options": options})
    assert answer.status_code == 422
    problem = answer.json()["problems"][0]
    assert problem["field"] == "options.language" and "numpy, c, matlab, julia" in problem["fix"]


@pytest.mark.parametrize(
    "content_type",
    ["text/plain;charset=json", "application/x-www-form-urlencoded", "text/json", ""],
)
def test_only_the_json_media_type_is_run(client: Any, content_type: str) -> None:
    """A cross-site form or text POST (a "simple" request, sent without a preflight) is
    refused before anything runs, whatever its parameters say."""
    body = json.dumps({"model": "coordinates: [x]\nkinetic: x_dot**2/2", "format": "yaml"})
    response = client.post("/api/derive", content=body, headers={"Content-Type": content_type})
    assert response.status_code == 415
    assert response.json()["problems"][0]["field"] == "body"


def test_the_json_media_type_with_a_charset_is_run(client: Any) -> None:
    body = json.dumps({"model": "coordinates: [x]\nkinetic: x_dot**2/2", "format": "yaml"})
    headers = {"Content-Type": "application/json; charset=utf-8"}
    assert client.post("/api/derive", content=body, headers=headers).status_code == 200
