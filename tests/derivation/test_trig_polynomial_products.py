"""Products and reductions of trigonometric monomials (lagrangian.derivation.trig_polynomial)
checked against the numbers they stand for: a product of two polynomials, in either of the
two canonical forms (cos^2 or sin^2 written away), has the value of the product of their
values at any angles, and keeps no power it was meant to write away."""

from __future__ import annotations

import math

import symengine as se
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation.trig_polynomial import TrigAlgebra, pairs

x, y, z, m = se.symbols("x y z m")
ANGLES = (x, y, z)

# a monomial: a power 0..4 of the sine and of the cosine of each angle, times 1 or m
_powers = st.tuples(*[st.integers(0, 4) for _ in range(2 * len(ANGLES))])
_monomial = st.tuples(_powers, st.booleans())
_polynomial = st.lists(st.tuples(st.integers(-3, 3), _monomial), min_size=1, max_size=4)


def _expression(terms: list) -> se.Expr:
    total = se.Integer(0)
    for number, (powers, weighted) in terms:
        term = se.Integer(number) * (m if weighted else 1)
        for angle, sine, cosine in zip(ANGLES, powers[::2], powers[1::2]):
            term *= se.sin(angle) ** sine * se.cos(angle) ** cosine
        total += term
    return total


def _value(expr: se.Expr, at: dict) -> float:
    return float(expr.xreplace({s: se.Float(v) for s, v in at.items()}))


POINTS = ({x: 0.3, y: -1.1, z: 2.0, m: 1.7}, {x: -2.4, y: 0.9, z: 0.1, m: -0.6})


@settings(max_examples=60, deadline=None)
@given(_polynomial, _polynomial)
def test_products_keep_their_value_and_their_canonical_form(first: list, second: list) -> None:
    algebra = TrigAlgebra(ANGLES)
    p, q = (algebra.finish(algebra.convert(_expression(t))) for t in (first, second))
    product = algebra.finish(algebra.multiply(p, q))
    # every cosine to at most the first power: cos^2 written 1 - sin^2 as it is formed
    for key in product:
        assert all(e < 2 for i, e in pairs(key) if algebra.cosine[i])
    sines = algebra.sine_form(product)
    for key in sines:
        assert all(e < 2 for i, e in pairs(key) if algebra.sine[i])
    for at in POINTS:
        expected = _value(_expression(first), at) * _value(_expression(second), at)
        for form in (product, sines):
            found = _value(algebra.expression(form), at)
            assert math.isclose(found, expected, rel_tol=1e-9, abs_tol=1e-9)


@settings(max_examples=40, deadline=None)
@given(_polynomial)
def test_a_product_remembered_is_the_product_made_afresh(terms: list) -> None:
    """The memos of products and reductions give what a fresh algebra computes."""
    warm = TrigAlgebra(ANGLES)
    p = warm.finish(warm.convert(_expression(terms)))
    once = warm.finish(warm.multiply(p, p))
    again = warm.finish(warm.multiply(p, p))
    fresh = TrigAlgebra(ANGLES)
    q = fresh.finish(fresh.convert(_expression(terms)))
    made = fresh.finish(fresh.multiply(q, q))
    assert once == again
    assert se.expand(warm.expression(once) - fresh.expression(made)) == 0
