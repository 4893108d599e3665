"""Typed reading of a model file's values, collecting every problem instead of stopping.

Each reading method takes a value and its path in the file and returns the value in model
terms (a SymPy expression, a vector, a name...), or ``None`` after recording a problem that
names the path, its line and column, and the fix.

>>> from lagrangian.io.document import Document
>>> reader = Reader(Document({}, "<string>"))
>>> reader.number("heavy", "parameters.m") is None, reader.problems[0].message
(True, "value 'heavy' is not a number")
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any, TypeVar

import sympy as sp

from lagrangian.errors import ExpressionError, Fix, Problem
from lagrangian.io.document import Document, child
from lagrangian.io.model_schema import entry_keys
from lagrangian.symbolic.expressions import (
    ParseCache,
    closest_name,
    parse_condition,
    parse_expression,
)
from lagrangian.symbolic.names import name_problem
from lagrangian.symbolic.probe import is_zero

T = TypeVar("T")

_EXAMPLE_VECTOR = 'a list such as ["l*sin(theta)", "-l*cos(theta)"]'


def describe(value: Any) -> str:
    """How a value of the wrong type is named in messages: ``describe([1]) == "a list"``."""
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if value is None:
        return "nothing (null)"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, (str, int, float)):
        return repr(value)
    return f"a {type(value).__name__}"


def suggestion(word: str, choices: Iterable[str], fix: str = "") -> str:
    """``"did you mean 'x'?"`` for the closest of ``choices`` (if any), then ``fix``.

    >>> suggestion("stifness", ["stiffness", "name"])
    "did you mean 'stiffness'?"
    """
    close = closest_name(word, choices)
    hint = f"did you mean {close!r}?" if close else ""
    return " ".join(part for part in (hint, fix) if part)


_MASSLESS = (
    "a frame is a massless reference frame (no inertia, no position)",
    "to give it mass, make it a rigid body (rigid_bodies: with mass, inertia and parent); "
    "else leave the key out",
)
#: Keys that belong to another kind of entry, with why they do not belong here and the fix.
_NOT_FOR: dict[tuple[str | None, str], tuple[str, str]] = {
    ("frame", key): (f"frames have no {word}: {_MASSLESS[0]}", _MASSLESS[1])
    for key, word in (("mass", "mass"), ("inertia", "inertia"), ("position", "position"))
}


class Reader:
    """Reads values of a Document; ``problems`` collects everything wrong."""

    def __init__(self, document: Document, names: Mapping[str, sp.Basic] | None = None) -> None:
        self.document = document
        self.names: dict[str, sp.Basic] = dict(names or {})
        self.problems: list[Problem] = []
        self.expression_problems = 0
        self.parsed = ParseCache()  # the expressions of one document share their parts

    def problem(self, path: str, message: str, fix: str | Fix = "", *, key: bool = False) -> None:
        """Record a problem at ``path`` (at its key when ``key``)."""
        self.problems.append(self.document.problem(path, message, fix, key=key))

    # -- structure ----------------------------------------------------------------------
    def mapping(self, value: Any, path: str) -> dict[str, Any] | None:
        """A mapping of keys to values."""
        if isinstance(value, dict):
            return value
        self.problem(
            path,
            f"must be a mapping of keys to values, got {describe(value)}",
            "write it as key: value pairs, e.g. {m: 1.0, g: 9.81}",
        )
        return None

    def items(self, value: Any, path: str) -> list[Any]:
        """A list (an empty list after a problem)."""
        if isinstance(value, list):
            return value
        self.problem(path, f"must be a list, got {describe(value)}", "write [ ... ] or - items")
        return []

    def entry(self, value: Any, path: str, definition: str | None) -> dict[str, Any] | None:
        """A mapping with the keys the schema allows for ``definition``; unknown and missing
        keys are reported (the top level, ``definition=None``, calls them sections)."""
        entry = self.mapping(value, path)
        if entry is None:
            return None
        keys = entry_keys(definition)
        word = "section" if definition is None else "key"
        meant = set()  # keys a misspelling stands for: not reported missing as well
        for key in entry:
            reason = _NOT_FOR.get((definition, key))
            if reason is not None:  # a key of another kind of entry, meant here
                self.problem(child(path, key), *reason, key=True)
                meant.add(key)
                continue
            if key not in keys.allowed:
                close = closest_name(key, keys.allowed)
                meant.update([close] if close else [])
                fix = suggestion(key, keys.allowed) or "allowed: " + ", ".join(keys.allowed)
                self.problem(child(path, key), f"unknown {word} {key!r}", fix, key=True)
        for key in keys.required:
            if key not in entry and key not in meant:
                self.problem(path or key, f"missing required {word} {key!r}", f"add {key}")
        return entry

    def entries(self, value: Any, path: str, definition: str) -> list[tuple[str, dict[str, Any]]]:
        """The entries of a list of mappings, each with its path."""
        found = []
        for i, item in enumerate(self.items(value, path)):
            entry = self.entry(item, child(path, i), definition)
            if entry is not None:
                found.append((child(path, i), entry))
        return found

    def known_entries(
        self, data: Mapping[str, Any], section: str, known: Iterable[str], unknown: str, fix: str
    ) -> Iterator[tuple[str, str, Any]]:
        """(key, path, value) of each entry of the mapping ``data[section]`` (a section keyed
        by declared names: initial values, units...) whose key is one of ``known``; every
        other key is reported at its key, with the message ``unknown`` (``{key!r}`` stands
        for the key), the closest known name and then ``fix``.

        >>> from lagrangian.io.document import Document
        >>> reader = Reader(Document({}, "<string>"))
        >>> data = {"initial": {"theta": 0.1, "thta_dot": 0.0}}
        >>> known = ["theta", "theta_dot"]
        >>> [key for key, path, value in reader.known_entries(
        ...     data, "initial", known, "{key!r} is not a coordinate", "give coordinates")]
        ['theta']
        >>> reader.problems[0].message, str(reader.problems[0].fix)
        ("'thta_dot' is not a coordinate", "did you mean 'theta_dot'? give coordinates")
        """
        known = list(known)
        for key, value in (self.mapping(data.get(section, {}), section) or {}).items():
            path = child(section, key)
            if key in known:
                yield key, path, value
            else:
                message = unknown.format(key=key)
                self.problem(path, message, suggestion(str(key), known, fix), key=True)

    def known_values(
        self,
        data: Mapping[str, Any],
        section: str,
        known: Iterable[str],
        unknown: str,
        fix: str,
        read: Callable[[Any, str], T | None],
    ) -> dict[str, T]:
        """The values of :meth:`known_entries`, each read by ``read(value, path)`` (a reading
        method: :meth:`number`, :meth:`expression`...), by key; a value that could not be
        read is left out, its problem recorded.

        >>> from lagrangian.io.document import Document
        >>> reader = Reader(Document({}, "<string>"))
        >>> data = {"initial": {"x": 0.5, "x_dot": "fast"}}
        >>> reader.known_values(data, "initial", ["x", "x_dot"], "", "", reader.number)
        {'x': 0.5}
        """
        entries = self.known_entries(data, section, known, unknown, fix)
        found = {key: read(value, path) for key, path, value in entries}
        return {key: value for key, value in found.items() if value is not None}

    def one_of(
        self, entry: Mapping[str, Any], kinds: Iterable[str], path: str, noun: str, example: str
    ) -> str | None:
        """The one key of ``kinds`` that ``entry`` has, or None after a problem naming those
        found (an entry is exactly one kind of thing: a holonomic constraint, an Euler-angle
        orientation...)."""
        kinds = tuple(kinds)
        found = [kind for kind in kinds if kind in entry]
        if len(found) == 1:
            return found[0]
        self.problem(
            path,
            f"{noun} has exactly one of {', '.join(kinds)}; found "
            + (" and ".join(found) if found else "none"),
            example,
        )
        return None

    # -- scalars ------------------------------------------------------------------------
    def expression(self, value: Any, path: str) -> sp.Expr | None:
        """An expression (text or number) parsed with the declared names."""
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            self.problem(
                path,
                f"expected an expression (text or a number), got {describe(value)}",
                'write one expression such as "m*g*l*cos(theta)"',
            )
            return None
        line, column = self.document.value_at(path)
        if isinstance(value, str) and column is not None:
            text = value.lstrip(" \t")  # so that columns count from the first character
            column += len(value) - len(text)
            value = text
        try:
            return parse_expression(
                value,
                self.names,
                field=path,
                source=self.document.source,
                line=line,
                column=column,
                cache=self.parsed,
                zero_test=is_zero,
            )
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            self.expression_problems += len(exc.problems)
            return None

    def vector(self, value: Any, path: str) -> tuple[sp.Expr, ...] | None:
        """A list of expressions (components)."""
        if not isinstance(value, list):
            self.problem(
                path,
                f"must be a list of expressions, got {describe(value)}",
                "give " + _EXAMPLE_VECTOR,
            )
            return None
        components = [self.expression(v, child(path, i)) for i, v in enumerate(value)]
        parsed = [c for c in components if c is not None]
        return tuple(parsed) if len(parsed) == len(components) else None

    def point(self, value: Any, path: str) -> str | tuple[sp.Expr, ...] | None:
        """A point: the name of a particle, body or ``origin``, or a position vector."""
        if isinstance(value, str):
            return self.name(value, path)
        if isinstance(value, list):
            return self.vector(value, path)
        self.problem(
            path,
            f"must be a point, got {describe(value)}",
            "name a particle, a rigid body or origin, or give " + _EXAMPLE_VECTOR,
        )
        return None

    def name(self, value: Any, path: str, *, key: bool = False) -> str | None:
        """A name: letters, digits and underscores, not starting with a digit; ASCII or Greek
        letters, not a Python keyword (:mod:`lagrangian.symbolic.names`)."""
        if isinstance(value, str) and value.isidentifier():
            found = name_problem(value)
            if found is None:
                return value
            self.problem(path, *found, key=key)
            return None
        self.problem(
            path,
            f"{describe(value)} is not a name",
            "use letters, digits and underscores, starting with a letter",
            key=key,
        )
        return None

    def condition(self, value: Any, path: str) -> sp.Basic | None:
        """A comparison of two expressions (``theta < 0``), parsed with the declared names."""
        if not isinstance(value, str):
            self.problem(path, f"expected a comparison, got {describe(value)}",
                         'write one comparison such as "theta < 0"')  # fmt: skip
            return None
        line, column = self.document.value_at(path)
        try:
            return parse_condition(value, self.names, field=path, source=self.document.source,
                                   line=line, column=column, zero_test=is_zero)  # fmt: skip
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            self.expression_problems += len(exc.problems)
            return None

    def text(self, value: Any, path: str) -> str | None:
        """Free text (a name or description)."""
        if isinstance(value, str):
            return value
        self.problem(path, f"must be text, got {describe(value)}", "quote it")
        return None

    def number(self, value: Any, path: str) -> float | None:
        """A finite real number."""
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            try:
                number = float(value)
            except OverflowError:  # an integer past the largest double
                number = math.inf
            if math.isfinite(number):
                return number
            self.problem(path, f"{describe(value)} is not a finite number", "give a finite number")
            return None
        self.problem(path, f"value {describe(value)} is not a number", "give a number such as 9.81")
        return None
