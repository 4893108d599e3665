"""Computed once: derive remembers the last Systems it derived (by identity), so simulating a
System twice and analyzing it derives it once; the CLI's derive derives once; forgetting lets
the equations go."""

from __future__ import annotations

import gc
import weakref
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import sympy as sp

import lagrangian as lg
import lagrangian.derivation.lagrange as lagrange
import lagrangian.derivation.terms as terms
from lagrangian.cli.commands import derive_command
from lagrangian.derivation.lagrange import RECENT_SYSTEMS, forget_derivations


@pytest.fixture
def assembled(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """The Systems assembled (the first step of every derivation) while the test runs."""
    calls: list[Any] = []
    original: Callable[..., Any] = terms.assemble

    def counting(system: Any) -> Any:
        calls.append(system)
        return original(system)

    monkeypatch.setattr(terms, "assemble", counting)
    return calls


def fresh_pendulum() -> lg.System:
    return lg.examples.simple_pendulum().replace()


def test_simulating_twice_and_analyzing_derives_once(assembled: list[Any]) -> None:
    system = fresh_pendulum()
    first = lg.simulate(system, {"theta": 0.1}, 0.5, samples=3)
    second = lg.simulate(system, {"theta": 0.2}, 0.5, samples=3)
    report = lg.analyze(system)
    assert len(assembled) == 1
    assert first.q[0, 0] == 0.1 and second.q[0, 0] == 0.2
    assert report.dof == 1


def test_derive_gives_the_same_equations_for_the_same_system(assembled: list[Any]) -> None:
    system = fresh_pendulum()
    assert lg.derive(system) is lg.derive(system)
    assert lg.derive(system.replace()) is not lg.derive(system)  # a new System, derived anew
    assert len(assembled) == 2


def test_the_steps_reuse_the_terms_of_the_derivation(assembled: list[Any]) -> None:
    eom = lg.derive(fresh_pendulum())
    views = eom.steps, eom.coriolis_matrix, eom.equations
    assert all(view is not None for view in views)
    assert len(assembled) == 1


def test_only_the_recent_systems_are_remembered(monkeypatch: pytest.MonkeyPatch) -> None:
    made: list[Any] = []
    original = lagrange.equations_of_motion
    monkeypatch.setattr(lagrange, "equations_of_motion", lambda s: made.append(s) or original(s))
    first = fresh_pendulum()
    remembered = lg.derive(first)
    for _ in range(RECENT_SYSTEMS):
        lg.derive(fresh_pendulum())
    again = lg.derive(first)  # pushed out by the newer ones: made again
    assert len(made) == RECENT_SYSTEMS + 2
    assert again is not remembered and again.mass_matrix == remembered.mass_matrix


def test_forgetting_the_derivations_lets_the_equations_go() -> None:
    eom = lg.derive(fresh_pendulum())
    alive = weakref.ref(eom)
    del eom
    forget_derivations()
    gc.collect()
    assert alive() is None


def test_the_derive_command_derives_a_constrained_model_once(
    assembled: list[Any], tmp_path: Path
) -> None:
    path = tmp_path / "cartesian_pendulum.yaml"
    path.write_text(
        "coordinates: [x, y]\n"
        "parameters: {m: 1.0, g: 9.81, l: 1.0}\n"
        "gravity: [0, -g]\n"
        "particles:\n  - {name: bob, mass: m, position: [x, y]}\n"
        'constraints:\n  - {holonomic: "x**2 + y**2 - l**2"}\n'
    )
    text = derive_command(str(path), fmt="text", steps=True, matrix=True, settings=[])
    assert len(assembled) == 1
    assert "lambda_1" in text and str(sp.Symbol("x_ddot")) in text
