"""Combine trigonometric products early (issue: "structure, not brute force").

Mass-matrix entries built as sums of m J^T J contain products such as
cos a cos b + sin a sin b.  Writing every product of sines and cosines as a sum of single
sines and cosines of combined angles (product-to-sum, the "Fourier form") is canonical for
trigonometric polynomials, so identities such as sin^2 + cos^2 = 1 or
cos a cos b + sin a sin b = cos(a - b) collapse by ordinary term collection, without a
general-purpose simplify.  :func:`combine_trig` keeps whichever form is shortest.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import symengine as se

from lagrangian.derivation.collect import collect_state

MAX_TRIG_DEGREE = 8  # beyond this a term is left as it is (2**(d-1) Fourier terms)


def _split(term: Any) -> tuple[Any, list[Any]] | None:
    """term = coefficient * product(trig factors); None when a trig power is not a small
    positive integer."""
    factors = term.args if term.is_Mul else (term,)
    coefficient, trig = se.Integer(1), []
    for factor in factors:
        base, power = factor.args if factor.is_Pow else (factor, se.Integer(1))
        if isinstance(base, (se.sin, se.cos)):
            if not (power.is_Integer and 0 < int(power) <= MAX_TRIG_DEGREE):
                return None
            trig.extend([base] * int(power))
        else:
            coefficient = coefficient * factor
    if len(trig) > MAX_TRIG_DEGREE:
        return None
    return coefficient, trig


def _product_to_sum(a: Any, b: Any) -> list[tuple[Any, Any]]:
    """(coefficient, trig) pairs with a*b = sum(coefficient * trig)."""
    x, y = a.args[0], b.args[0]
    # SymEngine keeps theta - (psi - theta) nested: expanded, equal angles meet and collect
    difference, total = se.expand(x - y), se.expand(x + y)
    half = se.Rational(1, 2)
    if isinstance(a, se.cos) and isinstance(b, se.cos):
        return [(half, se.cos(difference)), (half, se.cos(total))]
    if isinstance(a, se.sin) and isinstance(b, se.sin):
        return [(half, se.cos(difference)), (-half, se.cos(total))]
    if isinstance(a, se.cos):  # sin y cos x = (sin(y + x) + sin(y - x)) / 2
        return [(half, se.sin(total)), (-half, se.sin(difference))]
    return [(half, se.sin(total)), (half, se.sin(difference))]


def _linearize(trig: list[Any]) -> list[tuple[Any, Any]]:
    """Product of trig factors as a list of (coefficient, single trig or 1)."""
    if not trig:
        return [(se.Integer(1), se.Integer(1))]
    terms = [(se.Integer(1), trig[0])]
    for factor in trig[1:]:
        new = []
        for coefficient, current in terms:
            if current == 1:
                new.append((coefficient, factor))
                continue
            for c, f in _product_to_sum(current, factor):
                number, single = _as_single(f)
                if number != 0:
                    new.append((coefficient * c * number, single))
        terms = new
    return terms


def _as_single(value: Any) -> tuple[Any, Any]:
    """(number, sin/cos or 1) from what a product-to-sum step gives: SymEngine evaluates
    sin(0) to 0, cos(0) to 1 and sin(-x) to -sin(x)."""
    if value.is_Number:
        return value, se.Integer(1)
    if value.is_Mul:
        number = se.Mul(*[a for a in value.args if a.is_Number])
        rest = se.Mul(*[a for a in value.args if not a.is_Number])
        return number, rest
    return se.Integer(1), value


def fourier_form(expr: Any) -> Any:
    """Every product of sines and cosines rewritten as a sum of single sines and cosines
    (``expr`` itself when it has no such product)."""
    expanded = se.expand(expr)
    terms = expanded.args if expanded.is_Add else (expanded,)
    split_terms = [_split(term) for term in terms]
    if all(split is None or len(split[1]) < 2 for split in split_terms):
        return expanded
    collected: dict[Any, Any] = defaultdict(lambda: se.Integer(0))
    for term, split in zip(terms, split_terms):
        if split is None or len(split[1]) < 2:
            collected[se.Integer(1)] += term
            continue
        coefficient, trig = split
        for c, f in _linearize(trig):
            collected[f] += coefficient * c
    return se.Add(*[se.expand(c) * f for f, c in collected.items()])


def _multiple_angles(expr: Any) -> bool:
    """True when some sin/cos argument contains a symbol with a coefficient other than +-1."""
    for atom in _trig_atoms(expr):
        argument = se.expand(atom.args[0])
        for term in argument.args if argument.is_Add else (argument,):
            if term.is_Mul and term.args[0].is_Number and abs(term.args[0]) != 1:
                return True
    return False


def _trig_atoms(expr: Any) -> set[Any]:
    return set(expr.atoms(se.sin, se.cos))


def size(expr: Any) -> int:
    """The number of operations in ``expr`` (SymEngine's count_ops)."""
    return int(se.count_ops(expr))


def tidy(expr: Any, state: Any) -> Any:
    """:func:`combine_trig`, then terms grouped by state monomial with parameters factored."""
    return collect_state(combine_trig(expr), state)


def combine_trig(expr: Any) -> Any:
    """The shortest of: the expanded expression, its Fourier form, and the Fourier form with
    double angles written back as squares (cos 2x = 1 - 2 sin^2 x = 2 cos^2 x - 1), which gives
    the textbook r^2 sin^2(theta) rather than r^2/2 - r^2 cos(2 theta)/2.  No general simplify."""
    expanded = se.expand(expr)
    fourier = fourier_form(expanded)
    if fourier is expanded:
        return expanded
    halves = _half_angle_forms(fourier)
    if not halves:  # no double angles to weigh: the plain size decides
        return min((expanded, fourier), key=size)
    return min((expanded, fourier, *halves), key=_textbook_size)


def _textbook_size(expr: Any) -> int:
    """Size, with multiple angles counted dearer: sin(x) cos(x) reads better than sin(2x)/2."""
    return size(expr) + 3 * sum(1 for atom in _trig_atoms(expr) if _multiple_angles(atom))


def _half_angle_forms(expr: Any) -> list[Any]:
    """``expr`` with every cos(2x) written as 1 - 2 sin^2 x, and as 2 cos^2 x - 1
    (sin(2x) as 2 sin x cos x in both)."""
    doubled = {}
    for atom in _trig_atoms(expr):
        half = se.expand(atom.args[0] / 2)
        if _multiple_angles(atom) and not _multiple_angles(se.sin(half)):
            doubled[atom] = half
    if not doubled:
        return []
    forms = []
    for cosine in (lambda x: 1 - 2 * se.sin(x) ** 2, lambda x: 2 * se.cos(x) ** 2 - 1):
        swap = {
            atom: (cosine(half) if isinstance(atom, se.cos) else 2 * se.sin(half) * se.cos(half))
            for atom, half in doubled.items()
        }
        forms.append(se.expand(expr.xreplace(swap)))
    return forms
