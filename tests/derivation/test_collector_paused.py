"""The derivation and the multiplier form run with Python's cycle collector paused (they make
expressions by the hundred thousand and no cycle; a collector pass over them finds nothing)
and leave it as they found it."""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterator
from typing import Any

import pytest

import lagrangian as lg
import lagrangian.constraints.multipliers as multipliers
import lagrangian.derivation.lagrange as lagrange
from lagrangian.examples import BENCHMARKS


@pytest.fixture
def inside(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[str]]:
    """The collections that start inside the derivation's or the multiplier form's work,
    named by it (the work marked by wrapping the functions that do it)."""
    where: list[str] = []
    started: list[str] = []

    def marked(name: str, function: Callable[..., Any]) -> Callable[..., Any]:
        def run(*args: Any) -> Any:
            where.append(name)
            try:
                return function(*args)
            finally:
                where.pop()

        return run

    def note(phase: str, info: dict) -> None:
        if phase == "start" and where:
            started.append(where[-1])

    monkeypatch.setattr(
        lagrange, "equations_of_motion", marked("derive", lagrange.equations_of_motion)
    )
    monkeypatch.setattr(
        multipliers, "_multiplier_form", marked("multipliers", multipliers._multiplier_form)
    )
    gc.callbacks.append(note)
    try:
        yield started
    finally:
        gc.callbacks.remove(note)


def test_the_bicycle_derives_without_a_collection_and_the_collector_is_on_after(
    inside: list[str],
) -> None:
    assert gc.isenabled()
    system = BENCHMARKS["whipple_bicycle"]()
    lg.derive(system)
    equations = lg.constrained_equations(system)
    assert inside == []
    assert gc.isenabled()
    assert equations.gamma.shape == (5, 1)


def test_a_collector_switched_off_by_the_caller_stays_off() -> None:
    gc.disable()
    try:
        lg.derive(BENCHMARKS["whipple_bicycle"]())
        assert not gc.isenabled()
    finally:
        gc.enable()
