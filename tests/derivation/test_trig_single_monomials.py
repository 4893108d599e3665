"""combine_and_collect of a sum with nothing to combine (every term a product with at most
one sine or cosine of a plain angle: a chain of particles) is collected at once; it must be
exactly what the general route, through the trigonometric polynomial, gives."""

from __future__ import annotations

import symengine as se
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation import trig

q = se.symbols("q0:6")
v = se.symbols("v0:6")
a = se.symbols("a0:6")
t = se.Symbol("t")
p = se.symbols("p0:8")
STATE = {*q, *v, *a, t}
ANGLES = [q[0], q[1], q[0] - q[1], q[2] - q[4], -q[3] + q[5], q[1] + q[2], p[0], q[3] + p[1]]


def general(expr):
    """combine_and_collect with the shortcut turned off."""
    saved = trig._single_trig_expansion
    trig._single_trig_expansion = lambda expr, state: None
    try:
        return trig.combine_and_collect(expr, STATE)
    finally:
        trig._single_trig_expansion = saved


term_strategy = st.tuples(
    st.sampled_from([1, -1, 2, -3, se.Rational(1, 2), se.Rational(-5, 3)]),
    st.lists(st.sampled_from(p), max_size=3),
    st.lists(st.sampled_from([*q, *v, *a, t, v[0] ** 2, q[1] ** 3]), max_size=2),
    st.one_of(st.none(), st.tuples(st.sampled_from([se.sin, se.cos]), st.sampled_from(ANGLES))),
)


def product(spec):
    number, parameters, states, function = spec
    factors = [number, *parameters, *states]
    if function is not None:
        factors.append(function[0](function[1]))
    return se.Mul(*factors)


@settings(max_examples=300, deadline=None)
@given(st.lists(term_strategy, min_size=1, max_size=60))
def test_a_sum_of_single_trig_products_collects_as_the_general_route(specs):
    expr = se.Add(*[product(s) for s in specs])
    assert trig.combine_and_collect(expr, STATE) == general(expr)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(term_strategy, min_size=1, max_size=30),
    st.lists(
        st.tuples(
            st.sampled_from([-1, 2, se.Rational(-1, 2)]),
            st.lists(term_strategy, min_size=2, max_size=20),
        ),
        max_size=3,
    ),
)
def test_a_sum_with_numbers_times_sums_collects_as_the_general_route(specs, scaled):
    # -(C q_dot) + ...: a number times a sum of such products is expanded first
    expr = se.Add(
        *[product(s) for s in specs],
        *[se.Mul(n, se.Add(*[product(s) for s in inner])) for n, inner in scaled],
    )
    assert trig.combine_and_collect(expr, STATE) == general(expr)


def test_a_product_of_sums_is_not_expanded_by_the_shortcut():
    expr = (p[0] + v[0]) * (p[1] + v[1]) * se.sin(q[0]) + v[2]
    assert trig._single_trig_expansion(expr, STATE) is None


def test_a_long_sum_with_long_coefficients_goes_the_general_way_and_agrees():
    # past LARGE_POLYNOMIAL terms, a state monomial with more than FACTORED_TERMS terms
    # under it is left unfactored by the polynomial route: the shortcut must not be taken
    masses = se.symbols("m0:60")
    lengths = se.symbols("l0:10")
    shared = se.Add(*[m * v[0] ** 2 * se.sin(q[0] - q[1]) for m in masses])
    rest = se.Add(
        *[lk * m * a[k % 6] * se.cos(q[k % 6]) for k, lk in enumerate(lengths) for m in masses[:40]]
    )
    expr = shared + rest
    assert len(expr.args) > trig.LARGE_POLYNOMIAL
    assert trig._single_trig_expansion(expr, STATE) is None
    assert trig.combine_and_collect(expr, STATE) == general(expr)


def test_a_long_sum_with_short_coefficients_takes_the_shortcut_and_agrees():
    lengths = se.symbols("l0:450")
    expr = se.Add(
        *[lk * a[k % 6] * v[(k + 1) % 6] * se.cos(q[k % 5] - q[5]) for k, lk in enumerate(lengths)]
    )
    assert len(expr.args) > trig.LARGE_POLYNOMIAL
    assert trig._single_trig_expansion(expr, STATE) == expr
    assert trig.combine_and_collect(expr, STATE) == general(expr)


def test_products_squares_and_multiple_angles_go_the_general_way():
    for expr in (
        p[0] * se.sin(q[0]) * se.cos(q[1]) + v[0],
        p[0] * se.cos(q[0]) ** 2 + p[1] * se.sin(q[0]) ** 2,
        p[0] * se.cos(2 * q[0]) + v[1],
        p[0] * se.exp(q[0]) + v[1],
        p[0] * se.sqrt(q[0]) + v[1],
        (p[0] + v[0]) ** 2 * se.sin(q[0]),
    ):
        assert trig._single_trig_expansion(expr, STATE) is None, expr
