"""Impacts in the web API: the simulation's summary lists them, as the command line does."""

from __future__ import annotations

from typing import Any

from lagrangian import examples


def test_the_web_api_gives_the_impacts_in_its_summary(client: Any) -> None:
    model = examples.model_text("newtons_cradle")
    answer = client.post("/api/simulate", json={"model": model, "options": {}})
    assert answer.status_code == 200, answer.text
    summary = answer.json()["summary"]
    assert summary["impacts_summary"] == "2 impacts (first, second)"
    last = summary["impacts"][-1]
    assert last["constraints"] == ["second"] and last["after"]["x3_dot"] == 1.0
