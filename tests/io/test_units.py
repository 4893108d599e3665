"""The ``units:`` section: units of coordinates, parameters and t as short free text, read
from every format, checked by name (with a suggestion) and by characters, carried on the
System as a read-only mapping, and written back by dumps."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.constraints import eliminate
from lagrangian.errors import ModelError
from lagrangian.io import loads
from lagrangian.io.dump import dumps
from lagrangian.model.system import UNIT_LENGTH, unit_problem

PENDULUM = """\
name: Pendulum with units
coordinates: [theta]
parameters: {m: 1.0, l: 0.5, g: 9.81}
units: {m: kg, l: m, theta: rad, g: m/s^2}
kinetic: m*l**2*theta_dot**2/2
potential: -m*g*l*cos(theta)
"""

PENDULUM_TOML = """\
name = "Pendulum with units"
coordinates = ["theta"]
kinetic = "m*l**2*theta_dot**2/2"
potential = "-m*g*l*cos(theta)"
[parameters]
m = 1.0
l = 0.5
g = 9.81
[units]
m = "kg"
l = "m"
theta = "rad"
g = "m/s^2"
"""


def test_units_are_read_and_carried_on_the_system_read_only() -> None:
    system = loads(PENDULUM)
    assert dict(system.units) == {"m": "kg", "l": "m", "theta": "rad", "g": "m/s^2"}
    assert loads(PENDULUM_TOML, format="toml").units == system.units
    with pytest.raises(TypeError, match="does not support item assignment"):
        system.units["m"] = "g"  # type: ignore[index]


def test_a_model_without_units_has_none() -> None:
    assert dict(lg.examples.double_pendulum().units) == {}


def test_dumps_writes_the_units_back() -> None:
    system = loads(PENDULUM)
    text = dumps(system)
    assert "units: {m: kg, l: m, theta: rad, g: m/s^2}" in text
    assert loads(text) == system
    assert loads(dumps(system, format="json")).units == system.units


def test_an_unknown_name_is_reported_at_its_key_with_a_suggestion() -> None:
    text = PENDULUM.replace("theta: rad", "thetta: rad")
    with pytest.raises(ModelError, match=r"units\.thetta \(line 4, column 22\)") as caught:
        loads(text, source="pendulum.yaml")
    (problem,) = caught.value.problems
    assert "is not a coordinate, parameter or t" in problem.message
    assert problem.fix.startswith("did you mean 'theta'?")


@pytest.mark.parametrize(
    ("unit", "message"),
    [
        ('"<b>m</b>"', "has characters a unit does not use: <>"),
        ("1", "1 is not the text of a unit"),
        ('""', "'' is not the text of a unit"),
        ('"' + "m" * (UNIT_LENGTH + 1) + '"', "is longer than 32 characters"),
        ('"m\\n"', "has characters a unit does not use: \\n"),
        ('"$m$"', "has characters a unit does not use: $"),
    ],
)
def test_a_unit_is_short_text_of_plain_characters(unit: str, message: str) -> None:
    text = PENDULUM.replace("l: m,", f"l: {unit},")
    with pytest.raises(ModelError, match=r"units\.l") as caught:
        loads(text)
    (problem,) = caught.value.problems
    assert message in problem.message


def test_every_bad_unit_is_reported_at_once() -> None:
    text = PENDULUM.replace("{m: kg, l: m,", "{mass: kg, l: 2, t: '$s$',")
    with pytest.raises(ModelError, match=r"3 problems"):
        loads(text)


@pytest.mark.parametrize("unit", ["m/s^2", "kg·m²", "rad/s", "N m", "Ω", "µF", "°", "1/s", "%"])
def test_common_units_are_accepted(unit: str) -> None:
    assert unit_problem(unit) is None


def test_the_python_api_checks_units_too() -> None:
    theta, l = sp.symbols("theta l")
    system = lg.System(coordinates=[theta], parameters={l: 1.0}, units={theta: "rad", "t": "s"})
    assert dict(system.units) == {"theta": "rad", "t": "s"}
    with pytest.raises(ModelError, match=r"units\.lenght: 'lenght' is not a coordinate"):
        lg.System(coordinates=[theta], parameters={l: 1.0}, units={"lenght": "m"})
    with pytest.raises(ModelError, match=r"units: 'm' is not a mapping"):
        lg.System(coordinates=[theta], units="m")  # type: ignore[arg-type]


def test_a_system_without_a_coordinate_keeps_only_the_units_it_still_names() -> None:
    x, y, l = sp.symbols("x y l")
    system = lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        kinetic=(sp.Symbol("x_dot") ** 2 + sp.Symbol("y_dot") ** 2) / 2,
        constraints=[lg.Holonomic(y - l)],
        units={x: "m", y: "m", l: "m"},
    )
    reduced = eliminate(system, [x])
    assert dict(reduced.units) == {"x": "m", "l": "m"}
    assert dict(system.replace(units={"t": "ms"}).units) == {"t": "ms"}
