"""The expressions of one model share their parts while they are parsed (ParseCache): every
result and every refusal (message, fix, line, column) is the one of parsing each text alone."""

from __future__ import annotations

import pytest
import sympy as sp

from lagrangian.errors import ExpressionError
from lagrangian.symbolic.expressions import (
    MAX_DEPTH,
    ParseCache,
    _Builder,
    _read,
    _Refusal,
    parse_expression,
)

x, y, z, w, ll = sp.symbols("x y z w l")
NAMES = {
    "x": x,
    "y": y,
    "z": z,
    "w": w,
    "l": ll,
    **{f"th{i}": sp.Symbol(f"th{i}") for i in range(9)},
}


def outcome(text: str, names: dict[str, sp.Basic], cache: ParseCache | None) -> object:
    try:
        return sp.srepr(parse_expression(text, names, field="f", line=3, column=5, cache=cache))
    except ExpressionError as error:
        return [(p.field, p.message, p.fix, p.line, p.column) for p in error.problems]


def same_as_alone(texts: list[str], names: dict[str, sp.Basic] = NAMES) -> list[object]:
    cache = ParseCache()
    shared = [outcome(text, names, cache) for text in texts]
    assert shared == [outcome(text, names, None) for text in texts]
    return shared


def chain(n: int, term: str = "l*sin(th{})", op: str = " + ") -> str:
    return op.join(term.format(i) for i in range(1, n + 1))


def test_the_positions_of_a_chain_extend_each_other() -> None:
    texts = [chain(n) for n in range(1, 9)] + [chain(n, "-l*cos(th{})", " - ") for n in (1, 5, 8)]
    results = same_as_alone(texts)
    assert all(isinstance(result, str) for result in results)


@pytest.mark.parametrize(
    "texts",
    [
        ["x*y", "x*y + z", "x*y + z + w"],  # the left part of a sum is a product, then a sum
        ["x*y/z", "x*y/z*w", "x*y/z/w", "x*y/z - w"],
        ["x - y", "x - y - z", "x - y + z", "(x - y) - z", "x - (y - z)"],
        ["sin(x) + cos(y)", "sin(x) + cos(y) + sin(x)", "sin(x) + cos(y) - sin(x) - cos(y)"],
        ["x/y", "x/y/(y - y)", "x/y/0"],  # division by zero after a shared part
        ["(x +\n y)", "(x +\n y) + z", "x + y + z"],  # parts on several lines are not shared
        ["x + é", "x + y", "x + y + é"],
        ["x + y", "x + y + unknown", "x + y + _private", "x + y + 2**(1/3)**x"],
    ],
)
def test_results_and_refusals_are_those_of_each_text_alone(texts: list[str]) -> None:
    same_as_alone(texts)


def test_a_part_built_shallow_is_refused_where_it_would_nest_too_deep() -> None:
    part = "sin(" * 50 + "x" + ")" * 50
    deep = "cos(" * (MAX_DEPTH - 40) + part + ")" * (MAX_DEPTH - 40)
    results = same_as_alone([part, deep, part + " + x", f"x + {part}"])
    assert "nested more than" in results[1][0][1]  # type: ignore[index]


def test_the_number_budget_counts_shared_parts_at_each_use() -> None:
    part = "(x*7**1000 + y*7**1000)"  # each power spends 3,000 bits of the 50,000
    results = same_as_alone([part, " + ".join([part] * 7), " + ".join([part] * 9)])
    assert isinstance(results[1], str)
    assert "too large" in results[2][0][1]  # type: ignore[index]


def test_the_roots_budget_counts_shared_parts_at_each_use() -> None:
    root = f"sqrt({'9' * 150})"  # about 500 of the 512 bits of roots
    results = same_as_alone([root, f"x*{root}", f"{root} + x*{root}", f"x*{root} + {root}"])
    assert isinstance(results[0], str) and isinstance(results[1], str)
    assert "too large" in results[2][0][1]  # type: ignore[index]


def test_other_names_start_afresh() -> None:
    cache = ParseCache()
    first = parse_expression("a + b", {"a": x, "b": y}, field="f", cache=cache)
    second = parse_expression("a + b", {"a": z, "b": w}, field="f", cache=cache)
    assert (first, second) == (x + y, z + w)
    with pytest.raises(ExpressionError, match="unknown name 'b'"):
        parse_expression("a + b", {"a": x}, field="f", cache=cache)


def test_parts_past_the_room_are_built_again(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("lagrangian.symbolic.expressions._SHARED_CHARACTERS", 400)
    same_as_alone([chain(n) for n in range(1, 9)] * 2)


def test_a_system_s_symbols_are_made_canonical_wherever_a_part_recurs() -> None:
    from lagrangian.model import Particle, System

    theta, length, m = sp.symbols("theta l m")
    positive = sp.Symbol("l", positive=True)
    shared = length * sp.sin(theta)
    q = sp.Function("q")(sp.Symbol("t"))
    system = System(
        coordinates=[theta, "q"],
        parameters={length: 1.0, m: 1.0},
        particles=[
            Particle("a", m, (shared, -length * sp.cos(theta))),
            Particle("b", m, (shared + positive * sp.sin(theta), shared + q)),
        ],
        kinetic=m * q.diff(sp.Symbol("t")) ** 2 / 2,
    )
    b = system.particles[1].position
    assert b == (2 * length * sp.sin(theta), shared + sp.Symbol("q"))  # the positive l is l
    assert system.kinetic == m * sp.Symbol("q_dot") ** 2 / 2
    assert system.particles[0].position == (shared, -length * sp.cos(theta))


@pytest.mark.parametrize(
    "text",
    ["x", "th3", "  x", "x ", "\nx", "_x", "lambda", "None", "pi", "E", "sin", "é", "unknown", "q"],
)
def test_a_text_that_is_one_name_reads_as_its_syntax_tree_does(text: str) -> None:
    # "q" stands for an expression, "E" overrides the constant: both through the syntax tree
    names = {**NAMES, "q": x + 1, "E": y}
    expected: object
    try:
        body = text.lstrip()
        expected = sp.srepr(_Builder(body, names).build(_read(body).body, 1))
    except _Refusal as refusal:
        expected = refusal.message
    for cache in (None, ParseCache()):
        try:
            found: object = sp.srepr(parse_expression(text, names, field="f", cache=cache))
        except ExpressionError as error:
            found = error.problems[0].message
        assert found == expected
