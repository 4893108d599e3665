"""``simulate --out FILE.json``: the run's columns and summary as one JSON document (the web
API's simulate answer without its scene), not CSV in a file named .json."""

from __future__ import annotations

import json
import math

import pytest

from lagrangian.cli.main import main


def test_a_bouncing_ball_as_json(tmp_path, capsys) -> None:
    out = tmp_path / "ball.json"
    main(["simulate", "examples/bouncing_ball", "--t-end", "2", "--out", str(out)])
    document = json.loads(out.read_text())
    columns, summary = document["columns"], document["summary"]
    assert list(columns) == ["t", "y", "y_dot", "lambda_1", "energy"]
    assert len(columns["t"]) == summary["samples"] and summary["status"] == "success"
    # dropped from h = 1: it lands at t = sqrt(2h/g) with speed sqrt(2gh), leaves with e times it
    first = summary["impacts"][0]
    g, h, e = 9.81, 1.0, 0.8
    assert first["t"] == pytest.approx(math.sqrt(2 * h / g), rel=1e-8)
    assert first["before"]["y_dot"] == pytest.approx(-math.sqrt(2 * g * h), rel=1e-8)
    assert first["after"]["y_dot"] == pytest.approx(-e * first["before"]["y_dot"], rel=1e-10)
    assert not (tmp_path / "ball.impacts.json").exists()  # the impacts are in the document


def test_a_failed_run_keeps_its_rows_in_json(tmp_path) -> None:
    out = tmp_path / "run.json"
    code = main(["simulate", "examples/double_pendulum", "--max-steps", "5", "--out", str(out)])
    assert code == 1
    summary = json.loads(out.read_text())["summary"]
    assert summary["status"] == "failed" and "--max-steps" in summary["message"]


def test_a_poincare_table_beside_a_json_run_is_a_csv(tmp_path) -> None:
    out = tmp_path / "ball.json"
    main(
        ["simulate", "examples/bouncing_ball", "--t-end", "2", "--out", str(out), "--poincare", "y"]
    )
    assert (tmp_path / "ball.poincare.csv").read_text().startswith("t,")
