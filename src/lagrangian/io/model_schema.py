"""The JSON Schema of the model file, shipped with the package, and the keys it allows.

The schema is the one list of sections and keys: the loader takes the keys each entry allows
and requires from it, so the schema and the loader cannot drift apart.

>>> schema()["required"]
['coordinates']
>>> sorted(entry_keys("spring").required)
['between', 'stiffness']
"""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from importlib.abc import Traversable

#: Where the JSON Schema (draft 2020-12) of the model file lives inside the package.
SCHEMA_PATH: Traversable = files("lagrangian.io").joinpath("model.schema.json")


@cache
def _schema() -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    return loaded


def schema() -> dict[str, Any]:
    """The JSON Schema of the model file (a fresh copy, free to modify)."""
    return copy.deepcopy(_schema())


@dataclass(frozen=True)
class EntryKeys:
    """The keys an entry (a mapping in the file) may have, and those it must have."""

    allowed: tuple[str, ...]
    required: tuple[str, ...]


@cache
def entry_keys(definition: str | None = None) -> EntryKeys:
    """Keys of the schema definition ``definition`` (``None``: the top level of the file)."""
    node = _schema() if definition is None else _schema()["$defs"][definition]
    return EntryKeys(tuple(node["properties"]), tuple(node.get("required", ())))
