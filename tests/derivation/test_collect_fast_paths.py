"""collect_state's shortcuts give the very expressions of its general route: grouping terms
by the tuple of their state factors, remembering how each factor sorts (its sum put back),
and leaving out the arithmetic that changes nothing (1 x, b ** 1, b ** 0, e - 0, a product
of one factor) build the same SymEngine objects, structure and all, as the plain statement
of the algorithm below, over many generated expressions."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Mapping
from typing import Any

import symengine as se
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation.collect import (
    SHARED,
    _factor_common,
    collect_state,
    factor_common,
    product_powers,
    term_powers,
)

x, y, v, w = se.symbols("x y v w")  # the state
p, q, r, k = se.symbols("p q r k")  # parameters
s1, s2 = se.Dummy("sum"), se.Dummy("sum")  # symbols standing for sums of parameters
STATE = {x, y, v, w}
WHOLE = {s1: p + q + r, s2: 2 * p * q + 2 * p * r}
SUMS = {symbol: (whole, factor_common(list(whole.args))) for symbol, whole in WHOLE.items()}
NUMBERS = [se.Integer(n) for n in (2, -1, -3)] + [se.Rational(1, 2), se.Rational(-2, 3)]
NUMBERS.append(se.RealDouble(-1.5))
PARAMETERS = [p, q, r, p**2, q**3, p ** se.Rational(1, 2), p**k, p + q, s1, s2, s1**2]
MOVING = [x, v, v**2, se.sin(x), se.cos(x - y), se.sin(x) ** 2, se.cos(y), x + s1]


def _reference_factor_common(products: list[Any]) -> Any:
    """_factor_common with every operation written out."""
    if len(products) == 1:
        return se.Mul(*products[0])
    split = []
    for factors in products:
        number = se.Integer(1)
        powers: dict[Any, Any] = {}
        for factor in factors:
            if factor.is_Number:
                number *= factor
                continue
            base, exponent = factor.args if factor.is_Pow else (factor, se.Integer(1))
            powers[base] = powers[base] + exponent if base in powers else exponent
        split.append((number, powers))
    common = dict(split[0][1])
    for _, powers in split[1:]:
        for base in list(common):
            if base not in powers or not (common[base].is_Number and powers[base].is_Number):
                del common[base]
            else:
                common[base] = min(common[base], powers[base])
    magnitudes = {abs(number) for number, _ in split}
    scale = magnitudes.pop() if len(magnitudes) == 1 else se.Integer(1)
    if all(number < 0 for number, _ in split):
        scale = -scale
    if not common and scale == 1:
        return se.Add(*[se.Mul(*factors) for factors in products])
    outside = scale * se.Mul(*[b**e for b, e in common.items()])
    inside = se.Add(
        *[
            number / scale * se.Mul(*[b ** (e - common.get(b, 0)) for b, e in powers.items()])
            for number, powers in split
        ]
    )
    return outside * inside


def _put_back(factor: Any, sums: Mapping[Any, tuple[Any, Any]], form: int) -> Any:
    if factor in sums:
        return sums[factor][form]
    if factor.is_Pow and factor.args[0] in sums:
        return sums[factor.args[0]][form] ** factor.args[1]
    return factor


def _reference_with_sums(products: list[list[Any]], sums: Mapping[Any, Any]) -> Any:
    def holds(factor: Any) -> bool:
        return (factor.args[0] if factor.is_Pow else factor) in sums

    if not any(holds(f) for p in products for f in p):
        return _reference_factor_common(products)
    if len(products) == 1:
        return se.Mul(*[_put_back(f, sums, 1) for f in products[0]])
    expanded = se.expand(se.Add(*[se.Mul(*[_put_back(f, sums, 0) for f in p]) for p in products]))
    if expanded.is_Number:
        return expanded
    terms = expanded.args if expanded.is_Add else (expanded,)
    return _reference_factor_common([t.args if t.is_Mul else (t,) for t in terms])


def _reference_by_coefficient(pairs: list[tuple[Any, Any]], unchanged: Any) -> Any:
    shared: dict[Any, list[Any]] = {}
    for key, coefficient in pairs:
        if coefficient.is_Number:
            shared.setdefault(coefficient, []).append(key)
        elif coefficient.is_Mul and coefficient.args[0].is_Number and coefficient.args[0] < 0:
            shared.setdefault(-coefficient, []).append(-key)
        elif -coefficient in shared:
            shared[-coefficient].append(-key)
        else:
            shared.setdefault(coefficient, []).append(key)
    if unchanged is not None and all(len(keys) < SHARED for keys in shared.values()):
        return unchanged
    terms = []
    for coefficient, keys in shared.items():
        if coefficient.is_Number or len(keys) < SHARED:
            terms += [coefficient * key for key in keys]
        else:
            terms.append(coefficient * se.Add(*keys))
    return se.Add(*terms)


def _reference_collect(expr: Any, sums: Mapping[Any, Any] | None) -> Any:
    """collect_state as first written: every term's factors sorted, grouped by the product."""
    groups: dict[Any, list[list[Any]]] = defaultdict(list)
    for term in expr.args if expr.is_Add else (expr,):
        key: list[Any] = []
        coefficient: list[Any] = []
        for factor in term.args if term.is_Mul else (term,):
            symbols = factor.free_symbols
            moving = None if STATE.isdisjoint(symbols) else factor
            if sums and moving is not None and not symbols.isdisjoint(sums):
                moving = factor.xreplace({s: sums[s][0] for s in sums})
            if moving is None:
                coefficient.append(factor)
            else:
                key.append(moving)
        groups[se.Mul(*key)].append(coefficient)
    if sums:
        pairs = [(key, _reference_with_sums(products, sums)) for key, products in groups.items()]
        if len(pairs) < SHARED:
            return se.Add(*[key * coefficient for key, coefficient in pairs])
        return _reference_by_coefficient(pairs, None)
    if len(groups) < SHARED and all(len(v) == 1 for v in groups.values()):
        return expr
    pairs = [(key, _reference_factor_common(products)) for key, products in groups.items()]
    if len(pairs) < SHARED:
        return se.Add(*[key * coefficient for key, coefficient in pairs])
    single = all(len(v) == 1 for v in groups.values())
    return _reference_by_coefficient(pairs, expr if single else None)


def _same(a: Any, b: Any) -> bool:
    """The same expression, structure and all."""
    return bool(a == b) and str(a) == str(b) and a.args == b.args


products_st = st.lists(
    st.lists(st.sampled_from(NUMBERS + PARAMETERS), min_size=1, max_size=4, unique=True),
    min_size=1,
    max_size=6,
)
terms_st = st.lists(
    st.tuples(
        st.sampled_from(NUMBERS + [se.Integer(1)] * 3),
        st.lists(st.sampled_from(PARAMETERS), max_size=3, unique=True),
        st.lists(st.sampled_from(MOVING), max_size=2, unique=True),
    ),
    min_size=1,
    max_size=14,
)


def _expression(terms: list[tuple[Any, list[Any], list[Any]]]) -> Any:
    return se.Add(*[se.Mul(number, *params, *moving) for number, params, moving in terms])


@settings(max_examples=300, deadline=None)
@given(products_st)
def test_factor_common_builds_the_general_routes_expression(products: list[list[Any]]) -> None:
    factors = [se.Mul(*p).args if se.Mul(*p).is_Mul else (se.Mul(*p),) for p in products]
    assert _same(_factor_common(list(factors)), _reference_factor_common(list(factors)))


@settings(max_examples=300, deadline=None)
@given(products_st)
def test_factor_common_of_terms_builds_the_general_routes_expression(
    products: list[list[Any]],
) -> None:
    """Given the terms themselves (a sum with nothing common is summed from them)."""
    terms = [se.Mul(*p) for p in products]
    factors = [t.args if t.is_Mul else (t,) for t in terms]
    assert _same(factor_common(terms), _reference_factor_common(factors))


@settings(max_examples=200, deadline=None)
@given(st.lists(products_st, min_size=1, max_size=4))
def test_factor_common_with_remembered_term_powers_builds_the_general_routes_expression(
    sums: list[list[list[Any]]],
) -> None:
    """Terms met again (the same objects, and equal ones made afresh) factor as when first
    met, and their remembered powers are those of their factors, unchanged by the factoring."""
    term_powers.cache_clear()
    for products in sums + sums:
        terms = [se.Mul(*p) for p in products]
        factors = [t.args if t.is_Mul else (t,) for t in terms]
        assert _same(factor_common(terms), _reference_factor_common(factors))
        assert _same(factor_common([se.Mul(*p) for p in products]), factor_common(terms))
        for term, own in zip(terms, factors):
            number, powers = term_powers(term)
            fresh_number, fresh_powers = product_powers(list(own))
            assert _same(number, fresh_number)
            assert powers == fresh_powers


@settings(max_examples=300, deadline=None)
@given(st.lists(terms_st, min_size=1, max_size=3), st.booleans())
def test_collect_state_builds_the_general_routes_expression(
    expressions: list[list[Any]], with_sums: bool
) -> None:
    sums = SUMS if with_sums else None
    remembered: dict[Any, Any] = {}  # shared by the calls, as a system's equations share it
    for terms in expressions:
        expr = _expression(terms)
        expected = _reference_collect(expr, sums)
        assert _same(collect_state(expr, STATE, sums), expected)
        assert _same(collect_state(expr, STATE, sums, remembered), expected)


def test_collect_state_sums_shared_coefficients_as_before() -> None:
    """Three monomials under one coefficient, a negative one among them, with sums."""
    expr = se.expand(
        -p * q * s1 * se.sin(x) + p * q * s1 * se.cos(y) - p * q * s1 * v**2 + 3 * r * v
    )
    for sums in (SUMS, None):
        assert _same(collect_state(expr, STATE, sums, {}), _reference_collect(expr, sums))
