"""Collect an expanded expression by its state-dependent monomials and factor the parameter
coefficients:  -g l1 m1 sin(theta1) - g l1 m2 sin(theta1)  ->  -g l1 (m1 + m2) sin(theta1).

This is the form a textbook writes (masses summed, lengths factored out) and it keeps the
output small: each state monomial appears once per equation.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from typing import Any

import symengine as se


def _powers(expr: Any) -> tuple[Any, dict[Any, Any]]:
    """(numeric coefficient, {base: exponent}) of a product of parameters."""
    number = se.Integer(1)
    powers: dict[Any, Any] = {}
    for factor in expr.args if expr.is_Mul else (expr,):
        if factor.is_Number:
            number *= factor
            continue
        base, exponent = factor.args if factor.is_Pow else (factor, se.Integer(1))
        powers[base] = powers.get(base, 0) + exponent
    return number, powers


def factor_common(terms: list[Any]) -> Any:
    """Sum of ``terms`` (products of parameters) with their common factors pulled out."""
    if len(terms) == 1:
        return terms[0]
    split = [_powers(term) for term in terms]
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
        return se.Add(*terms)
    outside = scale * se.Mul(*[b**e for b, e in common.items()])
    inside = se.Add(
        *[
            number / scale * se.Mul(*[b ** (e - common.get(b, 0)) for b, e in powers.items()])
            for number, powers in split
        ]
    )
    return outside * inside


def collect_state(expr: Any, state: Iterable[Any]) -> Any:
    """Group the terms of expanded ``expr`` by their factors that depend on ``state``."""
    state = set(state)
    terms = expr.args if expr.is_Add else (expr,)
    groups: dict[Any, list[Any]] = defaultdict(list)
    for term in terms:
        factors = term.args if term.is_Mul else (term,)
        key: list[Any] = []
        coefficient: list[Any] = []
        for factor in factors:
            (key if factor.free_symbols & state else coefficient).append(factor)
        groups[se.Mul(*key)].append(se.Mul(*coefficient))
    if all(len(v) == 1 for v in groups.values()):
        return expr
    return se.Add(*[key * factor_common(coefficients) for key, coefficients in groups.items()])
