"""File -> System -> file -> System -> JSON: every built-in example survives the round trip
through the model-file writer and reader with the same equations and the same JSON."""

from __future__ import annotations

import json

import pytest

import lagrangian as lg
from lagrangian.io import loads
from lagrangian.io.dump import dumps
from lagrangian.render.json import eom_document

FILE_EXAMPLES = [name for name in lg.examples.names() if name != "n_link_pendulum"]


@pytest.mark.parametrize("name", FILE_EXAMPLES)
@pytest.mark.parametrize("fmt", ["yaml", "json"])
def test_round_trip_keeps_the_equations(name: str, fmt: str) -> None:
    original = lg.examples.get(name)()
    again = loads(dumps(original, format=fmt), format=fmt, source=f"{name}.{fmt}")
    assert again.coordinates == original.coordinates
    assert dict(again.parameters) == dict(original.parameters)
    assert dict(again.initial) == dict(original.initial)
    assert dict(again.simulation) == dict(original.simulation)
    first = eom_document(lg.derive(original))
    second = eom_document(lg.derive(again))
    assert json.dumps(first, sort_keys=True) == json.dumps(second, sort_keys=True)


def test_the_model_file_shipped_is_what_the_writer_writes_back() -> None:
    system = lg.examples.double_pendulum()
    text = lg.examples.model_text("double_pendulum")
    body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
    assert dumps(system).strip() == body.strip()
