"""Read YAML (and JSON, which is YAML flow syntax) into a :class:`Document` with positions.

The text is composed into PyYAML's node tree (SafeLoader) so that every value keeps its start
mark; duplicate keys, which PyYAML would silently resolve to the last one, are reported.

>>> doc, problems = read_yaml("coordinates: [x]\\nkinetic: 'x_dot**2/2'\\n", "<string>")
>>> doc.data["kinetic"], doc.value_at("kinetic")
('x_dot**2/2', (2, 11))
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from typing import Any

import yaml
from yaml.constructor import SafeConstructor

from lagrangian.errors import ModelError, Problem
from lagrangian.io.document import Document, Position, child, syntax_error

#: The deepest nesting of lists and maps a model file may have.
MAX_DEPTH = 64
#: The most values a file may expand to: YAML aliases repeat what they name, so a few lines
#: of nested aliases ("billion laughs") would otherwise expand to gigabytes.
MAX_VALUES = 100_000
#: The most characters a model file may have (the examples have 2,000; a generated model of a
#: few thousand bodies fits): reading, composing and checking a file costs memory and time in
#: proportion to its size.
MAX_CHARACTERS = 1_000_000
#: The most digits of an integer: a longer one is beyond a double (1.8e308 has 309).
MAX_DIGITS = 309
_COLLECTION_TAGS = ("tag:yaml.org,2002:seq", "tag:yaml.org,2002:map")
_INT_TAG = "tag:yaml.org,2002:int"


class _Loader(yaml.SafeLoader):
    """SafeLoader that also reads ``1e-8`` as a number (YAML 1.2, JSON), not as text."""


#: The same loader on libyaml (the C parser), when PyYAML was built with it: it composes a
#: large file 30 times faster (:func:`_compose` says when it is used).
_FastLoader: type | None = None
if getattr(yaml, "__with_libyaml__", False):

    class _FastLoader(yaml.CSafeLoader):  # type: ignore[no-redef]
        """CSafeLoader that reads numbers as :class:`_Loader` does."""


for _loader in (_Loader, _FastLoader):
    if _loader is not None:
        _loader.add_implicit_resolver(  # type: ignore[attr-defined]
            "tag:yaml.org,2002:float",
            re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
            list("-+0123456789"),
        )


def _position(node: yaml.Node, text: str) -> Position:
    """Line and column (from 1) where the node's text starts: inside the quotes if quoted,
    on the line after the ``|`` or ``>`` of a block scalar (``text``: the text composed)."""
    mark = node.start_mark
    style = node.style if isinstance(node, yaml.ScalarNode) else None
    if style in ("|", ">"):
        start = text.find("\n", mark.index) + 1
        if start > 0:
            indent = len(text[start:]) - len(text[start:].lstrip(" "))
            return (mark.line + 2, indent + 1)
    return (mark.line + 1, mark.column + 1 + int(style in ('"', "'")))


class _TreeBuilder:
    """Turns composed nodes into plain data, recording positions and duplicate keys."""

    def __init__(self, source: str, text: str) -> None:
        self.source = source
        self.text = text
        self.values: dict[str, Position] = {}
        self.keys: dict[str, Position] = {}
        self.problems: list[Problem] = []
        self._constructor = SafeConstructor()
        self.count = 0

    def build(self, node: yaml.Node, path: str, depth: int = 0) -> Any:
        self.values[path] = _position(node, self.text)
        self.count += 1
        if self.count > MAX_VALUES:
            if self.count == MAX_VALUES + 1:
                self._problem(
                    path,
                    f"the file expands to more than {MAX_VALUES:,} values (YAML aliases?)",
                    "write the model without repeating anchors (*name)",
                )
            return None
        if depth > MAX_DEPTH:
            self._problem(path, "is nested too deeply (a recursive alias?)", "flatten it")
            return None
        if isinstance(node, yaml.CollectionNode) and node.tag not in _COLLECTION_TAGS:
            self._unknown_tag(node, path)
            return None
        if isinstance(node, yaml.MappingNode):
            return self._mapping(node, path, depth)
        if isinstance(node, yaml.SequenceNode):
            return [
                self.build(item, child(path, i), depth + 1) for i, item in enumerate(node.value)
            ]
        return self._scalar(node, path)

    def _scalar(self, node: yaml.Node, path: str) -> Any:
        if node.tag == _INT_TAG:  # before converting: Python refuses 4,300 digits and more
            digits = len(str(node.value).lstrip("+-").replace("_", ""))
            if digits > MAX_DIGITS:
                self._problem(
                    path,
                    f"an integer of {digits} digits is beyond a double (about 1.8e308)",
                    "give a smaller number, or write it in scientific notation",
                )
                return None
        try:
            return self._constructor.construct_object(node, deep=True)
        except yaml.constructor.ConstructorError:
            self._unknown_tag(node, path)
        except (ValueError, OverflowError) as error:  # a date such as 2024-13-45
            text = str(node.value)
            shown = text if len(text) <= 40 else text[:37] + "..."
            self._problem(
                path,
                f"{shown!r} cannot be read as a {node.tag.rsplit(':', 1)[-1]} ({error})",
                "write it in quotes to keep it as text",
            )
        return None

    def _mapping(self, node: yaml.MappingNode, path: str, depth: int) -> dict[str, Any]:
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                where = path or "the file"
                self._problem(path, f"{where} has a key that is not a name", "use plain names")
                continue
            if key_node.tag == "tag:yaml.org,2002:merge":
                self._problem(path, "YAML merge keys (<<) are not supported", "write the keys out")
                continue
            key = str(key_node.value)  # the key as written: `1:` or `on:` stay names
            key_path = child(path, key)
            if key in result:
                first = self.keys[key_path][0]
                self._problem(
                    key_path,
                    f"duplicate key {key!r} (first given on line {first})",
                    "give each key once (YAML would silently keep only the last)",
                    _position(key_node, self.text),
                )
                continue
            self.keys[key_path] = _position(key_node, self.text)
            result[key] = self.build(value_node, key_path, depth + 1)
        return result

    def _unknown_tag(self, node: yaml.Node, path: str) -> None:
        self._problem(
            path,
            f"unknown YAML tag {node.tag!r}",
            "remove it: model files use plain values (no !include, no !!python)",
        )

    def _problem(self, path: str, message: str, fix: str, where: Position | None = None) -> None:
        line, column = where or self.values.get(path, (None, None))
        self.problems.append(Problem(path, message, fix, line, column, self.source))


def _compose(text: str, source: str, language: str) -> yaml.Node | None:
    """The node tree of ``text``; a ModelError (syntax) naming the place when it is not YAML.

    libyaml composes it when it can do so safely and alike (:func:`_composed_alike`); every
    other text, and every text with an error, is composed by PyYAML, whose messages are the
    ones reported."""
    node = _composed_alike(text)
    if node is not None:
        return node
    try:
        return yaml.compose(text, Loader=_Loader)  # a SafeLoader subclass
    except RecursionError:
        detail = "lists or maps nested too deeply"
        raise syntax_error(source, language, detail, None, None) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, column = (mark.line + 1, mark.column + 1) if mark else (None, None)
        detail = " ".join(str(p) for p in (exc.context, exc.problem) if p)
        raise syntax_error(source, language, detail, line, column) from None
    except yaml.YAMLError as exc:
        raise syntax_error(source, language, str(exc), None, None) from None


#: Characters of YAML that libyaml and PyYAML read differently somewhere (a tab after a
#: value, ``|#``, a tag on nothing, an explicit key with nothing after it): a text with one
#: of them is composed by PyYAML, unless it is in a comment (:func:`_commented_read_apart`).
#: Model files of expressions use none of them, except ``>`` in a condition and ``|`` or
#: ``>`` for a long expression.
_READ_APART = frozenset("\t?!|>")
#: YAML's line breaks in an ASCII text (those that its marks count).
_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def _composed_alike(text: str) -> yaml.Node | None:
    """The node tree of ``text`` composed by libyaml, when it is the very tree PyYAML would
    compose (values, tags, lines and columns); None when that is not sure: libyaml missing, a
    text not ASCII (its marks then count characters as PyYAML's do) or with a character of
    :data:`_READ_APART` outside full-line comments, nested deeper than :data:`MAX_DEPTH`
    (libyaml's composer recurses in C, beyond Python's recursion limit), not read by libyaml,
    holding an empty value (libyaml places some of them a column apart from PyYAML), or with
    a quoted or block scalar across a line that looks like a comment and holds such a
    character (it is the scalar's text then, and a quote closing on it may be followed by
    YAML read apart)."""
    if _FastLoader is None or not text.isascii():
        return None
    commented = _commented_read_apart(text)
    if commented is None or not _nests_within(text, MAX_DEPTH):
        return None
    try:
        node = yaml.compose(text, Loader=_FastLoader)
    except yaml.YAMLError:
        return None
    for scalar in _distinct_scalars(node):
        if scalar.value == "" and not scalar.style:
            return None  # an empty value
        start, end = scalar.start_mark.line, scalar.end_mark.line
        if commented and scalar.style and any(start <= line <= end for line in commented):
            return None
    return node


def _commented_read_apart(text: str) -> list[int] | None:
    """The lines (from 0) holding a character of :data:`_READ_APART` that look like full-line
    comments (spaces, then ``#``); None when a tab is anywhere or such a character is on any
    other line.  Both parsers skip a comment whole, so what it holds cannot read apart; a
    line that looks like one and is not, inside a quoted or block scalar, is found by
    :func:`_composed_alike` from the scalars' marks."""
    if _READ_APART.isdisjoint(text):
        return []
    if "\t" in text:
        return None
    lines = []
    for number, line in enumerate(_LINE_BREAK.split(text)):
        if not _READ_APART.isdisjoint(line):
            if not line.lstrip(" ").startswith("#"):
                return None
            lines.append(number)
    return lines


def _distinct_scalars(node: yaml.Node | None) -> Iterator[yaml.ScalarNode]:
    """The scalar nodes in the tree of ``node``, each once (an alias is the node it names,
    and nested aliases would repeat it 9**10 times)."""
    stack, seen = [node] if node is not None else [], set()
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.ScalarNode):
            yield node
        elif isinstance(node, yaml.MappingNode):
            stack.extend(part for pair in node.value for part in pair)
        else:
            stack.extend(node.value)


def _nests_within(text: str, depth: int) -> bool:
    """Whether libyaml reads ``text`` as YAML whose lists and maps nest at most ``depth``
    deep, from its events (no recursion; it stops at the first level deeper)."""
    level = 0
    try:
        for event in yaml.parse(text, Loader=_FastLoader):
            if isinstance(event, yaml.CollectionStartEvent):
                level += 1
                if level > depth:
                    return False
            elif isinstance(event, yaml.CollectionEndEvent):
                level -= 1
    except yaml.YAMLError:
        return False
    return True


def _tree(node: yaml.Node | None, source: str, text: str) -> tuple[Document, list[Problem]]:
    if node is None:
        return Document(None, source), []
    builder = _TreeBuilder(source, text)
    data = builder.build(node, "")
    return Document(data, source, builder.values, builder.keys), builder.problems


def refuse_oversized(text: str, source: str) -> None:
    """Raise ModelError naming ``source`` when ``text`` has more than MAX_CHARACTERS.

    >>> refuse_oversized("x" * (MAX_CHARACTERS + 1), "big.yaml")
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: big.yaml cannot be read:
      - big.yaml: size: 1,000,001 characters, more than the 1,000,000 a model file may have \
— write the model with fewer or shorter entries
    """
    if len(text) > MAX_CHARACTERS:
        problem = Problem(
            "size",
            f"{len(text):,} characters, more than the {MAX_CHARACTERS:,} a model file may have",
            "write the model with fewer or shorter entries",
            source=source,
        )
        raise ModelError(f"{source} cannot be read:", [problem])


def read_yaml(text: str, source: str) -> tuple[Document, list[Problem]]:
    """The Document of a YAML text and its duplicate-key problems; ModelError on bad syntax."""
    refuse_oversized(text, source)
    return _tree(_compose(text, source, "YAML"), source, text)


def read_json(text: str, source: str) -> tuple[Document, list[Problem]]:
    """The Document of a JSON text, checked by :func:`json.loads`, positions from YAML.

    >>> read_json('{"coordinates": ["x"]}', "<string>")[0].value_at("coordinates[0]")
    (1, 19)
    """
    refuse_oversized(text, source)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise syntax_error(source, "JSON", exc.msg, exc.lineno, exc.colno) from None
    except RecursionError:
        raise syntax_error(source, "JSON", "lists or maps nested too deeply", None, None) from None
    except ValueError as exc:  # an integer beyond Python's 4,300 digits
        raise syntax_error(source, "JSON", str(exc).split(";")[0], None, None) from None
    try:
        # Raw tabs can only be whitespace in valid JSON; YAML refuses them in places.
        spaced = text.replace("\t", " ")
        document, problems = _tree(_compose(spaced, source, "JSON"), source, spaced)
    except ValueError:
        return Document(data, source), []
    if not problems and document.data != data:  # they disagree: trust json, drop positions
        return Document(data, source), []
    return document, problems
