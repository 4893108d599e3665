"""Product-to-sum combination of trigonometric products is an identity (property test against
numeric evaluation), and it collapses the identities the mass matrix needs."""

from __future__ import annotations

import math
import random

import symengine as se
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation.trig import combine_trig, fourier_form

a, b, c = se.symbols("a b c")
ANGLES = [a, b, c, a - b, b + c, 2 * a, a - b + c, se.Integer(0)]


def _value(expr: se.Basic, point: dict[se.Symbol, float]) -> float:
    return float(expr.subs(point))


@st.composite
def trig_polynomials(draw: st.DrawFn) -> se.Basic:
    terms = []
    for _ in range(draw(st.integers(1, 4))):
        factors = [se.Integer(draw(st.integers(-3, 3)))]
        for _ in range(draw(st.integers(0, 4))):
            function = draw(st.sampled_from([se.sin, se.cos]))
            factors.append(function(draw(st.sampled_from(ANGLES))) ** draw(st.integers(1, 3)))
        terms.append(se.Mul(*factors))
    return se.Add(*terms)


@settings(deadline=None, max_examples=150)
@given(trig_polynomials())
def test_fourier_form_and_combination_are_identities(expr: se.Basic) -> None:
    rng = random.Random(0)
    for _ in range(3):
        point = {s: rng.uniform(-3, 3) for s in (a, b, c)}
        expected = _value(expr, point)
        for form in (fourier_form(expr), combine_trig(expr)):
            assert math.isclose(_value(form, point), expected, rel_tol=1e-9, abs_tol=1e-9)


def test_identities_collapse() -> None:
    m, r = se.symbols("m r")
    assert combine_trig(m * (se.cos(a) * se.cos(b) + se.sin(a) * se.sin(b))) == m * se.cos(a - b)
    assert combine_trig(m * (se.sin(a) ** 2 + se.cos(a) ** 2)) == m
    assert combine_trig(se.sin(a) * se.cos(a) - se.cos(a) * se.sin(a)) == 0
    spherical = r**2 * se.sin(a) ** 2 * (se.sin(b) ** 2 + se.cos(b) ** 2)
    assert combine_trig(se.expand(spherical)) == r**2 * se.sin(a) ** 2


def test_a_product_whose_step_gives_sin_of_zero() -> None:
    # sin(a) cos(a)^2: the product-to-sum step yields sin(a - a) = 0, which must be dropped.
    expr = se.sin(a) * se.cos(a) ** 2
    point = {a: 0.7}
    assert math.isclose(_value(fourier_form(expr), point), _value(expr, point))


def test_products_of_three_factors_collect_their_equal_angles() -> None:
    """sin^2(theta) sin(psi) + cos^2(theta) sin(psi) = sin(psi): the product-to-sum steps give
    angles such as theta - (psi - theta), which must be expanded to meet psi - 2 theta."""
    theta, psi = se.symbols("theta psi")
    expr = se.sin(theta) * se.sin(psi) * se.sin(theta) + se.cos(theta) ** 2 * se.sin(psi)
    assert fourier_form(expr) == se.sin(psi)
    assert combine_trig(expr) == se.sin(psi)
