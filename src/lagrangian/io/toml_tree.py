"""Read TOML into a :class:`Document`, with positions found by a best-effort scan.

``tomllib`` parses the file but keeps no positions, so a small scanner walks the (already
valid) text again: table headers ``[a.b]`` and ``[[a]]``, ``key = value`` lines, and the
items of inline arrays and tables.  Where the scan cannot tell, a value has no position and
messages fall back to the line of the enclosing entry.

>>> doc = read_toml('coordinates = ["x"]\\n[parameters]\\nm = 1.0\\n', "<string>")
>>> doc.value_at("coordinates[0]"), doc.key_at("parameters.m")
((1, 17), (3, 1))
"""

from __future__ import annotations

import bisect
import contextlib
import re
import sys

from lagrangian.io.document import Document, Position, child, syntax_error
from lagrangian.io.yaml_tree import MAX_DEPTH, refuse_oversized

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

_AT = re.compile(r"\(at line (\d+), column (\d+)\)")
_BARE = re.compile(r"[A-Za-z0-9_-]+")
_TOKEN_END = re.compile(r"[\s,\]}#]")
_DOUBLE_BITS = 1024  # 2**1024 is past the largest double


def read_toml(text: str, source: str) -> Document:
    """The Document of a TOML text; ModelError with line and column on bad syntax."""
    refuse_oversized(text, source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        found = _AT.search(str(exc))
        line, column = (int(found[1]), int(found[2])) if found else (None, None)
        detail = _AT.sub("", str(exc)).strip()
        raise syntax_error(source, "TOML", detail, line, column) from None
    except RecursionError:
        raise syntax_error(source, "TOML", "lists or maps nested too deeply", None, None) from None
    except ValueError as exc:  # an integer beyond Python's 4,300 digits
        raise syntax_error(source, "TOML", str(exc).split(";")[0], None, None) from None
    _check_bounds(data, source, 0)
    scanner = _Scanner(text)
    with contextlib.suppress(IndexError, ValueError):  # best effort: keep what was found
        scanner.scan()
    return Document(data, source, scanner.values, scanner.keys)


def _check_bounds(value: object, source: str, depth: int) -> None:
    """The bounds the YAML reader keeps: nesting depth, and integers within a double."""
    if depth > MAX_DEPTH:
        raise syntax_error(source, "TOML", "lists or maps nested too deeply", None, None)
    if isinstance(value, dict):
        for item in value.values():
            _check_bounds(item, source, depth + 1)
    elif isinstance(value, list):
        for item in value:
            _check_bounds(item, source, depth + 1)
    elif isinstance(value, int) and value.bit_length() > _DOUBLE_BITS:
        detail = f"an integer of {len(str(value))} digits is beyond a double (about 1.8e308)"
        raise syntax_error(source, "TOML", detail, None, None)


class _Scanner:
    """Walks a valid TOML text and records where values and keys start."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.i = 0
        self.starts = [0] + [m.end() for m in re.finditer("\n", text)]
        self.values: dict[str, Position] = {"": (1, 1)}
        self.keys: dict[str, Position] = {}
        self.tables: dict[str, int] = {}  # array-of-tables path -> entries seen

    def at(self, offset: int) -> Position:
        line = bisect.bisect_right(self.starts, offset)
        return (line, offset - self.starts[line - 1] + 1)

    def scan(self) -> None:
        prefix = ""
        while self._skip(newlines=True) < len(self.text):
            if self.text.startswith("[", self.i):
                prefix = self._header()
            else:
                self._key_value(prefix)

    def _skip(self, *, newlines: bool) -> int:
        """Move past blanks and comments (and newlines when asked); the new offset."""
        space = " \t\r\n" if newlines else " \t"
        while self.i < len(self.text):
            if self.text[self.i] in space:
                self.i += 1
            elif self.text[self.i] == "#":
                end = self.text.find("\n", self.i)
                self.i = len(self.text) if end < 0 else end
            else:
                break
        return self.i

    def _resolve(self, parts: list[str], base: str = "") -> str:
        """The path of dotted key ``parts``, entering the latest entry of arrays of tables."""
        path = base
        for part in parts:
            path = child(path, part)
            if path in self.tables:
                path = child(path, self.tables[path] - 1)
        return path

    def _header(self) -> str:
        start = self.i
        array = self.text.startswith("[[", self.i)
        self.i += 2 if array else 1
        parts = self._key()
        self.i = self.text.index("]]" if array else "]", self.i) + (2 if array else 1)
        if not array:
            path = self._resolve(parts)
        else:
            base = child(self._resolve(parts[:-1]), parts[-1])
            self.tables[base] = self.tables.get(base, 0) + 1
            path = child(base, self.tables[base] - 1)
        self.values.setdefault(path, self.at(start))
        self.keys.setdefault(path, self.at(start))
        return path

    def _key(self) -> list[str]:
        """Read a dotted key (bare or quoted parts) and return its parts."""
        parts = []
        while True:
            self._skip(newlines=False)
            quote = self.text[self.i]
            if quote in "\"'":
                end = self.text.index(quote, self.i + 1)
                parts.append(self.text[self.i + 1 : end])
                self.i = end + 1
            else:
                match = _BARE.match(self.text, self.i)
                if not match:
                    raise ValueError("not a key")
                parts.append(match.group())
                self.i = match.end()
            self._skip(newlines=False)
            if not self.text.startswith(".", self.i):
                return parts
            self.i += 1

    def _key_value(self, prefix: str) -> None:
        start = self.i
        path = self._resolve(self._key(), prefix)
        self.keys[path] = self.at(start)
        self.i = self.text.index("=", self.i) + 1
        self._skip(newlines=False)
        self._value(path)

    def _value(self, path: str) -> None:
        text, i = self.text, self.i
        if text.startswith(('"""', "'''"), i):
            self.values[path] = self.at(i + 3)
            self.i = text.index(text[i : i + 3], i + 3) + 3
        elif text[i] in "\"'":
            self.values[path] = self.at(i + 1)
            self.i = self._string_end(i)
        elif text[i] in "[{":
            self.values[path] = self.at(i)
            self._container(path, text[i])
        else:
            self.values[path] = self.at(i)
            match = _TOKEN_END.search(text, i)
            self.i = match.start() if match else len(text)
            if self.i == i:
                raise ValueError("no value here")

    def _string_end(self, i: int) -> int:
        quote, j = self.text[i], i + 1
        while self.text[j] != quote:
            j += 2 if quote == '"' and self.text[j] == "\\" else 1
        return j + 1

    def _container(self, path: str, opening: str) -> None:
        closing, index = ("]" if opening == "[" else "}"), 0
        self.i += 1
        while self._skip(newlines=True) < len(self.text) and self.text[self.i] != closing:
            if opening == "[":
                self._value(child(path, index))
                index += 1
            else:
                self._key_value(path)
            self._skip(newlines=True)
            if self.text.startswith(",", self.i):
                self.i += 1
        self.i += 1
