"""Turn what a user passed to :class:`System` into canonical values, then validate them.

Canonical means: coordinates and parameters are SymPy Symbols (one object per name),
time functions ``x(t)`` and their derivatives are the plain symbols ``x``, ``x_dot``,
``x_ddot``, numbers are exact SymPy numbers, and every expression uses the canonical symbol
objects (a user's ``Symbol('m', positive=True)`` and ``Symbol('m')`` are one parameter ``m``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import fields, is_dataclass, replace
from typing import TYPE_CHECKING, Any, get_args

import sympy as sp

from lagrangian.errors import ModelError, Problem, raise_if_problems
from lagrangian.model.circuit import CircuitElement
from lagrangian.model.constraints import Constraint
from lagrangian.model.contact import RollingDisc, add_rolling_constraints, move_contact_forces
from lagrangian.model.elements import (
    Damper,
    Force,
    Particle,
    RigidBody,
    Spring,
    Torque,
    as_expression,
)
from lagrangian.model.frames import Frame, resolve_orientations
from lagrangian.model.inertia import Shape
from lagrangian.model.rotation import Orientation
from lagrangian.model.transitions import Transition
from lagrangian.model.validation import validate
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.expressions import is_plain
from lagrangian.symbolic.frozen import FrozenMapping
from lagrangian.symbolic.symbols import as_coordinate, from_time_functions, t

if TYPE_CHECKING:
    from lagrangian.model.system import System

EXPRESSION_FIELDS = ("kinetic", "potential", "lagrangian", "velocity_potential", "dissipation")
MAPPING_FIELDS = ("parameters", "generalized_forces", "initial", "simulation")
ELEMENT_FIELDS = (
    "particles",
    "rigid_bodies",
    "springs",
    "dampers",
    "forces",
    "torques",
    "circuit",
    "constraints",
    "frames",
    "rolling",
    "transitions",
)


class _Canonicalizer:
    """Maps every symbol to the one canonical object of its name."""

    def __init__(self, symbols: list[sp.Symbol]) -> None:
        self.by_name = {s.name: s for s in symbols}
        self.by_name["t"] = t
        self.canonical: set[sp.Basic] = set()  # parts with nothing to replace

    def __call__(self, value: Any) -> Any:
        value = as_expression(value)
        if isinstance(value, tuple):
            return tuple(self(v) for v in value)
        if isinstance(value, (Orientation, Shape)):  # rebuilt from its canonical expressions
            return value.map(self)
        if not isinstance(value, sp.Basic) or self._is_canonical(value):
            return value
        value = from_time_functions(value)
        swap = {
            s: self.by_name[s.name]
            for s in value.free_symbols
            if isinstance(s, sp.Symbol) and s.name in self.by_name and self.by_name[s.name] != s
        }
        return value.xreplace(swap) if swap else value

    def _is_canonical(self, value: sp.Basic) -> bool:
        """Whether ``value`` has nothing to replace: no time function or derivative, and
        every symbol the canonical one of its name (a walk that enters each shared part once,
        and not the parts found so before: the positions of a chain share most of them)."""
        seen: set[sp.Basic] = set()
        stack = [value]
        while stack:
            part = stack.pop()
            if part in self.canonical or part in seen:
                continue
            if isinstance(part, sp.Symbol):
                if self.by_name.get(part.name, part) != part:
                    return False
            elif not is_plain(part):
                return False
            seen.add(part)
            stack.extend(part.args)
        self.canonical.update(seen)
        return True


def _coordinates(raw: Any, problems: list[Problem]) -> tuple[sp.Symbol, ...]:
    if isinstance(raw, (str, sp.Basic)):
        raw = raw.replace(",", " ").split() if isinstance(raw, str) else [raw]
    if not isinstance(raw, Iterable):
        problems.append(
            Problem("coordinates", f"{raw!r} is not a list of coordinates", "give ['x', 'theta']")
        )
        return ()
    result = []
    for i, item in enumerate(raw):
        symbol = as_coordinate(item)
        if symbol is None:
            problems.append(
                Problem(
                    f"coordinates[{i}]",
                    f"{item!r} is not a coordinate",
                    "give a name, a Symbol or a time function x(t)",
                )
            )
        else:
            result.append(symbol)
    return tuple(result)


def _parameter_value(name: str, value: Any, problems: list[Problem]) -> float | None:
    if value is None:
        return None
    if type(value) is float and math.isfinite(value):
        return value + 0.0  # what float(sp.Float(value)) gives (-0.0 too: SymPy has one zero)
    try:
        number = to_sympy(value) if isinstance(value, (int, float, sp.Basic)) else None
    except (TypeError, sp.SympifyError):
        number = None
    if (
        number is None
        or not number.is_number
        or not number.is_real
        or not math.isfinite(float(number))
    ):
        problems.append(
            Problem(
                f"parameters.{name}",
                f"value {value!r} is not a real number",
                "give a number such as 9.81, or None for no default",
            )
        )
        return None
    return float(number)


def _parameters(raw: Any, problems: list[Problem]) -> dict[sp.Symbol, float | None]:
    if isinstance(raw, str):
        raw = raw.replace(",", " ").split()
    if not isinstance(raw, Iterable):
        problems.append(
            Problem(
                "parameters",
                f"{raw!r} is not a mapping of parameters",
                "give {'m': 1.0, 'g': 9.81} (or a list of names)",
            )
        )
        return {}
    items = raw.items() if isinstance(raw, Mapping) else ((name, None) for name in raw)
    result: dict[sp.Symbol, float | None] = {}
    names: set[str] = set()  # a set, not a scan of result: linear in the number declared
    for key, value in items:
        symbol = sp.Symbol(key) if isinstance(key, str) else key
        if not isinstance(symbol, sp.Symbol):
            problems.append(
                Problem(
                    "parameters", f"{key!r} is not a parameter name", "use a name or a SymPy Symbol"
                )
            )
            continue
        if symbol.name in names:
            problems.append(
                Problem(
                    f"parameters.{symbol.name}", "declared twice", "declare each parameter once"
                )
            )
            continue
        names.add(symbol.name)
        result[symbol] = _parameter_value(symbol.name, value, problems)
    return result


def _element(item: Any, canon: _Canonicalizer) -> Any:
    if not is_dataclass(item) or isinstance(item, type):
        return item
    changes = {}
    for f in fields(item):
        value = getattr(item, f.name)
        if f.name in ("name", "body"):
            continue
        if f.name == "coordinate":  # a voltage source names the charge it drives
            changes[f.name] = as_coordinate(value) if value is not None else value
            continue
        if f.name == "between":  # point names stay names; a malformed pair is the validator's
            if isinstance(value, tuple):
                changes[f.name] = tuple(v if isinstance(v, str) else canon(v) for v in value)
            continue
        if f.name == "at":
            changes[f.name] = value if isinstance(value, str) else canon(value)
            continue
        changes[f.name] = canon(value)
    return replace(item, **changes)


def normalize_system(system: System) -> dict[str, Any]:
    """Canonical field values for ``system`` (its mappings frozen); raises ModelError
    listing every problem."""
    problems: list[Problem] = []
    coordinates = _coordinates(system.coordinates, problems)
    parameters = _parameters(system.parameters, problems)
    canon = _Canonicalizer([*coordinates, *parameters])
    values: dict[str, Any] = {"coordinates": coordinates, "parameters": parameters}
    for name in EXPRESSION_FIELDS:
        values[name] = canon(getattr(system, name))
    forces = {}
    given = _mapping(system.generalized_forces, "generalized_forces", problems)
    for key, value in given.items():
        coordinate = as_coordinate(key)
        forces[coordinate if coordinate is not None else key] = canon(value)
    values["generalized_forces"] = forces
    values["gravity"] = None if system.gravity is None else canon(_as_vector(system.gravity))
    misfits: list[Problem] = []  # elements of the wrong kind, reported with the rest
    for name in ELEMENT_FIELDS:
        items = _elements_of_kind(name, getattr(system, name), misfits)
        values[name] = tuple(_element(item, canon) for item in items)
    values["initial"] = _mapping(system.initial, "initial", problems)
    values["initial"] = {(as_coordinate(k) or k): v for k, v in values["initial"].items()}
    values["simulation"] = _mapping(system.simulation, "simulation", problems)
    raise_if_problems(problems, "The system's coordinates or parameters are not valid", ModelError)
    problems.extend(misfits)
    problems.extend(resolve_orientations(values))  # before the bodies' rotations are checked
    problems.extend(add_rolling_constraints(values))
    move_contact_forces(values)  # onto the body, before the points are checked
    problems.extend(validate(values))
    raise_if_problems(
        problems, f"The system {system.name or ''} is not valid".replace("  ", " "), ModelError
    )
    for name in MAPPING_FIELDS:  # a System is a value: its mappings are read-only
        values[name] = FrozenMapping(values[name])
    return values


#: What each element field holds: its classes, one of them called, and how to build one.
ELEMENT_KINDS: dict[str, tuple[tuple[type, ...], str, str]] = {
    "particles": ((Particle,), "particle", "lagrangian.Particle(...)"),
    "rigid_bodies": ((RigidBody,), "rigid body", "lagrangian.RigidBody(...)"),
    "springs": ((Spring,), "spring", "lagrangian.Spring(...)"),
    "dampers": ((Damper,), "damper", "lagrangian.Damper(...)"),
    "forces": ((Force,), "force", "lagrangian.Force(...)"),
    "torques": ((Torque,), "torque", "lagrangian.Torque(...)"),
    "circuit": (
        get_args(CircuitElement),
        "circuit element",
        "Resistor, Capacitor, Inductor, MutualInductance or VoltageSource",
    ),
    "constraints": (
        get_args(Constraint),
        "constraint",
        "Holonomic, VelocityConstraint or Unilateral",
    ),
    "frames": ((Frame,), "frame", "lagrangian.model.Frame(...)"),
    "rolling": ((RollingDisc,), "rolling disc", "lagrangian.model.RollingDisc(...)"),
    "transitions": ((Transition,), "transition", "lagrangian.Transition(...)"),
}


def _elements_of_kind(name: str, items: tuple[Any, ...], problems: list[Problem]) -> list[Any]:
    """The items of element field ``name`` that are elements of its kind; a problem for each
    other one."""
    kinds, noun, maker = ELEMENT_KINDS[name]
    kept = []
    for i, item in enumerate(items):
        if isinstance(item, kinds):
            kept.append(item)
        else:
            message = f"{type(item).__name__} is not a {noun}"
            problems.append(Problem(f"{name}[{i}]", message, f"use {maker}"))
    return kept


def _mapping(value: Any, field: str, problems: list[Problem]) -> dict[Any, Any]:
    """``value`` as a dict; a problem (and nothing) when it is not a mapping."""
    if isinstance(value, Mapping):
        return dict(value)
    problems.append(Problem(field, f"{value!r} is not a mapping", "give {name: value, ...}"))
    return {}


def _as_vector(value: Any) -> Any:
    if isinstance(value, sp.MatrixBase):
        return tuple(value)
    if isinstance(value, (list, tuple)):
        return tuple(as_expression(v) for v in value)
    return value
