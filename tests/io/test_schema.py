"""The JSON Schema of the model file is valid, describes what the loader reads, and refuses
what the loader refuses."""

from __future__ import annotations

import dataclasses
import json

import jsonschema  # the test extra must list it
import pytest

from lagrangian.io import SCHEMA_PATH, loads, schema
from lagrangian.io.sections import ELEMENT_TYPES

#: Every section and key of the format, once.
FULL_MODEL = {
    "$schema": "urn:lagrangian:model:v1",
    "name": "Everything",
    "description": "Every section of the format at least once.",
    "coordinates": ["x", "theta", "q1", "q2"],
    "parameters": {"m": 1.0, "l": 1, "g": 9.81, "k": 2, "b": 0.1, "L1": 1, "C": 1, "u0": None},
    "kinetic": "m*x_dot**2/2",
    "potential": "k*x**2/2",
    "lagrangian": 0,
    "velocity_potential": "b*x*theta_dot",
    "dissipation": "b*x_dot**2/2",
    "generalized_forces": {"x": "u0*cos(t)"},
    "gravity": [0, "-g"],
    "particles": [{"name": "cart", "mass": "m", "position": ["x", 0]}],
    "rigid_bodies": [
        {
            "name": "rod",
            "mass": "m",
            "inertia": "m*l**2/12",
            "position": ["x + l/2*sin(theta)", "-l/2*cos(theta)"],
            "angle": "theta",
        }
    ],
    "springs": [{"name": "s", "between": ["cart", [0, 0]], "stiffness": "k", "rest_length": 0.5}],
    "dampers": [{"name": "d", "between": ["rod", "origin"], "coefficient": "b"}],
    "forces": [{"name": "f", "at": "rod", "force": ["u0", 0]}],
    "torques": [{"name": "tau", "body": "rod", "torque": "u0*sin(t)"}],
    "circuit": {
        "inductors": [{"name": "L", "inductance": "L1", "current": "q1_dot"}],
        "mutual": [{"name": "M", "inductance": "L1/2", "currents": ["q1_dot", "q2_dot"]}],
        "capacitors": [{"name": "C", "capacitance": "C", "charge": "q1 - q2"}],
        "resistors": [{"name": "R", "resistance": 1, "current": "q2_dot"}],
        "sources": [{"name": "u", "voltage": "u0", "coordinate": "q1"}],
    },
    "initial": {"x": 0.1, "theta_dot": 0},
    "units": {"x": "m", "theta": "rad", "g": "m/s^2", "t": "s"},
    "simulate": {"t_end": 10, "method": "RK45", "rtol": 1e-8, "atol": 1e-10, "samples": 100},
    "constraints": [
        {"name": "c", "holonomic": "q1 - q2"},
        {"velocity": "x_dot - l*theta_dot"},
        {"unilateral": "x + 1"},
    ],
}


def validator() -> jsonschema.Draft202012Validator:
    return jsonschema.Draft202012Validator(schema())


def test_the_schema_is_a_valid_draft_2020_12_schema() -> None:
    jsonschema.Draft202012Validator.check_schema(schema())
    assert schema()["$schema"] == "https://json-schema.org/draft/2020-12/schema"


def test_the_schema_ships_with_the_package_and_is_returned_as_a_copy() -> None:
    assert json.loads(SCHEMA_PATH.read_text(encoding="utf-8")) == schema()
    changed = schema()
    changed["required"].append("name")
    assert schema()["required"] == ["coordinates"]


def test_a_full_model_is_valid_and_loads() -> None:
    validator().validate(FULL_MODEL)
    system = loads(json.dumps(FULL_MODEL), format="json")
    assert (len(system.circuit), system.simulation["samples"]) == (5, 100)


def test_the_examples_in_the_schema_are_valid_and_load() -> None:
    for example in schema()["examples"]:
        validator().validate(example)
        assert loads(json.dumps(example), format="json").name == example["name"]


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"partcles": []}, r"'partcles' was unexpected"),
        ({"springs": [{"between": ["cart", "origin"], "stifness": 1}]}, r"'stifness'"),
        ({"parameters": {"m": "heavy"}}, r"'heavy' is not of type 'number', 'null'"),
        ({"particles": [{"name": "a", "position": ["x"]}]}, r"'mass' is a required property"),
        ({"coordinates": []}, r"\[\] should be non-empty"),
        ({"constraints": [{"holonomic": "x", "velocity": "x_dot"}]}, r"is valid under each of"),
        ({"constraints": [{"name": "c"}]}, r"is not valid under any of the given schemas"),
        ({"constraints": [{"holonomic": "x", "rheonomic": True}]}, r"'rheonomic' was unexpected"),
        ({"kinetic": True}, r"True is not of type 'string', 'number'"),
        ({"units": {"x": "<b>m</b>"}}, r"does not match"),
        ({"units": {"x": "m" * 33}}, r"is too long"),
        ({"units": {"x": 1}}, r"1 is not of type 'string'"),
    ],
)
def test_the_schema_refuses_what_the_loader_refuses(change: dict, match: str) -> None:
    model = {**FULL_MODEL, **change}
    with pytest.raises(jsonschema.ValidationError, match=match):
        validator().validate(model)
    with pytest.raises(ValueError, match=r"not a valid model file"):
        loads(json.dumps(model), format="json")


#: Keys of a model file that the loader turns into another field (inertia_about: the
#: inertia moved to the centre of mass; a force's offset: the force at the centre and its
#: moment; a torque's by and frame: the reaction, generalized forces of a frame).
READ_INTO_OTHERS = {
    "rigid_body": {"inertia_about"},
    "force": {"offset"},
    "torque": {"by", "frame"},
}


def test_every_entry_of_the_schema_has_the_keys_of_its_model_type() -> None:
    definitions = schema()["$defs"]
    for definition, kind in ELEMENT_TYPES.items():
        fields = {f.name for f in dataclasses.fields(kind)}
        keys = set(definitions[definition]["properties"]) - READ_INTO_OTHERS.get(definition, set())
        assert keys == fields, definition
