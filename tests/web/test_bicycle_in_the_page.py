"""The Whipple bicycle, the playground's largest example, simulated end to end through the web
API as the page asks for it: its run conserves energy and keeps its rolling constraints (the
invariants of a conservative nonholonomic system), and its scene draws its bodies on the
ground."""

from __future__ import annotations

import json

import pytest

from lagrangian import examples
from lagrangian.web.runs import run

pytestmark = pytest.mark.slow


def test_the_bicycle_simulates_and_draws_in_the_page() -> None:
    status, body = run("simulate", examples.model_text("whipple_bicycle"), "yaml", {})
    document = json.loads(body)
    assert status == 200, document
    summary = document["summary"]
    assert summary["status"] == "success"
    assert summary["drift"]["energy_relative"] < 1e-6
    assert summary["drift"]["constraint_residual_max"] < 1e-6
    kinds = {e["kind"] for panel in document["scene"]["panels"] for e in panel["elements"]}
    assert {"body", "body_axes", "ground"} <= kinds
    assert len(document["rows"]) == len(document["scene"]["times"])
