"""The parser's sums and products, made by the canonical Builder of
lagrangian.symbolic.canonical from what is known of their terms, are the expressions SymPy's
own Add and Mul make of the same terms: srepr-equal for texts generated from the grammar, for
every built-in model file and for a long chain's file."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.errors import ExpressionError
from lagrangian.examples import BENCHMARKS, CATALOG, SIZES, model_text
from lagrangian.symbolic import expressions
from lagrangian.symbolic.canonical import EXPR, Builder, Part
from lagrangian.symbolic.expressions import parse_expression

x, y, theta, m = sp.symbols("x y theta m")
q = sp.Symbol("q", positive=True)
NAMES = {s.name: s for s in (x, y, theta, m, q)}


class SympyConstructors(Builder):
    """Every sum and product made by SymPy's own constructors (the reference)."""

    def sum(self, parts: Sequence[Part]) -> Part:
        return self.part(sp.Add(*[p[EXPR] for p in parts]))

    def product(self, parts: Sequence[Part]) -> Part:
        return self.part(sp.Mul(*[p[EXPR] for p in parts]))


def _both(read: Any, monkeypatch: pytest.MonkeyPatch) -> tuple[Any, Any]:
    """``read()`` with the canonical Builder, then with SymPy's constructors."""
    found = read()
    with monkeypatch.context() as patched:
        patched.setattr(expressions, "CanonicalBuilder", SympyConstructors)
        reference = read()
    return found, reference


_LEAVES = st.sampled_from(["x", "y", "theta", "m", "q", "2", "3", "0.5", "1/3", "pi", "-1"])


def _grow(children: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    binary = st.tuples(children, st.sampled_from(["+", "-", "*", "/"]), children).map(
        lambda p: f"({p[0]}) {p[1]} ({p[2]})"
    )
    chain = st.lists(st.tuples(st.sampled_from(["+", "-", "*", "/"]), children), min_size=2).map(
        lambda links: "x" + "".join(f" {op} {term}" for op, term in links)
    )
    power = st.tuples(children, st.sampled_from(["2", "3", "-1", "(1/2)"])).map(
        lambda p: f"({p[0]})**{p[1]}"
    )
    call = st.tuples(st.sampled_from(["sin", "cos", "sqrt", "exp"]), children).map(
        lambda p: f"{p[0]}({p[1]})"
    )
    return st.one_of(binary, chain, power, call, children.map(lambda c: f"-({c})"))


@settings(deadline=None, max_examples=300)
@given(st.recursive(_LEAVES, _grow, max_leaves=12))
def test_generated_texts_parse_to_what_sympy_s_constructors_make(text: str) -> None:
    def read() -> str:
        try:
            return sp.srepr(parse_expression(text, NAMES, field="f"))
        except ExpressionError as error:
            return str(error)

    with pytest.MonkeyPatch.context() as monkeypatch:
        found, reference = _both(read, monkeypatch)
    assert found == reference


def _fields(value: object) -> object:
    """Every field of a System, and of what it holds, as srepr strings."""
    if isinstance(value, (sp.Basic, sp.MatrixBase)):
        return sp.srepr(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [(f.name, _fields(getattr(value, f.name))) for f in dataclasses.fields(value)]
    if isinstance(value, Mapping):
        return [(_fields(k), _fields(v)) for k, v in value.items()]
    if isinstance(value, (tuple, list)):
        return [_fields(v) for v in value]
    return repr(value)


@pytest.mark.parametrize("name", [*CATALOG, *BENCHMARKS])
def test_every_model_file_reads_as_with_sympy_s_constructors(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = model_text(name, 3 if name in SIZES else None)
    found, reference = _both(lambda: _fields(lg.loads(text, format="yaml")), monkeypatch)
    assert found == reference


def test_a_long_chain_s_file_reads_as_with_sympy_s_constructors(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    text = model_text("n_link_pendulum", 40)
    found, reference = _both(lambda: _fields(lg.loads(text, format="yaml")), monkeypatch)
    assert found == reference
