"""A rolling wheel's ``tyre_radius`` (a torus) is read from the model file and written back."""

from __future__ import annotations

import sympy as sp

import lagrangian as lg
from lagrangian.io import loads
from lagrangian.io.dump import dumps


def test_a_tyre_radius_is_read_and_written_back() -> None:
    text = lg.examples.model_text("rolling_coin")
    assert "- {body: coin, radius: r}" in text and "position: [x, y, r*cos(theta)]" in text
    text = text.replace("position: [x, y, r*cos(theta)]", "position: [x, y, r*cos(theta) + r/10]")
    system = loads(
        text.replace("- {body: coin, radius: r}", "- {body: coin, radius: r, tyre_radius: r/10}")
    )
    assert system.rolling[0].tyre_radius == sp.Symbol("r") / 10
    assert "tyre_radius: r/10" in dumps(system)
    assert loads(dumps(system)) == system
    thin = lg.examples.model_text("rolling_coin")
    assert "tyre_radius" not in dumps(loads(thin))  # a thin disc: nothing more to say
