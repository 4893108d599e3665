"""Sums whose terms are products with a sum among their factors, and products of sums, made
by the canonical Builder: the same expressions (srepr-identical) as SymPy's Add and Mul of
the same arguments, whether two such terms combine or not, and whether their sums were made
by the Builder (their SymPy hash not asked) or by SymPy."""

from __future__ import annotations

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.symbolic.canonical import EXPR, Builder, Part

x, y, z, w = sp.symbols("x y z w")
#: Sums, each made by the Builder (``made``) or taken from SymPy (``given``).
SUMS = [(x, y), (x, z), (y, -z), (x, 2 * w, sp.Integer(1))]
OTHERS = [z, w, sp.sin(x), sp.cos(y) ** 2, sp.sqrt(x + y)]
NUMBERS = [sp.Integer(1), sp.Integer(2), sp.Integer(-3), sp.Rational(1, 2)]


def assert_identical(fast: sp.Expr, slow: sp.Expr) -> None:
    assert fast == slow
    assert type(fast) is type(slow)
    assert fast.args == slow.args
    assert sp.srepr(fast) == sp.srepr(slow)


def a_sum(build: Builder, index: int, made: bool) -> Part:
    terms = SUMS[index]
    if made:
        return build.sum([build.part(t) for t in terms])
    return build.part(sp.Add(*terms))


def factor_parts(build: Builder, factors: list[tuple[str, int, bool]]) -> list[Part]:
    parts = []
    for kind, index, made in factors:
        if kind == "sum":
            parts.append(a_sum(build, index, made))
        elif kind == "number":
            parts.append(build.part(NUMBERS[index % len(NUMBERS)]))
        else:
            parts.append(build.part(OTHERS[index % len(OTHERS)]))
    return parts


def test_two_products_of_equal_sums_made_apart_combine() -> None:
    """z (x + y) and 2 z (x + y), the sums made by the Builder or given by SymPy: SymPy's Add
    combines them into 3 z (x + y), and so does the Builder's sum."""
    for first_made in (True, False):
        for second_made in (True, False):
            build = Builder()
            one = build.product([build.part(z), a_sum(build, 0, first_made)])
            two = build.product(
                [build.part(sp.Integer(2)), build.part(z), a_sum(build, 0, second_made)]
            )
            made = build.sum([one, two, build.part(w)])[EXPR]
            assert_identical(made, sp.Add(one[EXPR], two[EXPR], w))
            assert made == 3 * z * (x + y) + w


def test_products_of_different_sums_with_the_same_other_factors_stay_apart() -> None:
    """z (x + y) + 2 z (x + z) + w (x + y): two terms alike but for their sums, one alike but
    for its other factor; nothing combines."""
    build = Builder()
    terms = [
        build.product([build.part(z), a_sum(build, 0, True)]),
        build.product([build.part(sp.Integer(2)), build.part(z), a_sum(build, 1, True)]),
        build.product([build.part(w), a_sum(build, 0, True)]),
    ]
    made = build.sum(terms)[EXPR]
    assert_identical(made, sp.Add(*[t[EXPR] for t in terms]))
    assert len(made.args) == 3


def test_a_sum_times_its_own_power_is_sympys_product() -> None:
    """(x + y) sqrt(x + y), the sum made by the Builder: SymPy's Mul gives (x + y)**(3/2)."""
    build = Builder()
    total = a_sum(build, 0, True)
    made = build.product([total, build.part(sp.sqrt(x + y))])[EXPR]
    assert_identical(made, sp.Mul(total[EXPR], sp.sqrt(x + y)))
    assert made == (x + y) ** sp.Rational(3, 2)


FACTOR = st.tuples(
    st.sampled_from(["sum", "number", "other"]),
    st.integers(min_value=0, max_value=len(SUMS) - 1),
    st.booleans(),
)


@settings(deadline=None, max_examples=300)
@given(st.lists(st.lists(FACTOR, min_size=1, max_size=4), min_size=1, max_size=5))
def test_sums_of_products_of_sums_are_sympys_add(
    products: list[list[tuple[str, int, bool]]],
) -> None:
    """Any sum of products of numbers, symbols, functions, powers and sums (made or given),
    one Builder for all: each product and the sum are SymPy's Mul and Add of the same
    arguments."""
    build = Builder()
    terms = []
    for factors in products:
        parts = factor_parts(build, factors)
        product = build.product(parts)
        assert_identical(product[EXPR], sp.Mul(*[p[EXPR] for p in parts]))
        terms.append(product)
    made = build.sum(terms)[EXPR]
    assert_identical(made, sp.Add(*[t[EXPR] for t in terms]))
