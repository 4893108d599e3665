"""The example catalog: every entry builds a System that derives, and the listing helpers
(names, describe, get) behave as `lagrangian examples` needs."""

from __future__ import annotations

import inspect

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian import examples
from lagrangian.errors import ModelError

SIZE = 3  # for scalable examples, which take their size as the only argument


def _build(name: str) -> lg.System:
    function = examples.get(name)
    required = [p for p in inspect.signature(function).parameters.values() if p.default is p.empty]
    return function(*([SIZE] * len(required)))


@pytest.mark.parametrize("name", examples.names())
def test_every_example_builds_and_derives(name: str) -> None:
    system = _build(name)
    eom = lg.derive(system)
    n = len(system.coordinates)
    assert n > 0
    assert eom.equations.shape == (n, 1)
    assert eom.mass_matrix.shape == (n, n)
    # The residual form and the matrix form M q_ddot = forcing say the same thing.
    residual = eom.equations - (eom.mass_matrix * sp.Matrix(eom.accelerations) - eom.forcing)
    assert sp.simplify(residual) == sp.zeros(n, 1)


@pytest.mark.parametrize("name", examples.names())
def test_every_example_has_a_one_line_description(name: str) -> None:
    line = examples.describe(name)
    assert line.strip() and "\n" not in line
    assert _build(name).description


def test_names_are_sorted_and_cover_the_catalog() -> None:
    names = examples.names()
    assert names == sorted(names) == sorted(examples.CATALOG)
    assert len(set(names)) == len(names)


def test_examples_are_attributes_of_the_package() -> None:
    for name in examples.names():
        assert getattr(lg.examples, name) is examples.CATALOG[name]
    assert set(examples.names()) <= set(examples.__all__)


def test_unknown_example_suggests_close_names() -> None:
    with pytest.raises(ModelError, match="Did you mean double_pendulum"):
        examples.get("double_pendulm")
    with pytest.raises(AttributeError, match="no attribute 'no_such_example'"):
        _ = lg.examples.no_such_example
