"""Hypothesis fuzz of the model loader: documents built from the model file's JSON Schema
(``io/model.schema.json``), with values now and then swapped for something of the wrong
kind, written as YAML, JSON and TOML, and raw text.  Whatever comes in, ``loads`` returns a
System or raises a LagrangianError; any other exception is a bug.  A small budget runs by
default, a large one under ``-m slow``."""

from __future__ import annotations

import json
import math
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lagrangian.errors import LagrangianError
from lagrangian.io.load import loads
from lagrangian.io.model_schema import schema
from lagrangian.symbolic.expressions import FUNCTIONS

SCHEMA = schema()
COORDINATES = ["x", "y", "theta"]
PARAMETERS = ["m", "k", "g", "l"]
NAMES = [*COORDINATES, *PARAMETERS, *(f"{q}_dot" for q in COORDINATES), "t", "pi", "origin"]

FUZZ = settings(
    max_examples=60,
    deadline=None,  # no speed assertion: the test's question is what is raised
    derandomize=True,  # the same examples on every run: CI reproducible, a failure replayable
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
FUZZ_LONG = settings(FUZZ, max_examples=3000)

numbers = st.one_of(
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, 1, -1, 10**400, 2**1024, 1e308, 5e-324]),
)


@st.composite
def expressions(draw: st.DrawFn, depth: int = 0) -> str:
    """Text in (and sometimes just outside) the expression language."""
    leaves = st.one_of(
        st.sampled_from(NAMES), st.integers(0, 10**4).map(str), st.sampled_from(["0.5", "1e-3"])
    )
    if depth > 3 or draw(st.booleans()):
        return draw(leaves)
    kind = draw(st.sampled_from(["op", "call", "neg", "raw"]))
    if kind == "op":
        op = draw(st.sampled_from(["+", "-", "*", "/", "**", "^", "%", "//", "@", " and "]))
        return f"({draw(expressions(depth + 1))}){op}({draw(expressions(depth + 1))})"
    if kind == "call":
        name = draw(st.sampled_from([*FUNCTIONS, "eval", "__import__", "open", "Symbol"]))
        args = draw(st.lists(expressions(depth + 1), min_size=0, max_size=3))
        return f"{name}({', '.join(args)})"
    if kind == "neg":
        return f"-{draw(expressions(depth + 1))}"
    return draw(st.text(max_size=30))


def garbage() -> st.SearchStrategy[Any]:
    """A value of any kind, nested a little."""
    scalars = st.one_of(st.none(), st.booleans(), numbers, st.text(max_size=20))
    return st.recursive(
        scalars,
        lambda inner: st.one_of(
            st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
        ),
        max_leaves=12,
    )


def resolve(node: dict[str, Any]) -> dict[str, Any]:
    while "$ref" in node:
        target = node["$ref"].rsplit("/", 1)[-1]
        node = {**SCHEMA["$defs"][target], **{k: v for k, v in node.items() if k != "$ref"}}
    return node


@st.composite
def from_schema(draw: st.DrawFn, node: dict[str, Any], depth: int = 0) -> Any:
    """A value the schema node describes; one time in eight something else."""
    if depth > 6 or draw(st.integers(0, 7)) == 0:
        return draw(garbage())
    node = resolve(node)
    if "const" in node:
        return node["const"]
    if "enum" in node:
        return draw(st.sampled_from(node["enum"]))
    for key in ("oneOf", "anyOf"):
        if key in node and "type" not in node and "properties" not in node:
            return draw(from_schema(draw(st.sampled_from(node[key])), depth + 1))
    kinds = node.get("type", "object")
    kind = draw(st.sampled_from(kinds)) if isinstance(kinds, list) else kinds
    if kind == "string":
        if "pattern" in node:
            return draw(st.sampled_from(NAMES))
        return draw(expressions())
    if kind in ("number", "integer"):
        return draw(numbers)
    if kind == "boolean":
        return draw(st.booleans())
    if kind == "null":
        return None
    if kind == "array":
        items = node.get("prefixItems") or [node.get("items", {})]
        count = draw(st.integers(0, 4))
        return [draw(from_schema(items[i % len(items)], depth + 1)) for i in range(count)]
    properties = node.get("properties", {})
    keys = sorted(properties)
    chosen = draw(st.lists(st.sampled_from(keys), unique=True, max_size=6)) if keys else []
    document = {key: draw(from_schema(properties[key], depth + 1)) for key in chosen}
    extra = node.get("additionalProperties")
    if isinstance(extra, dict):
        for name in draw(st.lists(st.sampled_from(NAMES), unique=True, max_size=3)):
            document[name] = draw(from_schema(extra, depth + 1))
    return document


@st.composite
def documents(draw: st.DrawFn) -> dict[str, Any]:
    """A model document, three times in four with its coordinates and parameters declared."""
    document = draw(from_schema(SCHEMA))
    if not isinstance(document, dict):
        return {"coordinates": document}
    if draw(st.integers(0, 3)):  # declared well, so that the other sections are read deeply
        coordinates = st.lists(st.sampled_from(COORDINATES), min_size=1, unique=True)
        document["coordinates"] = draw(coordinates)
        document["parameters"] = dict.fromkeys(PARAMETERS, 1.0)
    return document


def toml_value(value: Any) -> str:
    """A TOML rendering of ``value`` (inline tables and arrays; None as an empty string)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return (
            "nan"
            if math.isnan(value)
            else ("inf" if value > 0 else "-inf")
            if math.isinf(value)
            else repr(value)
        )
    if isinstance(value, int):
        return str(value)
    if isinstance(value, dict):
        return (
            "{"
            + ", ".join(f"{json.dumps(str(k))} = {toml_value(v)}" for k, v in value.items())
            + "}"
        )
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return json.dumps("" if value is None else str(value))


def as_text(document: Any, language: str) -> str:
    if language == "yaml":
        return yaml.safe_dump(document, allow_unicode=True, sort_keys=False)
    if language == "json":
        return json.dumps(document)
    if not isinstance(document, dict):
        return toml_value(document)
    return "".join(f"{json.dumps(str(k))} = {toml_value(v)}\n" for k, v in document.items())


def load_or_refuse(text: str, language: str) -> None:
    """``loads`` either gives a System or raises a LagrangianError (which is fine)."""
    try:
        loads(text, language)
    except LagrangianError as error:
        assert str(error)  # a refusal says something
    except RecursionError:  # pragma: no cover - reported with the input that caused it
        pytest.fail(f"RecursionError on {language} text {text[:500]!r}")


LANGUAGES = st.sampled_from(["yaml", "json", "toml"])


@FUZZ
@given(documents(), LANGUAGES)
def test_a_document_from_the_schema_loads_or_is_refused(document, language):
    load_or_refuse(as_text(document, language), language)


@FUZZ
@given(st.text(max_size=300), LANGUAGES)
def test_raw_text_loads_or_is_refused(text, language):
    load_or_refuse(text, language)


@FUZZ
@given(
    st.lists(
        st.sampled_from(
            [
                "[",
                "]",
                "{",
                "}",
                "&a",
                "*a",
                "!t",
                ":",
                "-",
                ",",
                "'",
                '"',
                "\n",
                "  ",
                "x",
                "1",
                "coordinates:",
                "kinetic:",
                "9" * 400,
            ]
        ),
        max_size=60,
    ),
    LANGUAGES,
)
def test_yaml_punctuation_loads_or_is_refused(pieces, language):
    load_or_refuse("".join(pieces), language)


@pytest.mark.slow
@FUZZ_LONG
@given(documents(), LANGUAGES)
def test_a_document_from_the_schema_loads_or_is_refused_long_run(document, language):
    load_or_refuse(as_text(document, language), language)


@pytest.mark.slow
@FUZZ_LONG
@given(st.text(max_size=2000), LANGUAGES)
def test_raw_text_loads_or_is_refused_long_run(text, language):
    load_or_refuse(text, language)
