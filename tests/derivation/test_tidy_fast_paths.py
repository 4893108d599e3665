"""The shortcuts of the tidying decide exactly as the general route does: combined_trig's
one walk over the tree gives what expanding, checking every term of the expansion and
counting the expanded terms gives, and compress keeps the same sums whole however cheaply
it tells a moving sum from one of parameters."""

from __future__ import annotations

from typing import Any

import symengine as se
from hypothesis import example, given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.derivation.terms import combined_trig, euler_lagrange_terms
from lagrangian.derivation.trig import NESTED_CHECK_OPS, NESTED_TERMS, combine_trig, size
from lagrangian.derivation.trig_polynomial import expanded_terms

a, b, c, k = se.symbols("a b c k")
s = se.Dummy("s")
ANGLES = [a, b, a - b, a + b - c, -a + c, 2 * a, a - 2 * b, a * b, k * (a - b)]
ATOMS: list[Any] = [a, b, c, k, s, se.Integer(2), se.Rational(-1, 2), se.pi]


def _plain_angle(angle: Any) -> bool:
    terms = angle.args if angle.is_Add else (angle,)
    return all(
        term.is_Symbol
        or (
            term.is_Mul
            and len(term.args) == 2
            and term.args[1].is_Symbol
            and term.args[0] in (1, -1)
        )
        for term in terms
    )


def _at_most_one_plain_trig(term: Any) -> bool:
    """The rule of combined_trig, stated on a term of the expansion."""
    trig = 0
    for factor in term.args if term.is_Mul else (term,):
        if factor.is_Number or factor.is_Symbol:
            continue
        if factor.is_Pow:
            if not (factor.args[0].is_Symbol and factor.args[1].is_Integer):
                return False
        elif isinstance(factor, (se.sin, se.cos)) and _plain_angle(factor.args[0]):
            trig += 1
        else:
            return False
    return trig <= 1


def _general_route(expr: Any) -> Any:
    """combined_trig as its docstring states it: expand, check every term, count."""
    expanded = se.expand(expr)
    terms = expanded.args if expanded.is_Add else (expanded,)
    if not all(map(_at_most_one_plain_trig, terms)):
        return combine_trig(expr)
    if size(expr) > NESTED_CHECK_OPS and expanded_terms(expr, NESTED_TERMS) >= NESTED_TERMS:
        return expr
    return expanded


@st.composite
def expressions(draw: st.DrawFn, depth: int = 3) -> Any:
    kind = draw(st.integers(0, 7 if depth else 3))
    if kind in (0, 1):
        return draw(st.sampled_from(ATOMS))
    if kind == 2:
        trig = draw(st.sampled_from([se.sin, se.cos]))
        return trig(draw(st.sampled_from(ANGLES)))
    if kind == 3:
        base = draw(st.sampled_from([a, s, se.sin(a), a + b]))
        return base ** draw(st.sampled_from([-1, 2, 3, se.Rational(1, 2)]))
    parts = draw(st.lists(expressions(depth - 1), min_size=1, max_size=4))
    if kind in (4, 5):
        return se.Add(*parts)
    return se.Mul(*parts)


@settings(max_examples=300, deadline=None)
@given(expressions())
@example(se.cos(a) * se.cos(b) + se.sin(a) * se.sin(b))  # two sines or cosines: cos(a - b)
@example(k * (se.sin(a) * se.cos(b) - se.cos(a) * se.sin(b)) + k * se.cos(a - b))
@example(k * (se.sin(a) + c) * (se.cos(a) + c) - k * se.sin(2 * a) / 2)
def test_combined_trig_decides_as_the_general_route(expr: Any) -> None:
    ours, reference = combined_trig(expr), _general_route(expr)
    assert ours == reference
    assert ours.args == reference.args  # the very same expression, its terms in order


def test_a_long_product_of_sums_is_kept_nested_without_expanding_it() -> None:
    """2**18 expanded terms (beyond NESTED_TERMS) of a long expression: kept as it is."""
    sums = [se.Symbol(f"x{i}") + se.Symbol(f"y{i}") for i in range(18)]
    flat = se.Add(*[se.Symbol(f"z{i}") * se.cos(a) for i in range(NESTED_CHECK_OPS)])
    expr = flat + se.sin(a - b) * se.Mul(*sums)
    assert expanded_terms(expr, NESTED_TERMS) >= NESTED_TERMS
    assert size(expr) > NESTED_CHECK_OPS
    assert combined_trig(expr) == expr


def test_a_long_expression_within_the_bound_is_expanded() -> None:
    sums = [se.Symbol(f"x{i}") + se.Symbol(f"y{i}") for i in range(8)]
    flat = se.Add(*[se.Symbol(f"z{i}") * se.cos(a - c) for i in range(NESTED_CHECK_OPS)])
    expr = flat + se.sin(b) * se.Mul(*sums)
    assert combined_trig(expr) == _general_route(expr) == se.expand(expr)


def test_compress_keeps_whole_the_long_sums_of_parameters_only() -> None:
    """A long sum with a state symbol (a factor of a term, or only inside a sine) stays a
    sum; a long sum of parameters becomes one symbol, the same for the same sum."""
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(2))
    q, v = terms.assembly.q, terms.assembly.q_dot
    masses = se.symbols("p0:9")
    parameters = se.Add(*masses)
    movings = [
        se.Add(*[p * v[0] for p in masses]),
        se.Add(*[p * v[1] ** 2 for p in masses]),
        se.Add(*[p * se.sin(q[0]) for p in masses]),
        se.Add(*[p * se.sin(q[0]) for p in masses]) + v[0],
    ]
    for moving in movings:
        expr = k * moving * parameters * se.cos(q[1]) + c * parameters * v[1]
        compact = terms.compress(expr)
        (symbol,) = compact.free_symbols - expr.free_symbols
        assert compact.free_symbols >= moving.free_symbols
        factors = {f for term in compact.args for f in term.args}
        assert moving in factors and parameters not in factors
        assert terms.expand_sums(compact) == expr
        assert terms.expand_sums(symbol) == parameters
