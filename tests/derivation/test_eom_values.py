"""EquationsOfMotion is a value: read-only mappings, no attribute filled in after derive, and
every view a function of the fields (so dataclasses.replace gives consistent results)."""

from __future__ import annotations

import dataclasses
import pickle

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.steps import coordinate_steps

VIEWS = ("steps", "equations", "coriolis_matrix", "explicit", "mass_matrix_is_regular")


def fresh(name: str) -> lg.System:
    """A new System object (the examples are built once and shared)."""
    return lg.examples.get(name)().replace()


def test_the_mappings_of_the_equations_are_read_only() -> None:
    eom = lg.derive(fresh("double_pendulum"))
    m = next(iter(eom.parameters))
    with pytest.raises(TypeError, match="does not support item assignment"):
        eom.parameters[m] = 99  # type: ignore[index]
    with pytest.raises(TypeError, match="does not support item assignment"):
        eom.coordinate_orders[eom.coordinates[0]] = 1  # type: ignore[index]
    with pytest.raises(TypeError, match="does not support item assignment"):
        eom.explicit[eom.accelerations[0]] = 0  # type: ignore[index]
    with pytest.raises(dataclasses.FrozenInstanceError):
        eom.forcing = sp.ImmutableMatrix([0, 0])  # type: ignore[misc]


def test_no_attribute_is_filled_in_after_derive() -> None:
    eom = lg.derive(fresh("double_pendulum"))
    names = {f.name for f in dataclasses.fields(eom)}
    assert set(vars(eom)) == names
    for view in VIEWS:
        getattr(eom, view)
    assert set(vars(eom)) == names  # the views are cached elsewhere, per object
    assert not hasattr(eom, "_work")


def test_the_equations_know_their_system() -> None:
    system = fresh("double_pendulum")
    eom = lg.derive(system)
    assert eom.system is system
    assert eom.steps == coordinate_steps(system)


def test_replacing_the_system_gives_the_steps_of_the_new_one() -> None:
    eom = lg.derive(fresh("double_pendulum"))
    other = fresh("simple_pendulum")
    replaced = dataclasses.replace(eom, system=other)
    reference = lg.derive(other)
    assert replaced.steps == reference.steps
    assert replaced.equations == reference.equations
    assert replaced.coriolis_matrix == reference.coriolis_matrix
    assert eom.steps[0].coordinate.name == "theta" and len(eom.steps) == 2  # unchanged


def test_replacing_the_forcing_gives_its_solution() -> None:
    eom = lg.derive(fresh("simple_pendulum"))
    doubled = dataclasses.replace(eom, forcing=2 * eom.forcing)
    (acceleration,) = eom.accelerations
    assert sp.simplify(doubled.explicit[acceleration] - 2 * eom.explicit[acceleration]) == 0


def test_replacing_the_mass_matrix_gives_its_regularity() -> None:
    eom = lg.derive(fresh("double_pendulum"))
    assert eom.mass_matrix_is_regular
    singular = dataclasses.replace(eom, mass_matrix=sp.ImmutableMatrix([[1, 1], [1, 1]]))
    assert not singular.mass_matrix_is_regular


def test_the_equations_survive_pickling() -> None:
    eom = lg.derive(fresh("double_pendulum"))
    copy = pickle.loads(pickle.dumps(eom))
    assert copy.mass_matrix == eom.mass_matrix and copy.parameters == eom.parameters
    assert copy.steps == eom.steps and copy.system == eom.system
