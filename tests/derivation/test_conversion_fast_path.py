"""The fast paths of the backend conversion and of the tidying of a chain's equations give
exactly what the general routes give: SymPy's own Add and Mul (equal, the same arguments in
the same order, the same hash), Basic.compare's order, combine_trig, term.diff."""

from __future__ import annotations

from functools import cmp_to_key

import symengine as se
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.derivation.terms import combined_trig, euler_lagrange_terms
from lagrangian.derivation.trig import combine_trig
from lagrangian.size_limits import operations
from lagrangian.symbolic.canonical import (
    Builder,
    CanonicalOrder,
    Unorderable,
    sympy_product,
    sympy_sum,
)
from lagrangian.symbolic.sympy_view import SympyView

#: One Builder for every example: its Parts, remembered per object, are reused across them.
SHARED = Builder()

x, y, z, m = sp.symbols("x y z m")
d = sp.Dummy("d")
ATOMS = [x, y, z, m, d, sp.sin(x), sp.cos(x - y), sp.sin(y - x), sp.exp(z), sp.pi, sp.I]
NUMBERS = [sp.Integer(n) for n in (-3, -2, -1, 0, 1, 2, 5)]
NUMBERS += [sp.Rational(1, 2), sp.Rational(-3, 4), sp.Float(0.5), sp.sqrt(2)]


@st.composite
def factors(draw: st.DrawFn, depth: int = 2) -> sp.Expr:
    kind = draw(st.integers(0, 5 if depth else 2))
    if kind == 0:
        return draw(st.sampled_from(NUMBERS))
    if kind in (1, 2):
        return draw(st.sampled_from(ATOMS))
    if kind == 3:
        exponent = draw(st.sampled_from([-2, -1, 2, 3, sp.Rational(1, 2), m]))
        return sp.Pow(draw(factors(depth - 1)), exponent)
    parts = draw(st.lists(factors(depth - 1), min_size=1, max_size=4))
    return sp.Add(*parts) if kind == 4 else sp.Mul(*parts)


def assert_identical(fast: sp.Expr, slow: sp.Expr) -> None:
    assert fast == slow
    assert type(fast) is type(slow)
    assert fast.args == slow.args
    assert hash(fast) == hash(slow)
    assert sp.srepr(fast) == sp.srepr(slow)


@settings(deadline=None, max_examples=400)
@given(st.lists(factors(), max_size=6))
def test_sum_is_sympys_add(terms: list[sp.Expr]) -> None:
    assert_identical(sympy_sum(list(terms)), sp.Add(*terms))
    assert_identical(sympy_sum(list(terms), SHARED), sp.Add(*terms))


@settings(deadline=None, max_examples=400)
@given(st.lists(factors(), max_size=6))
def test_product_is_sympys_mul(terms: list[sp.Expr]) -> None:
    assert_identical(sympy_product(list(terms)), sp.Mul(*terms))
    assert_identical(sympy_product(list(terms), SHARED), sp.Mul(*terms))


def test_a_number_times_a_sum_is_distributed_as_sympy_does() -> None:
    for number in (sp.Integer(2), sp.Integer(-1), sp.Rational(1, 2)):
        assert_identical(sympy_product([number, x + y]), sp.Mul(number, x + y))
        assert_identical(sympy_product([x + y, number]), sp.Mul(x + y, number))
        assert_identical(sympy_product([number, x + y, z]), sp.Mul(number, x + y, z))
    assert_identical(sympy_sum([2 * (x + y), x]), sp.Add(2 * (x + y), x))
    assert_identical(sympy_product([x, x**2]), sp.Mul(x, x**2))  # bases combined
    assert_identical(sympy_sum([x, 2 * x, 3]), sp.Add(x, 2 * x, 3))  # terms combined


@settings(deadline=None, max_examples=300)
@given(st.lists(factors(), min_size=2, max_size=8))
def test_canonical_order_is_basic_compare(items: list[sp.Expr]) -> None:
    order = CanonicalOrder()
    try:
        keyed = sorted(items, key=order)
    except Unorderable:  # an expression without a key: the caller sorts by compare
        return
    compared = sorted(items, key=cmp_to_key(sp.Basic.compare))
    assert keyed == compared
    assert [type(e) for e in keyed] == [type(e) for e in compared]


def _general_route(view: SympyView, expr: se.Basic) -> sp.Expr:
    """SympyView's conversion through SymPy's own Add and Mul only."""
    if expr.is_Add:
        return sp.Add(*[_general_route(view, a) for a in expr.args])
    if expr.is_Mul:
        return sp.Mul(*[_general_route(view, a) for a in expr.args])
    if expr.is_Pow:
        return sp.Pow(*[_general_route(view, a) for a in expr.args])
    return view(expr)


def test_pendulum_entries_convert_as_sympy_builds_them() -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(12))
    terms = euler_lagrange_terms(eom.system)
    reference = SympyView(terms.view.by_name.values())
    for row in terms.mass:
        for entry in row:
            assert_identical(terms.view(entry), _general_route(reference, entry))
    for entry in terms.forcing:
        assert_identical(terms.view(entry), _general_route(reference, entry))


BACKEND_SYMBOLS = se.symbols("x y z m")
bx, by, bz, bm = BACKEND_SYMBOLS
BACKEND_FACTORS = [bx, by, bm, se.sin(bx), se.cos(bx - by), se.sin(by - bx), bx**2]
BACKEND_FACTORS += [bx + bz, (bx + by) ** 2, se.sqrt(bx + bm), bm ** se.Rational(-1, 2)]
COEFFICIENTS = [se.Integer(c) for c in (1, -1, 2, -3)] + [se.Rational(1, 2)]


@st.composite
def backend_sums(draw: st.DrawFn) -> list[object]:
    """Sums of products of a coefficient and factors (SymEngine keeps a sum's terms apart
    from their coefficients), and of some of the same terms with other coefficients."""
    terms = draw(
        st.lists(
            st.tuples(
                st.sampled_from(COEFFICIENTS),
                st.lists(st.sampled_from(BACKEND_FACTORS), min_size=1, max_size=4),
            ),
            min_size=1,
            max_size=6,
        )
    )
    products = [c * se.Mul(*f) for c, f in terms]
    constant = draw(st.sampled_from([se.Integer(0), se.Integer(3)]))
    rescaled = draw(st.sampled_from(COEFFICIENTS))
    return [se.Add(constant, *products), se.Add(*[rescaled * p for p in products])]


@settings(deadline=None, max_examples=300)
@given(backend_sums())
def test_sums_convert_as_sympy_builds_them_from_symengines_arguments(
    sums: list[object],
) -> None:
    symbols = [sp.Symbol(s.name) for s in BACKEND_SYMBOLS]
    view = SympyView(symbols)
    reference = SympyView(symbols)
    for total in sums:  # the second shares the first's terms, with other coefficients
        assert_identical(view(total), _general_route(reference, total))
        assert view.operations(total) == operations(total)


def test_chain_equations_tidy_as_combine_trig_does() -> None:
    system = lg.examples.n_link_pendulum(12)
    terms = euler_lagrange_terms(system)
    asm = terms.assembly
    lagrangian = terms.compress(terms.kinetic.kinetic_energy - se.expand(asm.potential))
    slopes = terms.gradient(lagrangian, [*asm.q, *asm.q_dot])
    whole = [lagrangian.diff(s) for s in [*asm.q, *asm.q_dot]]
    n = len(asm.q)
    for j in range(n):
        assert se.expand(slopes[j] - whole[j]) == 0
        assert se.expand(slopes[n + j] - whole[n + j]) == 0
        rate = terms.time_derivative(slopes[n + j])
        equation = rate - slopes[j] - asm.applied[j]
        assert combined_trig(equation) == combine_trig(equation)


def test_combined_trig_weighs_forms_when_there_are_products() -> None:
    a, b, k = se.symbols("a b k")
    cases = [
        k * se.sin(a) ** 2 + k * se.cos(a) ** 2,
        se.cos(a) * se.cos(b) + se.sin(a) * se.sin(b),
        k * se.sin(2 * a),
        k * (se.sin(a - b) + se.cos(a)),
        k / (1 + se.cos(a)),
    ]
    for expr in cases:
        assert combined_trig(expr) == combine_trig(expr)
