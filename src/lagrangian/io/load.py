"""Load a model file (YAML, TOML or JSON) into a :class:`~lagrangian.model.System`.

Every problem of the file is collected (unknown sections and keys, wrong types, duplicate
names, bad expressions, ...) and raised once as a :class:`~lagrangian.errors.ModelError`
whose problems name the file, the field, the line and the column.  The System's own checks
are reported the same way, at the place in the file they come from.

>>> system = loads("coordinates: [x]\\nparameters: {k: 2}\\npotential: k*x**2/2\\n")
>>> system.potential
k*x**2/2
"""

from __future__ import annotations

import os
import re
from dataclasses import replace
from pathlib import Path
from typing import Any

import sympy as sp

from lagrangian.errors import (
    ExpressionError,
    ModelError,
    Problem,
    decode_text,
    raise_if_problems,
)
from lagrangian.io.applied import Loads, apply_loads, read_loads
from lagrangian.io.declarations import (
    expression_names,
    read_coordinates,
    read_initial,
    read_parameters,
    read_simulate,
    read_units,
)
from lagrangian.io.document import Document, parent
from lagrangian.io.reader import Reader
from lagrangian.io.sections import (
    MECHANICAL_SECTIONS,
    check_body_names,
    read_circuit,
    read_constraints,
    read_elements,
    read_energies,
    read_generalized_forces,
    read_transitions,
)
from lagrangian.io.toml_tree import read_toml
from lagrangian.io.yaml_tree import MAX_CHARACTERS, read_json, read_yaml
from lagrangian.model import System
from lagrangian.symbolic.sympy_view import cycle_collection_paused

FORMATS = ("yaml", "toml", "json")
SUFFIXES = {".yaml": "yaml", ".yml": "yaml", ".toml": "toml", ".json": "json"}
_NOT_A_PATH = re.compile(r"[\n{}\[\]]|: ")


def load(path: str | os.PathLike[str], *, format: str | None = None) -> System:
    """The System described by the model file at ``path`` (format from the extension .yaml,
    .yml, .toml or .json, or ``format``).

    ``load`` reads files only: the text of a model is read by :func:`loads`, never here.  A
    string that looks like model text (a newline, braces, ``key: value``) is refused without
    being opened, so text from elsewhere can never be taken for the name of a file whose lines
    an error message would then quote.

    >>> load("double_pendulum.yaml")  # doctest: +SKIP
    >>> load('{"coordinates": ["x"]}')  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: load takes the path of a model file, and this looks like ...
    """
    file = _as_path(path)
    with file.open("rb") as stream:  # no more than a model file may hold
        text = model_text(stream.read(MAX_BYTES), str(file))
    chosen = format or SUFFIXES.get(file.suffix.lower()) or _guess_format(text)
    return _load_text(text, chosen, str(file), file.stem)


#: The bytes read of a model file or of standard input: enough for one character more than
#: a model may hold (:data:`~lagrangian.io.yaml_tree.MAX_CHARACTERS`) in UTF-8's longest.
MAX_BYTES = 4 * (MAX_CHARACTERS + 1)


def model_text(data: bytes, source: str) -> str:
    """The text of a model read as ``data`` (at most :data:`MAX_BYTES` bytes of a file or of
    standard input): UTF-8, else a ModelError naming the byte, its line and column.  All
    :data:`MAX_BYTES` read means a file longer than a model may be: its start is kept (the
    last character may be cut), for the size check to refuse it by its length.

    >>> model_text(b"coordinates: [x]", "<string>")
    'coordinates: [x]'
    """
    if len(data) >= MAX_BYTES:
        return data.decode("utf-8", errors="replace")[: MAX_CHARACTERS + 1]
    return decode_text(data, source, ModelError)


def loads(text: str, format: str | None = None, source: str = "<string>") -> System:
    """The System described by the model text ``text`` in ``format`` ("yaml", "toml",
    "json"; default JSON when the text starts with ``{``, else YAML).

    ``source`` names the text in messages.

    >>> loads('coordinates = ["x"]', format="toml").coordinates
    (x,)
    """
    if not isinstance(text, str):
        raise ModelError(f"loads takes the text of a model (a str), not {type(text).__name__}")
    return _load_text(text, format or _guess_format(text), source, "")


def _as_path(value: object) -> Path:
    if isinstance(value, os.PathLike):
        return Path(value)
    if not isinstance(value, str):
        raise ModelError(
            f"load takes the path of a model file (a str or a pathlib.Path), not "
            f"{type(value).__name__}; model text goes to lagrangian.loads(text)"
        )
    if _NOT_A_PATH.search(value) or len(value) > 4096:
        raise ModelError(
            "load takes the path of a model file, and this looks like the text of a model: "
            "read text with lagrangian.loads(text) (format='toml' for TOML)"
        )
    return Path(value)  # a missing file raises FileNotFoundError, naming it


def _guess_format(text: str) -> str:
    return "json" if text.lstrip().startswith("{") else "yaml"


def _load_text(text: str, format: str, source: str, default_name: str) -> System:
    with cycle_collection_paused():  # as the System's own checks (parsing frees no cycles)
        return _system_of(text, format, source, default_name)


def _system_of(text: str, format: str, source: str, default_name: str) -> System:
    document, problems = _read_document(text, format, source)
    fields, system_paths, loads = _read_model(document, problems, default_name)
    try:  # the loads need the bodies' orientations: their paths are known once applied
        system_paths = {**apply_loads(fields, loads), **system_paths}
        system = System(**fields)
    except ModelError as exc:  # the System's own checks, moved to their place in the file
        located = [_locate(p, document, system_paths) for p in exc.problems]
    else:
        return system
    raise_if_problems(located, f"{source} does not describe a valid system", ModelError)
    raise AssertionError("a ModelError lists its problems")  # pragma: no cover


def _read_document(text: str, format: str, source: str) -> tuple[Document, list[Problem]]:
    if format == "yaml":
        return read_yaml(text, source)
    if format == "json":
        return read_json(text, source)
    if format == "toml":
        return read_toml(text, source), []
    problem = Problem("format", f"unknown format {format!r}", "use one of " + ", ".join(FORMATS))
    raise ModelError(f"{source} cannot be read:", [problem])


def _read_model(
    document: Document, problems: list[Problem], default_name: str
) -> tuple[dict[str, Any], dict[str, str], Loads]:
    """System keyword arguments read from the file, System field -> path in the file, and
    the forces and torques (:func:`lagrangian.io.applied.apply_loads` puts them in)."""
    reader = Reader(document)
    reader.problems.extend(problems)
    data = _top_level(reader, document.data)
    coordinates = read_coordinates(reader, data)
    parameters = read_parameters(reader, data, coordinates)
    reader.names = dict(expression_names(coordinates, parameters))
    check_body_names(reader, data)
    fields: dict[str, Any] = {
        "name": _text(reader, data, "name", default_name),
        "description": _text(reader, data, "description", ""),
        "coordinates": [sp.Symbol(q) for q in coordinates],
        "parameters": {sp.Symbol(p): value for p, value in parameters.items()},
        **read_energies(reader, data),
        "generalized_forces": read_generalized_forces(reader, data, coordinates),
        "initial": read_initial(reader, data, coordinates),
        "simulation": read_simulate(reader, data),
        "units": read_units(reader, data, coordinates, list(parameters)),
    }
    if "gravity" in data:
        fields["gravity"] = reader.vector(data["gravity"], "gravity")
    for section, definition in MECHANICAL_SECTIONS.items():
        if section in ("forces", "torques"):
            continue  # read with the loads below
        elements = read_elements(reader, data.get(section, []), section, definition, coordinates)
        fields[section] = [element for _, element in elements]
    loads = read_loads(reader, data, coordinates)
    circuit = read_circuit(reader, data, coordinates)
    fields["circuit"] = [element for _, element in circuit]
    constraints = read_constraints(reader, data)
    fields["constraints"] = [constraint for _, constraint in constraints]
    fields["transitions"] = read_transitions(reader, data)
    _raise_problems(reader)
    paths = {f"circuit[{i}]": path for i, (path, _) in enumerate(circuit)}
    for i, (path, _) in enumerate(constraints):  # the expression sits under its kind
        paths[f"constraints[{i}].expression"] = path
        paths[f"constraints[{i}]"] = parent(path) or path
    paths.update({f"coordinates.{q}": f"coordinates[{i}]" for i, q in enumerate(coordinates)})
    return fields, paths, loads


def _top_level(reader: Reader, data: Any) -> dict[str, Any]:
    """The mapping of sections, or raise: nothing else can be read without it."""
    if data is None:
        reader.problem("", "the model is empty", "give at least coordinates: [q]")
    elif (entry := reader.entry(data, "", None)) is not None:
        return entry
    else:
        reader.problems[-1] = replace(
            reader.problems[-1],
            message=f"a model is a mapping of sections, got {_kind(data)}",
            fix="start with coordinates: [q] (for TOML text pass format='toml')",
        )
    _raise_problems(reader)
    return {}  # pragma: no cover - _raise_problems raised


def _kind(data: Any) -> str:
    return "a list" if isinstance(data, list) else f"the value {data!r}"


def _text(reader: Reader, data: dict[str, Any], key: str, default: str) -> str:
    return (reader.text(data[key], key) or "") if key in data else default


def _raise_problems(reader: Reader) -> None:
    """Raise every problem found, in file order; an ExpressionError if all are expressions."""
    problems = sorted(reader.problems, key=lambda p: (p.line is None, p.line or 0, p.column or 0))
    only_expressions = bool(problems) and reader.expression_problems == len(problems)
    kind = ExpressionError if only_expressions else ModelError
    raise_if_problems(problems, f"{reader.document.source} is not a valid model file", kind)


def _locate(problem: Problem, document: Document, paths: dict[str, str]) -> Problem:
    """A System problem moved to the file: its path there, line, column and source."""
    path = _file_path(problem.field, paths)
    section = re.split(r"[.\[]", path, maxsplit=1)[0]
    at = document.key_at if section == "parameters" else document.value_at  # about the name
    line, column = at(path) if section in document.data else (None, None)
    return replace(problem, field=path, line=line, column=column, source=document.source)


def _file_path(field: str, paths: dict[str, str]) -> str:
    """``circuit[2].charge`` -> ``circuit.capacitors[0].charge`` (prefixes from ``paths``)."""
    for system_path, file_path in paths.items():
        if field == system_path or field.startswith((system_path + ".", system_path + "[")):
            return file_path + field[len(system_path) :]
    return field
