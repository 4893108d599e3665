"""Write a System as a model file (YAML or JSON), the inverse of :func:`lagrangian.io.load`.

Expressions are written with SymPy's string printer, which the safe expression language
reads back (``l1*sin(theta1)``, ``m*x_dot**2/2``).

>>> import lagrangian as lg
>>> text = dumps(lg.examples.simple_pendulum())
>>> text.splitlines()[0]
'name: simple_pendulum'
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

import sympy as sp
import yaml

from lagrangian.model import (
    Capacitor,
    Inductor,
    MutualInductance,
    Resistor,
    RigidBody,
    System,
    VoltageSource,
)
from lagrangian.model.contact import GENERATED
from lagrangian.model.inertia import Shape

CIRCUIT_SECTIONS = (
    ("inductors", Inductor),
    ("mutual", MutualInductance),
    ("capacitors", Capacitor),
    ("resistors", Resistor),
    ("sources", VoltageSource),
)


def _expr(value: Any) -> str | int | float:
    """An expression as model-file text; plain integers stay numbers."""
    if isinstance(value, sp.Integer):
        return int(value)
    return sp.sstr(value, order="none")


def _point(value: Any) -> Any:
    return value if isinstance(value, str) else [_expr(v) for v in value]


def _with_name(entry: dict[str, Any], name: str) -> dict[str, Any]:
    """``entry`` with its ``name`` first, when it has one (unnamed entries stay short)."""
    return {"name": name, **entry} if name else entry


def _transition(item: Any) -> dict[str, Any]:
    """A transition as its model-file entry."""
    entry: dict[str, Any] = {"name": item.name, "guard": _expr(item.guard)}
    if item.direction != "both":
        entry["direction"] = item.direction
    if item.when is not None:
        entry["when"] = str(item.when)
    entry["reset"] = {key.name: _expr(value) for key, value in item.reset}
    return entry


def _constraint_entry(constraint: Any) -> dict[str, Any]:
    """``{kind: expression}`` with its name and, for an impact's, its restitution."""
    entry = _with_name({constraint.kind: _expr(constraint.expression)}, constraint.name)
    if getattr(constraint, "restitution", None) is not None:
        entry["restitution"] = _expr(constraint.restitution)
    return entry


def _scalar_or_vector(value: Any) -> Any:
    return [_expr(v) for v in value] if isinstance(value, tuple) else _expr(value)


def _matrix(value: Any) -> list[list[Any]]:
    return [[_expr(e) for e in row] for row in value.tolist()]


def _rigid_body(body: RigidBody) -> dict[str, Any]:
    """A planar body with its angle; a 3-D one with its inertia (matrix or shape) and its
    orientation in the form it was given."""
    entry: dict[str, Any] = {"name": body.name, "mass": _expr(body.mass)}
    if body.planar:
        entry["inertia"] = _expr(body.inertia)
        return {**entry, "position": _point(body.position), "angle": _expr(body.angle)}
    if isinstance(body.inertia, Shape):
        axis = {"axis": body.inertia.axis} if body.inertia.axis != "z" else {}
        sizes = {name: _expr(value) for name, value in body.inertia.dimensions}
        entry["inertia"] = {"shape": body.inertia.kind, **sizes, **axis}
    else:
        entry["inertia"] = _matrix(body.inertia)
    entry["position"] = _point(body.position)
    if body.relative:
        return {**entry, **_relative(body)}
    given = body.orientation
    if given is not None and given.form == "rotations" and given.parent is None:
        # built with rotation_sequence: written back as the same rotations
        return {**entry, "rotations": [[_axis(a), _expr(x)] for a, x in given.rotations]}
    return {**entry, "orientation": _orientation(given)}


def _relative(item: Any) -> dict[str, Any]:
    """``parent`` and ``rotations`` of a body or frame oriented relative to a parent."""
    parent = {} if item.parent is None else {"parent": item.parent}
    turns = [[_axis(a), _expr(x)] for a, x in item.rotations]
    return {**parent, "rotations": turns}


def _frame(frame: Any) -> dict[str, Any]:
    if frame.relative:
        return {"name": frame.name, **_relative(frame)}
    given = {} if frame.orientation is None else {"orientation": _orientation(frame.orientation)}
    return {"name": frame.name, **given}


def _rolling(disc: Any) -> dict[str, Any]:
    axis = {} if disc.axis is None else {"axis": _axis(disc.axis)}
    name = {"name": disc.name} if disc.name else {}
    tyre = {"tyre_radius": _expr(disc.tyre_radius)} if disc.tyre_radius != 0 else {}
    return {"body": disc.body, "radius": _expr(disc.radius), **axis, **name, **tyre}


def _axis(axis: Any) -> Any:
    """x, y, z for a body axis (named or a unit vector along it), else the vector."""
    if isinstance(axis, str):
        return axis.lower()
    units: dict[tuple[str, ...], str] = {
        ("1", "0", "0"): "x",
        ("0", "1", "0"): "y",
        ("0", "0", "1"): "z",
    }
    return units.get(tuple(str(e) for e in axis), _point(axis))


def _orientation(orientation: Any) -> Any:
    if orientation.form == "euler":
        extrinsic = {} if orientation.intrinsic else {"intrinsic": False}
        angles = [_expr(a) for a in orientation.angles]
        return {"euler": orientation.sequence, "angles": angles, **extrinsic}
    if orientation.form == "axis_angle":
        return {"axis": _point(orientation.axis), "angle": _expr(orientation.angles[0])}
    if orientation.form == "quaternion":
        return {"quaternion": _point(orientation.quaternion)}
    return _matrix(orientation.matrix)


def _mechanics(system: System) -> dict[str, Any]:
    sections: dict[str, Any] = {}
    if system.gravity is not None:
        sections["gravity"] = [_expr(g) for g in system.gravity]
    sections["frames"] = [_frame(f) for f in system.frames]
    sections["particles"] = [
        {"name": p.name, "mass": _expr(p.mass), "position": _point(p.position)}
        for p in system.particles
    ]
    sections["rigid_bodies"] = [_rigid_body(b) for b in system.rigid_bodies]
    sections["springs"] = [
        _with_name(
            {
                "between": [_point(p) for p in s.between],
                "stiffness": _expr(s.stiffness),
                **({"rest_length": _expr(s.rest_length)} if s.rest_length != 0 else {}),
            },
            s.name,
        )
        for s in system.springs
    ]
    sections["dampers"] = [
        _with_name(
            {"between": [_point(p) for p in d.between], "coefficient": _expr(d.coefficient)}, d.name
        )
        for d in system.dampers
    ]
    sections["forces"] = [
        _with_name({"at": _point(f.at), "force": _point(f.force)}, f.name) for f in system.forces
    ]
    sections["torques"] = [
        _with_name({"body": tq.body, "torque": _scalar_or_vector(tq.torque)}, tq.name)
        for tq in system.torques
    ]
    sections["rolling"] = [_rolling(disc) for disc in system.rolling]
    return {key: value for key, value in sections.items() if value}


def _circuit_entry(element: Any) -> dict[str, Any]:
    entry: dict[str, Any]
    if isinstance(element, Inductor):
        entry = {"inductance": _expr(element.inductance), "current": _expr(element.current)}
    elif isinstance(element, MutualInductance):
        entry = {
            "inductance": _expr(element.inductance),
            "currents": [_expr(c) for c in element.currents],
        }
    elif isinstance(element, Capacitor):
        entry = {"capacitance": _expr(element.capacitance), "charge": _expr(element.charge)}
    elif isinstance(element, Resistor):
        entry = {"resistance": _expr(element.resistance), "current": _expr(element.current)}
    else:
        entry = {"voltage": _expr(element.voltage), "coordinate": str(element.coordinate)}
    return _with_name(entry, element.name)


def _circuit(elements: Iterable[Any]) -> dict[str, list[dict[str, Any]]]:
    grouped: dict[str, list[dict[str, Any]]] = {}
    for section, kind in CIRCUIT_SECTIONS:
        entries = [_circuit_entry(e) for e in elements if isinstance(e, kind)]
        if entries:
            grouped[section] = entries
    return grouped


def model_document(system: System) -> dict[str, Any]:
    """The model-file mapping of ``system`` (its sections, empty ones left out)."""
    document: dict[str, Any] = {"name": system.name or "system"}
    if system.description:
        document["description"] = system.description
    document["coordinates"] = [q.name for q in system.coordinates]
    document["parameters"] = {p.name: value for p, value in system.parameters.items()}
    if system.units:
        document["units"] = dict(system.units)
    for field in ("kinetic", "potential", "lagrangian", "velocity_potential", "dissipation"):
        value = getattr(system, field)
        if value != 0:
            document[field] = _expr(value)
    if system.generalized_forces:
        document["generalized_forces"] = {
            q.name: _expr(v) for q, v in system.generalized_forces.items()
        }
    document.update(_mechanics(system))
    circuit = _circuit(system.circuit)
    if circuit:
        document["circuit"] = circuit
    given = [c for c in system.constraints if not isinstance(c, GENERATED)]  # not rolling's
    if given:
        document["constraints"] = [_constraint_entry(c) for c in given]
    if system.transitions:
        document["transitions"] = [_transition(item) for item in system.transitions]
    if system.initial:
        document["initial"] = {s.name: float(v) for s, v in system.initial.items()}
    if system.simulation:
        document["simulate"] = dict(system.simulation)
    return document


def dumps(system: System, format: str = "yaml", header: str = "") -> str:
    """``system`` as model-file text in ``format`` (yaml or json); ``header`` becomes leading
    comment lines (YAML only)."""
    document = model_document(system)
    if format == "json":
        return json.dumps(document, indent=2, ensure_ascii=False) + "\n"
    body = yaml.safe_dump(
        document, sort_keys=False, default_flow_style=None, width=100, allow_unicode=True
    )
    comments = "".join(f"# {line}".rstrip() + "\n" for line in header.splitlines())
    return comments + body
