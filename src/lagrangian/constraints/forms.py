"""Differential forms on the extended configuration space z = (q_1, ..., q_n, t), just enough
for the integrability of Pfaffian constraints: wedge products and the exterior derivative.

A k-form is a mapping from increasing index tuples to coefficients,
``{(0, 2): f}`` is f dz_0 ^ dz_2.  For a 1-form omega = sum_k a_k dz_k,

    d omega = sum_{i<j} (da_j/dz_i - da_i/dz_j) dz_i ^ dz_j,

and omega is exact (omega = dh) when d omega = 0 on a simply connected region.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> exterior_derivative({(0,): -y, (1,): x}, (x, y))
{(0, 1): 2}
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import sympy as sp

from lagrangian.symbolic.conversion import to_sympy

Form = dict[tuple[int, ...], sp.Expr]


def one_form(coefficients: Iterable[sp.Expr]) -> Form:
    """sum_k a_k dz_k from its coefficients (zeros left out)."""
    return {(k,): to_sympy(a) for k, a in enumerate(coefficients) if a != 0}


def _sorted_with_sign(indices: tuple[int, ...]) -> tuple[tuple[int, ...], int]:
    """The increasing order of distinct ``indices`` and the sign of that permutation."""
    order = list(indices)
    sign = 1
    for i in range(len(order)):  # bubble sort: each swap flips the sign
        for j in range(len(order) - 1 - i):
            if order[j] > order[j + 1]:
                order[j], order[j + 1] = order[j + 1], order[j]
                sign = -sign
    return tuple(order), sign


def _add(result: Form, key: tuple[int, ...], value: sp.Expr) -> None:
    total = result.get(key, sp.Integer(0)) + value
    if total == 0:
        result.pop(key, None)
    else:
        result[key] = total


def wedge(a: Mapping[tuple[int, ...], sp.Expr], b: Mapping[tuple[int, ...], sp.Expr]) -> Form:
    """The exterior product a ^ b."""
    result: Form = {}
    for ia, ca in a.items():
        for ib, cb in b.items():
            if set(ia) & set(ib):
                continue
            key, sign = _sorted_with_sign(ia + ib)
            _add(result, key, sp.expand(sign * ca * cb))
    return result


def wedge_values(
    a: Mapping[tuple[int, ...], float], b: Mapping[tuple[int, ...], float]
) -> dict[tuple[int, ...], float]:
    """a ^ b of forms whose coefficients are numbers (a form's value at one point)."""
    result: dict[tuple[int, ...], float] = {}
    for ia, ca in a.items():
        for ib, cb in b.items():
            if not set(ia) & set(ib):
                key, sign = _sorted_with_sign(ia + ib)
                result[key] = result.get(key, 0.0) + sign * ca * cb
    return result


def exterior_derivative(
    a: Mapping[tuple[int, ...], sp.Expr], variables: Sequence[sp.Symbol]
) -> Form:
    """d a = sum_k d(coefficient)/dz_k dz_k ^ (dz_I)."""
    result: Form = {}
    for indices, coefficient in a.items():
        for k, z in enumerate(variables):
            if k in indices:
                continue
            slope = coefficient.diff(z)
            if slope != 0:
                key, sign = _sorted_with_sign((k, *indices))
                _add(result, key, sp.expand(sign * slope))
    return result


def describe(form: Mapping[tuple[int, ...], sp.Expr], variables: Sequence[sp.Symbol]) -> str:
    """``-1 dx^dy^dphi + ...`` for messages (first three terms)."""
    terms = [
        f"({coefficient}) " + "^".join(f"d{variables[i]}" for i in indices)
        for indices, coefficient in sorted(form.items())
    ]
    shown = " + ".join(terms[:3])
    return shown + (" + ..." if len(terms) > 3 else "")
