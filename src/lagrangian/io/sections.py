"""Builders for the sections of a model file that become System fields: energies,
generalized forces, gravity, mechanical elements, circuit elements and constraints.

Each builder reads one section through a :class:`Reader` (which records every problem) and
returns model values; an element whose fields could not all be read is left out (its problems
are already recorded, so no System is built from the file).

>>> from lagrangian.io.document import Document
>>> from lagrangian.io.reader import Reader
>>> from lagrangian.io.declarations import expression_names
>>> reader = Reader(Document({}, "<string>"), expression_names(["x"], ["k"]))
>>> read_energies(reader, {"potential": "k*x**2/2"})
{'potential': k*x**2/2}
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.io.bodies import (
    about_the_centre,
    read_axis,
    read_inertia,
    read_orientation,
    read_rotations,
)
from lagrangian.io.document import child
from lagrangian.io.model_schema import entry_keys
from lagrangian.io.reader import Reader, describe, suggestion
from lagrangian.model import (
    Capacitor,
    Damper,
    Force,
    Frame,
    Holonomic,
    Inductor,
    MutualInductance,
    Particle,
    Resistor,
    RigidBody,
    RollingDisc,
    Spring,
    Torque,
    Unilateral,
    VelocityConstraint,
    VoltageSource,
)
from lagrangian.model.elements import ORIGIN
from lagrangian.model.transitions import Transition

ENERGIES = ("kinetic", "potential", "lagrangian", "velocity_potential", "dissipation")

#: Section -> schema definition of its entries.
MECHANICAL_SECTIONS = {
    "frames": "frame",
    "particles": "particle",
    "rigid_bodies": "rigid_body",
    "springs": "spring",
    "dampers": "damper",
    "forces": "force",
    "torques": "torque",
    "rolling": "rolling",
}
#: circuit key -> schema definition; System.circuit lists them in this order.
CIRCUIT_SECTIONS = {
    "inductors": "inductor",
    "mutual": "mutual_inductance",
    "capacitors": "capacitor",
    "resistors": "resistor",
    "sources": "voltage_source",
}
#: Schema definition -> the model type it becomes.
ELEMENT_TYPES: dict[str, type] = {
    "frame": Frame,
    "rolling": RollingDisc,
    "particle": Particle,
    "rigid_body": RigidBody,
    "spring": Spring,
    "damper": Damper,
    "force": Force,
    "torque": Torque,
    "inductor": Inductor,
    "mutual_inductance": MutualInductance,
    "capacitor": Capacitor,
    "resistor": Resistor,
    "voltage_source": VoltageSource,
}

#: Element key -> the Reader method that reads it (special keys are read in read_fields).
_READ_AS = {
    "mass": "expression",
    "angle": "expression",
    "stiffness": "expression",
    "rest_length": "expression",
    "coefficient": "expression",
    "torque": "expression",
    "inductance": "expression",
    "capacitance": "expression",
    "resistance": "expression",
    "current": "expression",
    "charge": "expression",
    "voltage": "expression",
    "radius": "expression",
    "tyre_radius": "expression",
    "position": "vector",
    "force": "vector",
    "at": "point",
    "body": "name",
    "parent": "name",
    "offset": "vector",  # a force's body point
    "by": "name",  # the body or frame that exerts a torque
    "frame": "name",  # the frame a torque acts on
}


def read_energies(reader: Reader, data: dict[str, Any]) -> dict[str, sp.Expr]:
    """T, V, L, U and F, where given."""
    found = {key: reader.expression(data[key], key) for key in ENERGIES if key in data}
    return {key: value for key, value in found.items() if value is not None}


def read_generalized_forces(
    reader: Reader, data: dict[str, Any], coordinates: list[str]
) -> dict[sp.Symbol, sp.Expr]:
    """Coordinate -> Q(q, q_dot, t)."""
    unknown, fix = "unknown coordinate {key!r}", "generalized forces are keyed by coordinate"
    section = "generalized_forces"
    forces = reader.known_values(data, section, coordinates, unknown, fix, reader.expression)
    return {sp.Symbol(key): expression for key, expression in forces.items()}


def read_fields(
    reader: Reader, entry: dict[str, Any], path: str, coordinates: list[str]
) -> dict[str, Any] | None:
    """Every key of an element entry read by its kind; ``None`` if any could not be read."""
    values: dict[str, Any] = {}
    for key, value in entry.items():
        where = child(path, key)
        if key == "between":
            values[key] = _between(reader, value, where)
        elif key == "currents":
            values[key] = _pair(reader, value, where)
        elif key == "coordinate":
            values[key] = _coordinate(reader, value, where, coordinates)
        elif key == "name":
            values[key] = reader.text(value, where)
        elif key == "inertia":
            values[key] = read_inertia(reader, value, where)
        elif key == "inertia_about":
            values[key] = reader.vector(value, where)
        elif key == "orientation":
            values[key] = read_orientation(reader, value, where)
        elif key == "rotations":
            values[key] = read_rotations(reader, value, where)
        elif key == "axis":  # a rolling disc's axle
            values[key] = read_axis(reader, value, where)
        elif key == "torque" and isinstance(value, list):  # on a 3-D body: [tx, ty, tz]
            values[key] = reader.vector(value, where)
        elif key in _READ_AS:
            values[key] = getattr(reader, _READ_AS[key])(value, where)
    # unknown keys are skipped here: the entry check reported them
    return None if None in values.values() else values


def _between(reader: Reader, value: Any, path: str) -> tuple[Any, ...] | None:
    items = reader.items(value, path)
    if isinstance(value, list) and len(items) != 2:
        reader.problem(path, f"needs two points, got {len(items)}", "give [point_a, point_b]")
        return None
    points = [reader.point(item, child(path, i)) for i, item in enumerate(items)]
    return tuple(points) if points and None not in points else None


def _pair(reader: Reader, value: Any, path: str) -> tuple[sp.Expr, ...] | None:
    if isinstance(value, list) and len(value) != 2:
        reader.problem(path, f"needs two currents, got {len(value)}", "give [i_a, i_b]")
        return None
    return reader.vector(value, path)


def _coordinate(reader: Reader, value: Any, path: str, coordinates: list[str]) -> Any:
    if isinstance(value, str) and value in coordinates:
        return sp.Symbol(value)
    fix = suggestion(str(value), coordinates, "name one of the coordinates (a charge)")
    reader.problem(path, f"{describe(value)} is not a coordinate", fix)
    return None


def read_elements(
    reader: Reader, value: Any, section: str, definition: str, coordinates: list[str]
) -> list[tuple[str, Any]]:
    """The elements of the list ``value`` of a section (``particles``, ``circuit.inductors``)
    with the path of each entry in the file."""
    kind = ELEMENT_TYPES[definition]
    required = set(entry_keys(definition).required)
    elements = []
    allowed = set(entry_keys(definition).allowed)
    for path, entry in reader.entries(value, section, definition):
        # a key the entry may not have is reported by the entry check, never passed on
        known = {key: item for key, item in entry.items() if key in allowed}
        values = read_fields(reader, known, path, coordinates)
        if values is not None and "inertia_about" in values:
            values = about_the_centre(reader, values, child(path, "inertia_about"))
        if values is not None and required <= set(values):
            elements.append((path, kind(**values)))
    return elements


def check_body_names(reader: Reader, data: dict[str, Any]) -> None:
    """Each particle and rigid body has its own name; ``origin`` is taken."""
    taken: dict[str, str] = {ORIGIN: "the fixed origin"}
    for section in ("particles", "rigid_bodies"):
        entries = data.get(section)
        for i, entry in enumerate(entries if isinstance(entries, list) else []):
            name = entry.get("name") if isinstance(entry, dict) else None
            if not isinstance(name, str):
                continue
            if name in taken:
                reader.problem(
                    child(child(section, i), "name"),
                    f"name {name!r} is taken (by {taken[name]})",
                    "give each particle and rigid body its own name",
                )
            else:
                taken[name] = child(section, i)


def read_circuit(
    reader: Reader, data: dict[str, Any], coordinates: list[str]
) -> list[tuple[str, Any]]:
    """Circuit elements in System order: inductors, mutual, capacitors, resistors, sources."""
    if "circuit" not in data:
        return []
    circuit = reader.entry(data["circuit"], "circuit", "circuit") or {}
    elements = []
    for key, definition in CIRCUIT_SECTIONS.items():
        if key in circuit:
            path = child("circuit", key)
            elements += read_elements(reader, circuit[key], path, definition, coordinates)
    return elements


#: Constraint key -> the model type it becomes.
CONSTRAINT_TYPES: dict[str, type] = {
    "holonomic": Holonomic,
    "velocity": VelocityConstraint,
    "unilateral": Unilateral,
}


def read_constraints(reader: Reader, data: dict[str, Any]) -> list[tuple[str, Any]]:
    """Constraints, each ``{holonomic: h}``, ``{velocity: a.q_dot + b}`` or
    ``{unilateral: g}`` with an optional ``name``, and the path of its expression in the file."""
    constraints = []
    for path, entry in reader.entries(data.get("constraints", []), "constraints", "constraint"):
        unknown = set(entry) - set(entry_keys("constraint").allowed)
        if unknown and not set(entry) & set(CONSTRAINT_TYPES):
            continue  # a misspelt kind: reported as an unknown key with a suggestion
        example = 'write one per entry, e.g. {holonomic: "x**2 + y**2 - l**2"}'
        kind = reader.one_of(entry, CONSTRAINT_TYPES, path, "a constraint", example)
        if kind is None:
            continue
        expression = reader.expression(entry[kind], child(path, kind))
        name = reader.text(entry["name"], child(path, "name")) if "name" in entry else ""
        extra = _restitution(reader, entry, path, kind)
        if expression is not None and name is not None and extra is not None:
            made = CONSTRAINT_TYPES[kind](expression, name, **extra)
            constraints.append((child(path, kind), made))
    return constraints


def _restitution(
    reader: Reader, entry: dict[str, Any], path: str, kind: str
) -> dict[str, Any] | None:
    """The ``restitution`` of a unilateral constraint (its impacts' coefficient e), as keyword
    arguments; None after a problem."""
    if "restitution" not in entry:
        return {}
    where = child(path, "restitution")
    if kind != "unilateral":
        reader.problem(
            where,
            f"a {kind} constraint has no impacts, so no coefficient of restitution",
            "give restitution on a unilateral constraint only",
        )
        return None
    value = reader.expression(entry["restitution"], where)
    return None if value is None else {"restitution": value}


def read_transitions(reader: Reader, data: dict[str, Any]) -> list[Transition]:
    """Transitions, each ``{name, guard, reset: {NAME: expression}, direction, when}``."""
    found = []
    for path, entry in reader.entries(data.get("transitions", []), "transitions", "transition"):
        name = reader.text(entry.get("name", ""), child(path, "name"))
        guard = reader.expression(entry.get("guard", ""), child(path, "guard"))
        values = reader.mapping(entry.get("reset", {}), child(path, "reset")) or {}
        reset = {key: reader.expression(value, child(child(path, "reset"), key))
                 for key, value in values.items()}  # fmt: skip
        direction = reader.text(entry.get("direction", "both"), child(path, "direction"))
        when = reader.condition(entry["when"], child(path, "when")) if "when" in entry else None
        complete = None not in (name, guard, direction, *reset.values())
        if complete and ("when" not in entry or when is not None):
            found.append(Transition(str(name), guard, reset, str(direction), when))
    return found
