"""The sections keyed by declared names (initial values, units, generalized forces) are read
by one Reader.known_entries: each refuses an unknown key at the key, in its own words, with
the closest declared name and its own fix, reads the known keys its own way, and reports every
problem of the file at once."""

from __future__ import annotations

import pytest
import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.io import loads
from lagrangian.io.document import Document
from lagrangian.io.reader import Reader

HEADER = "coordinates: [theta]\nparameters: {l: 1.0}\nkinetic: l**2*theta_dot**2/2\n"


def problems_of(text: str) -> list[Problem]:
    with pytest.raises(ModelError, match="is not a valid model file") as caught:
        loads(HEADER + text, source="model")
    return list(caught.value.problems)


@pytest.mark.parametrize(
    ("section", "message", "fix"),
    [
        (
            "initial: {thta_dot: 1.0}",
            "'thta_dot' is not a coordinate or a velocity",
            "did you mean 'theta_dot'? give values of coordinates and NAME_dot velocities",
        ),
        (
            "units: {ll: m}",
            "'ll' is not a coordinate, parameter or t",
            "did you mean 'l'? give units of coordinates, parameters and t",
        ),
        (
            "generalized_forces: {thetaa: -theta_dot}",
            "unknown coordinate 'thetaa'",
            "did you mean 'theta'? generalized forces are keyed by coordinate",
        ),
    ],
)
def test_each_section_keeps_its_own_message_and_fix(section, message, fix):
    (problem,) = problems_of(section + "\n")
    key = section.split(": {")[0] + "." + section.split("{")[1].split(":")[0]
    assert (problem.field, problem.line, problem.message, str(problem.fix)) == (
        key,
        4,
        message,
        fix,
    )
    assert problem.column == len(section.split("{")[0]) + 2  # at the key, not its value


def test_known_keys_are_read_by_each_sections_own_reading():
    system = loads(
        HEADER
        + "initial: {theta: 0.5, theta_dot: -1}\n"
        + "units: {theta: rad, l: m, t: s}\n"
        + "generalized_forces: {theta: -2*theta_dot}\n"
    )
    theta, theta_dot = sp.Symbol("theta"), sp.Symbol("theta_dot")
    assert system.initial == {theta: 0.5, theta_dot: -1.0}  # numbers
    assert dict(system.units) == {"theta": "rad", "l": "m", "t": "s"}  # text
    (force,) = system.generalized_forces.values()  # an expression in the declared names
    assert sp.simplify(force - (-2 * theta_dot)) == 0


def test_every_unknown_key_of_every_section_is_reported_at_once():
    problems = problems_of("initial: {x: 1, y: 2}\nunits: {z: m}\ngeneralized_forces: {w: 1}\n")
    assert [p.field for p in problems] == [
        "initial.x",
        "initial.y",
        "units.z",
        "generalized_forces.w",
    ]


def test_a_key_that_is_not_text_is_refused_as_unknown():
    reader = Reader(Document({}, "<string>"))
    found = list(reader.known_entries({"units": {1: "m"}}, "units", ["l"], "{key!r} no", "fix"))
    assert found == []
    assert [(p.message, str(p.fix)) for p in reader.problems] == [("1 no", "fix")]


def test_a_section_that_is_not_a_mapping_is_reported_once():
    reader = Reader(Document({}, "<string>"))
    assert list(reader.known_entries({"initial": [1]}, "initial", ["x"], "{key!r}", "")) == []
    (problem,) = reader.problems
    assert problem.message == "must be a mapping of keys to values, got a list"


def test_a_value_is_read_by_its_sections_reading_and_left_out_when_it_cannot_be():
    reader = Reader(Document({}, "<string>"), {"theta": sp.Symbol("theta")})
    data = {"initial": {"theta": "fast", "theta_dot": 2}, "forces": {"theta": "theta**", "x": 1}}
    known = ["theta", "theta_dot"]
    numbers = reader.known_values(data, "initial", known, "{key!r}?", "", reader.number)
    expressions = reader.known_values(data, "forces", known, "{key!r}?", "", reader.expression)
    assert numbers == {"theta_dot": 2.0} and expressions == {}
    assert [p.field for p in reader.problems] == ["initial.theta", "forces.theta", "forces.x"]
    assert reader.problems[0].message == "value 'fast' is not a number"  # Reader.number's
    assert reader.expression_problems == 1  # "theta**" was parsed as an expression
