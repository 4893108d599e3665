"""The body of an API request, checked before any work: the model text, its format, and the
command-line options of the command by name (``set``, ``about``, ``t_end``, ...), each problem
named as ``options.NAME`` with its fix.

>>> body = {"model": "coordinates: [x]", "options": {"t_end": 2, "set": {"k": 3}}}
>>> read_request("simulate", body).options
{'t_end': 2.0, 'set': ['k=3.0']}
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from lagrangian.errors import ModelError, Problem, raise_if_problems

FORMATS = ("yaml", "toml", "json")


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"options.{name} is a number, as in {{{name!r}: 10}}")
    return float(value)


def _count(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"options.{name} is a whole number of at least 1, as in {{{name!r}: 500}}")
    return value


def _degree(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 3:
        raise ValueError(f"options.{name} is a whole number from 0 (no search) to 3")
    return value


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"options.{name} is true or false")
    return value


def _text(name: str, value: Any) -> str:
    if not isinstance(value, str):
        raise ValueError(f"options.{name} is a string, as in {{{name!r}: 'RK45'}}")
    return value


def _assignments(name: str, value: Any) -> list[str]:
    """``{"m": 2}`` or ``["m=2"]`` (the CLI's repeated ``--set m=2``) as ``["m=2"]``."""
    if isinstance(value, dict):
        return [f"{key}={_number(f'{name}.{key}', number)!r}" for key, number in value.items()]
    if isinstance(value, list) and all(isinstance(item, str) for item in value):
        return list(value)
    raise ValueError(f"options.{name} maps names to numbers, as in {{{name!r}: {{'m': 2}}}}")


def _state(name: str, value: Any) -> str:
    """``{"theta": 0.5}`` or ``"theta=0.5"`` (the CLI's ``--about theta=0.5``)."""
    if isinstance(value, str):
        return value
    return ",".join(_assignments(name, value))


def _names(name: str, value: Any) -> list[str]:
    if isinstance(value, list) and all(isinstance(item, str) for item in value):
        return list(value)
    raise ValueError(f"options.{name} is a list of parameter names, as in {{{name!r}: ['F']}}")


#: The languages of ``lagrangian export``.
LANGUAGES = ("numpy", "c", "matlab", "julia")


def _language(name: str, value: Any) -> str:
    if value not in LANGUAGES:
        raise ValueError(f"options.{name} is one of {', '.join(LANGUAGES)}")
    return str(value)


Reader = Callable[[str, Any], Any]
#: The options of each command, with how each is read.
OPTIONS: dict[str, dict[str, Reader]] = {
    "derive": {"set": _assignments, "steps": _flag},
    "analyze": {
        "set": _assignments,
        "about": _state,
        "input": _names,
        "project": _flag,
        "search_degree": _degree,
    },
    "simulate": {
        "set": _assignments,
        "initial": _assignments,
        "t_end": _number,
        "samples": _count,
        "method": _text,
        "rtol": _number,
        "atol": _number,
        "dt": _number,
        "max_steps": _count,
        "project_initial": _flag,
    },
    "export": {"set": _assignments, "language": _language},
}


@dataclass(frozen=True)
class Request:
    """A checked request: the command, the model text, its format, the options."""

    command: str
    model: str
    format: str
    options: dict[str, Any] = field(default_factory=dict)


def read_request(command: str, body: Any, max_samples: int = 20_000) -> Request:
    """The :class:`Request` of ``body`` (parsed JSON), or a ModelError listing every problem."""
    problems: list[Problem] = []
    if not isinstance(body, dict):
        problem = Problem("body", "the body is a JSON object", '{"model": "coordinates: [x] ..."}')
        raise ModelError("Bad request:", [problem])
    for key in sorted(set(body) - {"model", "format", "options"}):
        problems.append(Problem(key, "unknown key of the request", "use model, format, options"))
    model = body.get("model")
    if not isinstance(model, str) or not model.strip():
        problems.append(Problem("model", "the text of a model is missing", "give the model text"))
    fmt = body.get("format", "yaml")
    if fmt not in FORMATS:
        problems.append(Problem("format", f"unknown format {fmt!r}", "use yaml, toml or json"))
    given = body.get("options", {})
    if not isinstance(given, dict):
        problems.append(Problem("options", "options is a JSON object", '{"t_end": 10}'))
        given = {}
    options = _read_options(command, given, problems)
    samples = options.get("samples")
    if samples is not None and samples > max_samples:
        fix = f"ask for at most {max_samples} samples"
        problems.append(Problem("options.samples", f"{samples} samples is too many", fix))
    raise_if_problems(problems, "Bad request", ModelError)
    return Request(command, str(model), str(fmt), options)


def _read_options(command: str, given: dict[str, Any], problems: list[Problem]) -> dict[str, Any]:
    readers = OPTIONS[command]
    options: dict[str, Any] = {}
    for name, value in given.items():
        if name not in readers:
            fix = "the options of " + command + " are " + ", ".join(readers)
            problems.append(Problem(f"options.{name}", "unknown option", fix))
            continue
        if value is None:
            continue
        try:
            options[name] = readers[name](name, value)
        except ValueError as error:
            problems.append(Problem(f"options.{name}", "wrong type", str(error)))
    return options
