"""The declaring sections of a model file: coordinates and parameters (which fix the names
expressions may use), initial values and simulation settings.

>>> sorted(expression_names(["x"], {"m": 1.0}))
['m', 't', 'x', 'x_dot']
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import sympy as sp

from lagrangian.io.document import child
from lagrangian.io.reader import Reader, describe
from lagrangian.model import t, velocity
from lagrangian.model.system import unit_problem
from lagrangian.model.validation import MAX_COORDINATES, MAX_PARAMETERS, too_many_parameters


def expression_names(coordinates: Iterable[str], parameters: Iterable[str]) -> dict[str, sp.Symbol]:
    """The names an expression may use: coordinates, NAME_dot, parameters and ``t``."""
    names: dict[str, sp.Symbol] = {}
    for name in coordinates:
        q = sp.Symbol(name)
        names[name] = q
        names[velocity(q).name] = velocity(q)
    names.update({name: sp.Symbol(name) for name in parameters})
    names["t"] = t
    return names


def read_coordinates(reader: Reader, data: dict[str, Any]) -> list[str]:
    """The coordinate names, each once; none at all is a problem."""
    if "coordinates" not in data:
        return []  # reported as a missing section
    items = reader.items(data["coordinates"], "coordinates")
    if len(items) > MAX_COORDINATES:  # refused before reading each name
        reader.problem(
            "coordinates",
            f"{len(items):,} coordinates, more than the {MAX_COORDINATES:,} a system may have",
            "model fewer degrees of freedom, or split the system into parts",
        )
        return []
    names: dict[str, int] = {}
    for i, item in enumerate(items):
        name = reader.name(item, child("coordinates", i))
        if name is None:
            continue
        if name in names:
            reader.problem(
                child("coordinates", i),
                f"coordinate {name!r} is listed twice (also coordinates[{names[name]}])",
                "list each coordinate once",
            )
            continue
        names[name] = i
    if isinstance(data["coordinates"], list) and not items:
        reader.problem("coordinates", "no generalized coordinates", "list at least one: [theta]")
    return list(names)


def read_parameters(
    reader: Reader, data: dict[str, Any], coordinates: list[str]
) -> dict[str, float | None]:
    """Parameter names with their default values (``None``: no default)."""
    raw = reader.mapping(data.get("parameters", {}), "parameters") or {}
    parameters: dict[str, float | None] = {}
    if len(raw) > MAX_PARAMETERS:  # the names stay declared (each read in linear time)
        found = too_many_parameters(len(raw))
        first_beyond = child("parameters", list(raw)[MAX_PARAMETERS])
        reader.problem(first_beyond, found.message, str(found.fix), key=True)
    for key, value in raw.items():
        path = child("parameters", key)
        name = reader.name(key, path, key=True)
        if name in coordinates:
            reader.problem(
                path,
                f"{name!r} is both a coordinate and a parameter",
                "a name is either a coordinate or a parameter; rename one of them",
                key=True,
            )
        elif name is not None:
            # A bad value is reported, but the name stays declared for the expressions.
            parameters[name] = None if value is None else reader.number(value, path)
    return parameters


def read_initial(
    reader: Reader, data: dict[str, Any], coordinates: list[str]
) -> dict[sp.Symbol, float]:
    """Initial values of coordinates and velocities."""
    known = [*coordinates, *(velocity(sp.Symbol(q)).name for q in coordinates)]
    unknown = "{key!r} is not a coordinate or a velocity"
    fix = "give values of coordinates and NAME_dot velocities"
    initial = reader.known_values(data, "initial", known, unknown, fix, reader.number)
    return {sp.Symbol(key): number for key, number in initial.items()}


def read_units(
    reader: Reader, data: dict[str, Any], coordinates: list[str], parameters: list[str]
) -> dict[str, str]:
    """Units of coordinates, parameters and ``t``, as free text (``{l: m, theta: rad}``):
    short, in the characters of :func:`lagrangian.model.system.unit_problem`."""
    known = [*coordinates, *parameters, "t"]
    units: dict[str, str] = {}
    unknown = "{key!r} is not a coordinate, parameter or t"
    fix = "give units of coordinates, parameters and t"
    for key, path, value in reader.known_entries(data, "units", known, unknown, fix):
        message = unit_problem(value)
        if message is not None:
            reader.problem(path, message, "write it as text such as m, rad or m/s^2")
        else:
            units[key] = value
    return units


def read_simulate(reader: Reader, data: dict[str, Any]) -> dict[str, Any]:
    """Simulation settings, checked: positive t_end, rtol, atol; a positive integer samples."""
    entry = reader.entry(data.get("simulate", {}), "simulate", "simulate") or {}
    settings: dict[str, Any] = {}
    for key, value in entry.items():
        path = child("simulate", key)
        if key == "method":
            if reader.text(value, path) is not None:
                settings[key] = value
        elif key == "samples":
            if isinstance(value, int) and not isinstance(value, bool) and value >= 1:
                settings[key] = value
            else:
                reader.problem(
                    path,
                    f"{describe(value)} is not a positive whole number",
                    "give one such as 1000",
                )
        elif key in ("t_end", "rtol", "atol"):
            number = reader.number(value, path)
            if number is not None and number <= 0:
                reader.problem(path, f"must be positive, got {value!r}", "give a number > 0")
            elif number is not None:
                settings[key] = value
    return settings
