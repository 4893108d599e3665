"""The multiplier form is computed once per equations and constraints, and its symbolic Schur
solve only when someone reads ``explicit`` (a simulation never does)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
import sympy as sp

import lagrangian as lg
import lagrangian.constraints.multipliers as multipliers
from lagrangian.constraints import constrained_equations


def ring() -> lg.System:
    x, y, m, g = sp.symbols("x y m g")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - 1)],
    )


@pytest.fixture
def solves(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """The multiplier forms whose Schur solve ran while the test runs."""
    calls: list[Any] = []
    original: Callable[..., Any] = multipliers._solve

    def counting(equations: Any) -> Any:
        calls.append(equations)
        return original(equations)

    monkeypatch.setattr(multipliers, "_solve", counting)
    return calls


def test_the_multiplier_form_is_computed_once_per_equations_and_constraints() -> None:
    system = ring()
    eom = lg.derive(system)
    form = constrained_equations(system)
    assert constrained_equations(system) is form
    assert constrained_equations(eom, system.constraints) is form
    assert form.system is system
    other = [lg.Holonomic(system.coordinates[0] - system.coordinates[1])]
    assert constrained_equations(eom, other).constraints == tuple(other)
    assert constrained_equations(eom, other).system.particles == system.particles


def test_simulating_never_solves_the_multipliers_symbolically(solves: list[Any]) -> None:
    system = ring()
    start = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
    run = lg.simulate(system, start, 0.5, samples=3, baumgarte=(10, 10))
    assert run.success and solves == []
    form = constrained_equations(system)
    lam = form.explicit[sp.Symbol("lambda_1")]  # read: solved now, once
    assert form.explicit[sp.Symbol("lambda_1")] == lam
    assert len(solves) == 1
    with pytest.raises(TypeError, match="does not support item assignment"):
        form.explicit[sp.Symbol("lambda_1")] = 0  # type: ignore[index]


def test_the_augmented_lagrangian_is_formed_when_first_read(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """L + lambda h needs L, which a derivation forms only when asked: the multiplier form
    leaves it until someone reads it, then keeps it."""
    calls: list[Any] = []
    original: Callable[..., Any] = multipliers._augmented_lagrangian
    monkeypatch.setattr(
        multipliers, "_augmented_lagrangian", lambda e: calls.append(e) or original(e)
    )
    system = ring()
    form = constrained_equations(system)
    assert calls == []
    augmented = form.augmented_lagrangian
    assert form.augmented_lagrangian is augmented and len(calls) == 1
    x, y = system.coordinates
    expected = lg.derive(system).lagrangian + sp.Symbol("lambda_1") * (x**2 + y**2 - 1)
    assert sp.expand(augmented - expected) == 0
