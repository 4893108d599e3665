"""Collect an expanded expression by its state-dependent monomials and factor the parameter
coefficients:  -g l1 m1 sin(theta1) - g l1 m2 sin(theta1)  ->  -g l1 (m1 + m2) sin(theta1).

This is the form a textbook writes (masses summed, lengths factored out) and it keeps the
output small: each state monomial appears once per equation.  Three or more monomials that
share a coefficient (up to sign; 3-D bodies have many) are summed under it as well:
l1 l2 (m2/2 + m3) (sin a1 sin a2 + cos a1 cos a2 cos b1 + ...).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable, Mapping
from typing import Any

import symengine as se

ONE = se.Integer(1)
#: How many monomials must share a coefficient for :func:`collect_state` to sum them under it.
SHARED = 3


def _powers(factors: list[Any]) -> tuple[Any, dict[Any, Any]]:
    """(numeric coefficient, {base: exponent}) of a product of parameters, given as the
    list of its factors."""
    number = ONE
    powers: dict[Any, Any] = {}
    for factor in factors:
        if factor.is_Number:
            number *= factor
            continue
        base, exponent = factor.args if factor.is_Pow else (factor, ONE)
        powers[base] = powers[base] + exponent if base in powers else exponent
    return number, powers


def factor_common(terms: list[Any]) -> Any:
    """Sum of ``terms`` (products of parameters) with their common factors pulled out."""
    if len(terms) == 1:
        return terms[0]
    return _factor_common([term.args if term.is_Mul else (term,) for term in terms])


def _factor_common(products: list[Any]) -> Any:
    """:func:`factor_common` of products given as the sequences of their factors."""
    if len(products) == 1:
        return se.Mul(*products[0])
    split = [_powers(factors) for factors in products]
    common = dict(split[0][1])
    for _, powers in split[1:]:
        for base in list(common):
            if base not in powers or not (common[base].is_Number and powers[base].is_Number):
                del common[base]
            else:
                common[base] = min(common[base], powers[base])
    magnitudes = {abs(number) for number, _ in split}
    scale = magnitudes.pop() if len(magnitudes) == 1 else ONE
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


def collect_state(
    expr: Any,
    state: Iterable[Any],
    sums: Mapping[Any, tuple[Any, Any]] | None = None,
    factors: dict[Any, Any] | None = None,
) -> Any:
    """Group the terms of expanded ``expr`` by their factors that depend on ``state``.

    ``sums`` maps symbols that stand for sums of parameters in ``expr`` to (the sum, the sum
    with its common factors pulled out): the result has the sums back, as though ``expr`` had
    been expanded with them (a coefficient that is one product takes the factored sum, several
    that hold such symbols are expanded together and factored as one).

    ``factors``, when given, remembers across calls with the same ``state`` and ``sums`` (a
    mapping that may grow, never change) how each factor is sorted: the same factors recur
    in every equation of a system."""
    state = set(state)
    terms = expr.args if expr.is_Add else (expr,)
    groups: dict[Any, list[list[Any]]] = defaultdict(list)
    # factor -> None for a factor free of the state (a coefficient), else the factor as it
    # goes into the key (with the sums of ``sums`` put back); factors recur across terms
    sorted_factors: dict[Any, Any] = {} if factors is None else factors
    for term in terms:
        key: list[Any] = []
        coefficient: list[Any] = []
        for factor in term.args if term.is_Mul else (term,):
            if factor in sorted_factors:
                moving = sorted_factors[factor]
            else:
                symbols = factor.free_symbols
                moving = None if state.isdisjoint(symbols) else factor
                if sums and moving is not None and not symbols.isdisjoint(sums):
                    moving = factor.xreplace({s: sums[s][0] for s in sums})
                sorted_factors[factor] = moving
            if moving is not None:
                key.append(moving)
            else:
                coefficient.append(factor)
        groups[se.Mul(*key)].append(coefficient)
    if sums:
        pairs = [(key, _with_sums(products, sums)) for key, products in groups.items()]
        if len(pairs) < SHARED:
            return se.Add(*[key * coefficient for key, coefficient in pairs])
        return _sum_by_coefficient(pairs, None)
    if len(groups) < SHARED and all(len(v) == 1 for v in groups.values()):
        return expr
    pairs = [(key, _factor_common(products)) for key, products in groups.items()]
    if len(pairs) < SHARED:
        return se.Add(*[key * coefficient for key, coefficient in pairs])
    return _sum_by_coefficient(pairs, expr if all(len(v) == 1 for v in groups.values()) else None)


def _with_sums(products: list[list[Any]], sums: Mapping[Any, tuple[Any, Any]]) -> Any:
    """:func:`_factor_common` of ``products`` whose symbols in ``sums`` stand for sums."""
    holding = [p for p in products if any(_base(f) in sums for f in p)]
    if not holding:
        return _factor_common(products)
    if len(products) == 1:  # c S -> c (S factored), the form the expanded c S collects to
        return se.Mul(*[_put_back(f, sums, 1) for f in products[0]])
    expanded = se.expand(se.Add(*[se.Mul(*[_put_back(f, sums, 0) for f in p]) for p in products]))
    if expanded.is_Number:
        return expanded
    terms = expanded.args if expanded.is_Add else (expanded,)
    return _factor_common([term.args if term.is_Mul else (term,) for term in terms])


def _base(factor: Any) -> Any:
    return factor.args[0] if factor.is_Pow else factor


def _put_back(factor: Any, sums: Mapping[Any, tuple[Any, Any]], form: int) -> Any:
    """``factor`` with a symbol of ``sums`` (or its power) replaced by form 0 (the sum) or
    1 (the factored sum)."""
    if factor in sums:
        return sums[factor][form]
    if factor.is_Pow and factor.args[0] in sums:
        return sums[factor.args[0]][form] ** factor.args[1]
    return factor


def _sum_by_coefficient(pairs: list[tuple[Any, Any]], unchanged: Any) -> Any:
    """sum key * coefficient with the keys of a coefficient (or of its negative) shared by
    :data:`SHARED` or more summed first: c k1 - c k2 + c k3 -> c (k1 - k2 + k3), c without
    a negative number in front; numbers are not factored out.  ``unchanged`` (when not
    None) is returned if nothing is shared."""
    shared: dict[Any, list[Any]] = {}
    for key, coefficient in pairs:
        if coefficient.is_Number:
            shared.setdefault(coefficient, []).append(key)
        elif coefficient.is_Mul and coefficient.args[0].is_Number and coefficient.args[0] < 0:
            # c k1 - c k2 + c k3 whichever sign comes first: the same form for the same sum
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
