"""Constrained runs compile the multiplier form once per set of active constraints."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
import lagrangian.numerics.constrained as constrained


@pytest.fixture
def compiled(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, ...]]:
    """The names of the constraints of every multiplier form compiled during the test."""
    calls: list[tuple[str, ...]] = []
    original: Callable[..., Any] = constrained._compile_multiplier_form

    def counting(equations: Any) -> Any:
        calls.append(tuple(c.name for c in equations.constraints))
        return original(equations)

    monkeypatch.setattr(constrained, "_compile_multiplier_form", counting)
    return calls


def dome() -> lg.System:
    x, y, m, g = sp.symbols("x y m g")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Unilateral(x**2 + y**2 - 1, name="dome")],
    )


def test_a_unilateral_run_compiles_each_active_set_once(compiled: list[tuple[str, ...]]) -> None:
    top = {"x": np.sin(0.05), "y": np.cos(0.05), "x_dot": 0.0, "y_dot": 0.0}
    system = dome()
    run = lg.simulate(system, top, 2.0, samples=11)
    assert [e.name for e in run.events] == ["release dome"]
    assert sorted(compiled) == [(), ("dome",)]  # in contact, then free
    again = lg.simulate(system, top, 2.0, samples=11)
    assert len(compiled) == 2 and np.array_equal(again.q, run.q)


def test_a_bilateral_run_compiles_once(compiled: list[tuple[str, ...]]) -> None:
    x, y = sp.symbols("x y")
    system = dome().replace(constraints=[lg.Holonomic(x**2 + y**2 - 1, name="ring")])
    start = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
    for _ in range(2):
        lg.simulate(system, start, 0.5, samples=3, baumgarte=(10, 10))
    assert compiled == [("ring",)]
