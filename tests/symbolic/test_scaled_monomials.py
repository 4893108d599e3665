"""The conversion's shortcuts for the terms of sums, a number times a sum, powers, and sines
and cosines of symbols: each result the same expression (equal arguments in the same order,
srepr-identical) as SymPy's own constructors build."""

from __future__ import annotations

import symengine as se
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.size_limits import operations
from lagrangian.symbolic.canonical import Builder
from lagrangian.symbolic.sympy_view import SympyView, plain_power

x, y, z = sp.symbols("x y z")
s = sp.Symbol("s", positive=True)
FACTORS = [x, y, z, s, sp.sin(x), sp.cos(y), sp.cos(x - y), -sp.sin(x - y), x**2, y**-1]
FACTORS += [sp.sqrt(x + y), x + z, sp.exp(z), sp.I, sp.pi, sp.sqrt(2), sp.Integer(3)]
NUMBERS = [sp.Integer(n) for n in (-3, -1, 0, 1, 2)]
NUMBERS += [sp.Rational(-1, 2), sp.Float(0.5), sp.sqrt(3), sp.I]


def assert_identical(fast: sp.Expr, slow: sp.Expr) -> None:
    assert fast == slow
    assert type(fast) is type(slow)
    assert fast.args == slow.args
    assert sp.srepr(fast) == sp.srepr(slow)


@settings(deadline=None, max_examples=400)
@given(
    st.lists(st.sampled_from(FACTORS), min_size=1, max_size=5),
    st.lists(st.sampled_from(NUMBERS), min_size=1, max_size=3),
)
def test_a_monomial_scaled_is_sympys_mul(factors: list[sp.Expr], numbers: list[sp.Expr]) -> None:
    """A monomial read once and scaled by several numbers gives sp.Mul(number, *factors)
    for each, whether the factors are only sorted (distinct commutative bases) or not."""
    build = Builder()
    monomial = build.monomial([build.part(f) for f in factors])
    for number in numbers:
        made = build.scaled(build.part(number), monomial)[0]
        assert_identical(made, sp.Mul(number, *factors))


BACKEND = se.symbols("x y z")
bx, by, bz = BACKEND
TERMS = [bx * by, se.sin(bx) * se.cos(by) ** 2, bz, se.cos(bx - by) * bz, (bx + by) * bz]


@settings(deadline=None, max_examples=200)
@given(
    st.lists(
        st.tuples(st.sampled_from([2, -1, 3, se.Rational(1, 3)]), st.sampled_from(TERMS)),
        min_size=1,
        max_size=5,
    )
)
def test_terms_met_again_with_other_numbers_convert_as_sympy_builds_them(
    scaled: list[tuple[object, object]],
) -> None:
    """Sums that share their terms with other coefficients (each term's factors read once),
    each the SymPy sum of the converted terms."""
    view = SympyView([x, y, z])
    for number, term in scaled:
        total = se.Add(number * term, 7 * term + bx)
        expected = sp.Add(*[sp.sympify(a) for a in total.args])
        assert_identical(view(total), expected)


def test_a_term_of_another_terms_hash_converts_to_itself() -> None:
    """Two terms whose remembered factors share a hash (a clash, set up here by moving one's
    entry under the other's) are each converted to themselves."""
    view = SympyView([x, y, z])
    first, second = bx * by, bx * bz
    view(2 * first + bz)
    view._factors[hash(second)] = view._factors.pop(hash(first))
    for total in (3 * second + by, 5 * first + by, 3 * second + bx):
        expected = sp.Add(*[sp.sympify(a) for a in total.args])
        assert_identical(view(total), expected)
    # the clashing term's factors read once: its products with a number met again are found
    products = len(view._products)
    view(3 * second + 2 * by)  # a sum not met yet, its term met with 3 before
    assert len(view._products) == products + 1  # 2 * by's alone


def test_sines_and_cosines_of_symbols_are_sympys() -> None:
    """A sine or a cosine of a symbol of any assumptions (zero ones evaluate), of a symbol
    standing for another expression, and of a number, as SymPy's sin and cos make them."""
    angle = se.Symbol("a")
    for assumptions in ({}, {"positive": True}, {"real": True}, {"integer": True}, {"zero": True}):
        symbol = sp.Symbol("a", **assumptions)
        for stands_for in (symbol, sp.Dummy("a"), sp.Function("q")(sp.Symbol("t")), -symbol):
            view = SympyView([], {"a": stands_for})
            for backend, function in ((se.sin, sp.sin), (se.cos, sp.cos)):
                assert_identical(view(backend(angle)), function(stands_for))
                assert_identical(view(3 * backend(angle)), 3 * function(stands_for))
    view = SympyView([])
    assert_identical(view(se.sin(se.Integer(2))), sp.sin(2))


def test_numbers_are_those_sympify_makes() -> None:
    """SymEngine's integers and rationals, made directly, and its other numbers, each the
    number ``sympify`` makes of it, alone and as a coefficient."""
    view = SympyView([x])
    numbers = [se.Integer(n) for n in (0, 1, -1, 2, 10**30)]
    numbers += [se.Rational(1, 2), se.Rational(-3, 4), se.Rational(-(10**30), 7)]
    numbers += [se.RealDouble(0.25), se.I, se.Integer(2) + 3 * se.I]
    for number in numbers:
        assert_identical(view(number), sp.sympify(number, strict=True))
        total = number * bx + by
        expected = sp.Add(*[sp.sympify(a) for a in total.args]) if total.is_Add else y
        assert_identical(view(total), expected)


SUM_TERMS = [bx, bx * by, se.sin(bx) * se.cos(by) ** 2, bz + by, (bx + by) * bz]
SUM_TERMS += [se.sqrt(bx + bz) * by, se.cos(bx - by) * bx**2]


@settings(deadline=None, max_examples=300)
@given(
    st.sampled_from([-1, 2, -3, se.Rational(-1, 2), se.Rational(3, 4)]),
    st.sampled_from([0, 1, -5, se.Rational(1, 3)]),
    st.lists(
        st.tuples(st.sampled_from([1, -1, 2, se.Rational(-2, 3)]), st.sampled_from(SUM_TERMS)),
        min_size=1,
        max_size=6,
    ),
)
def test_a_rational_times_a_sum_is_sympys_distributed_product(
    number: object, constant: object, terms: list[tuple[object, object]]
) -> None:
    """A rational number times a sum (SymEngine keeps the product, SymPy's Mul distributes
    the number), each term made from its coefficient times the number: SymPy's Mul of the
    two converted, and the operations SymEngine counts."""
    total = se.Add(constant, *[c * t for c, t in terms])
    product = se.Mul(number, total)
    view = SympyView([x, y, z])
    if product.is_Mul:  # else SymEngine made something else of it (a lone term scaled)
        expected = sp.Mul(*[sp.sympify(a) for a in product.args])
        assert_identical(view(product), expected)
        assert view.operations(product) == operations(product)
    assert_identical(view(total), sp.sympify(total))  # the sum itself, converted after


def test_a_number_times_a_sum_with_other_coefficients_is_sympys_product() -> None:
    """A Float among the coefficients, or a Float number: SymPy's Mul, as before."""
    view = SympyView([x, y, z])
    for product in (
        se.Mul(-1, se.Add(se.RealDouble(0.5) * bx, by)),
        se.Mul(se.RealDouble(2.5), se.Add(bx, by)),
    ):
        expected = sp.Mul(*[sp.sympify(a) for a in product.args])
        assert_identical(view(product), expected)


def test_powers_of_symbols_and_function_values_are_sympys() -> None:
    """plain_power against sp.Pow for symbols of several assumptions, function values
    (those whose class changes its powers go through sp.Pow), and every kind of rational
    exponent."""
    f = sp.Function("f")
    bases = [sp.Symbol("a", **kind) for kind in ({}, {"positive": True}, {"negative": True})]
    bases += [sp.Symbol("n", integer=True), sp.Symbol("c", commutative=False), sp.Dummy("d")]
    bases += [sp.sin(x), sp.cos(x - y), f(x), sp.exp(x), sp.Abs(x), sp.sign(x), sp.sin(1)]
    exponents = [sp.Integer(n) for n in (-3, -1, 0, 1, 2, 5)]
    exponents += [sp.Rational(1, 2), sp.Rational(-3, 2), sp.Rational(2, 3)]
    for base in bases:
        for exponent in exponents:
            made, expected = plain_power(base, exponent), sp.Pow(base, exponent)
            assert_identical(made, expected)
            assert made.is_commutative == expected.is_commutative


def test_the_view_makes_powers_as_sympy_does() -> None:
    view = SympyView([x, y])
    for power in (bx**2, bx ** se.Rational(1, 2), se.sin(bx) ** -3, se.cos(bx - by) ** 2):
        assert_identical(view(power), sp.sympify(power))


PRODUCTS = [
    bx * by,
    se.sin(bx) * se.cos(by) ** 2 * bz,
    se.sin(by - bx) * bz,  # SymPy's sine of the flipped angle: a product with -1 in it
    (bx + by) * bz,
    (bx + by) * (by + bz) * bx,
    se.sqrt(bx + bz) * by,
]


@settings(deadline=None, max_examples=200)
@given(
    st.lists(
        st.tuples(
            st.booleans(), st.sampled_from([2, -1, se.Rational(1, 3)]), st.sampled_from(PRODUCTS)
        ),
        min_size=1,
        max_size=6,
    )
)
def test_products_met_alone_and_as_terms_convert_as_sympy_builds_them(
    uses: list[tuple[bool, object, object]],
) -> None:
    """A product converted alone and read as a term of sums with numbers, in any order with
    one view (each reuses the other's factors), is each time SymPy's expression of it, with
    the operations SymEngine counts."""
    view = SympyView([x, y, z])
    for alone, number, product in uses:
        expr = product if alone else se.Add(number * product, bz)
        expected = sp.Add(*[sp.sympify(a) for a in expr.args]) if not alone else None
        expected = sp.Mul(*[sp.sympify(a) for a in expr.args]) if alone else expected
        assert_identical(view(expr), expected)
        assert view.operations(expr) == operations(expr)
