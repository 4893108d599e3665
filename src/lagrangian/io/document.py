"""A parsed model file: its plain data and where every value and key sits in the text.

Paths name a place in the file the way messages do: ``parameters.m``, ``particles[1].mass``,
``circuit.inductors[0].current``.

>>> doc = Document({"coordinates": ["x"]}, "m.yaml", values={"coordinates[0]": (1, 15)})
>>> doc.value_at("coordinates[0]")
(1, 15)
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from lagrangian.errors import Fix, ModelError, Problem

#: (line, column), both counted from 1; None where unknown.
Position = tuple[int | None, int | None]
NOWHERE: Position = (None, None)

_LAST_STEP = re.compile(r"(\[\d+\]|\.[^.\[]*)$")


def child(path: str, key: str | int) -> str:
    """The path of ``key`` inside ``path``: ``child("a", 0) == "a[0]"``, ``child("a", "b")``."""
    if isinstance(key, int):
        return f"{path}[{key}]"
    return f"{path}.{key}" if path else key


def parent(path: str) -> str | None:
    """The path one step up, ``None`` at the top: ``parent("a.b[0]") == "a.b"``."""
    if not path:
        return None
    match = _LAST_STEP.search(path)
    return path[: match.start()] if match else ""


@dataclass(frozen=True)
class Document:
    """Plain data (dicts, lists, scalars) read from ``source`` with the positions of its
    values and keys (paths as in messages)."""

    data: Any
    source: str
    values: Mapping[str, Position] = field(default_factory=dict)
    keys: Mapping[str, Position] = field(default_factory=dict)

    def value_at(self, path: str) -> Position:
        """Where the value at ``path`` starts; else the line of the nearest known ancestor."""
        if path in self.values:
            return self.values[path]
        up = parent(path)
        while up is not None:
            if up in self.values:
                return (self.values[up][0], None)
            up = parent(up)
        return NOWHERE

    def key_at(self, path: str) -> Position:
        """Where the key of the entry at ``path`` is written (its value if no key is known)."""
        return self.keys.get(path) or self.value_at(path)

    def problem(
        self, path: str, message: str, fix: str | Fix = "", *, key: bool = False
    ) -> Problem:
        """A Problem at ``path`` of this file (at its key when ``key``)."""
        line, column = self.key_at(path) if key else self.value_at(path)
        field = path or "(top level)"
        return Problem(field, message, fix, line=line, column=column, source=self.source)


def syntax_error(
    source: str, language: str, detail: str, line: int | None, column: int | None
) -> ModelError:
    """The error for a file that is not valid ``language`` (YAML, TOML or JSON)."""
    problem = Problem(
        "syntax",
        f"not valid {language}: {detail}",
        f"fix the {language} syntax at this place",
        line=line,
        column=column,
        source=source,
    )
    return ModelError(f"{source} cannot be read:", [problem])
