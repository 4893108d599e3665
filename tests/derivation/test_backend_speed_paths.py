"""The backend conversion's shortcuts build what SymPy's own constructors build: a sine or a
cosine made without Function.__new__ (equal, the same arguments, hash, srepr and nargs),
sums and products with nested sums, products and numbers to flatten (sp.Add, sp.Mul), and
the cycle collector is left as it was found."""

from __future__ import annotations

import gc

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation.backend import to_backend
from lagrangian.symbolic.canonical import Builder, sympy_product, sympy_sum
from lagrangian.symbolic.sympy_view import (
    SympyView,
    unevaluated_trig,
)

#: One Builder for every example: its Parts, remembered per object, are reused across them.
SHARED = Builder()

x, y, z = sp.symbols("x y z")
a = sp.Symbol("a", positive=True)
d = sp.Dummy("d")
ATOMS = [x, y, z, a, d, sp.pi, sp.sin(x), sp.cos(x - y)]
NUMBERS = [sp.Integer(n) for n in (-2, -1, 0, 1, 3)] + [sp.Rational(-1, 2), sp.Rational(2, 3)]


@st.composite
def expressions(draw: st.DrawFn, depth: int = 2) -> sp.Expr:
    kind = draw(st.integers(0, 4 if depth else 1))
    if kind == 0:
        return draw(st.sampled_from(NUMBERS))
    if kind == 1:
        return draw(st.sampled_from(ATOMS))
    if kind == 2:
        return sp.Pow(
            draw(expressions(depth - 1)), draw(st.sampled_from([-1, 2, sp.Rational(1, 2)]))
        )
    parts = draw(st.lists(expressions(depth - 1), min_size=1, max_size=4))
    return sp.Add(*parts) if kind == 3 else sp.Mul(*parts)


def assert_identical(fast: sp.Basic, slow: sp.Basic) -> None:
    assert fast == slow
    assert type(fast) is type(slow)
    assert fast.args == slow.args
    assert hash(fast) == hash(slow)
    assert sp.srepr(fast) == sp.srepr(slow)


@settings(deadline=None, max_examples=300)
@given(st.sampled_from([sp.sin, sp.cos]), expressions())
def test_unevaluated_trig_is_sympys_unevaluated_value(function: type, argument: sp.Expr) -> None:
    fast = unevaluated_trig(function, argument)
    slow = function(argument, evaluate=False)
    assert_identical(fast, slow)
    assert fast.nargs == slow.nargs == sp.FiniteSet(1)
    assert vars(fast) == vars(slow)  # nargs is the only attribute either has
    assert fast.func is slow.func and fast.func(*fast.args) == slow.func(*slow.args)
    assert fast.is_commutative == slow.is_commutative
    assert fast.diff(x) == slow.diff(x)


@settings(deadline=None, max_examples=400)
@given(st.lists(expressions(), max_size=6))
def test_sums_and_products_of_nested_terms_are_sympys(terms: list[sp.Expr]) -> None:
    assert_identical(sympy_sum(list(terms)), sp.Add(*terms))
    assert_identical(sympy_sum(list(terms), SHARED), sp.Add(*terms))
    assert_identical(sympy_product(list(terms)), sp.Mul(*terms))
    assert_identical(sympy_product(list(terms), SHARED), sp.Mul(*terms))


def test_a_product_or_a_sum_met_late_is_flattened() -> None:
    order = Builder()
    minus_sine = -sp.sin(x - y)  # a product: -1 times the sine
    for factors in (
        [sp.Integer(2), x, minus_sine, y**2],
        [x, y, sp.Rational(1, 2) * z, sp.Integer(3)],
        [x, sp.Integer(-1), minus_sine],
    ):
        assert_identical(sympy_product(factors, order), sp.Mul(*factors))
    for terms in ([sp.Integer(1), x, y + z], [x, sp.Rational(1, 3), 2 * y + sp.Integer(2)]):
        assert_identical(sympy_sum(terms, order), sp.Add(*terms))


def test_pendulum_angles_convert_to_sympys_own_values() -> None:
    theta = sp.symbols("theta1:5")
    view = SympyView(theta)
    for j, first in enumerate(theta):
        for second in theta[j + 1 :]:
            for angle in (first - second, second - first):
                for function in (sp.sin, sp.cos):
                    assert_identical(view(to_backend(function(angle))), function(angle))


@pytest.mark.parametrize("enabled", [True, False])
def test_conversion_leaves_the_cycle_collector_as_it_was(enabled: bool) -> None:
    was = gc.isenabled()
    try:
        gc.enable() if enabled else gc.disable()
        view = SympyView([x, y])
        assert view.vector([to_backend(x * sp.sin(x - y))])[0] == x * sp.sin(x - y)
        assert gc.isenabled() is enabled
        with pytest.raises(AttributeError):
            view.vector([object()])  # not an expression: the conversion fails midway
        assert gc.isenabled() is enabled
    finally:
        gc.enable() if was else gc.disable()


def test_unflattened_sums_and_products_go_to_sympy() -> None:
    nested_sum = sp.Add(x, sp.Add(y, z, evaluate=False), evaluate=False)
    nested_product = sp.Mul(x, sp.Mul(y, z, evaluate=False), evaluate=False)
    for order in (None, Builder()):
        assert_identical(sympy_sum([nested_sum, sp.Integer(1)], order), sp.Add(nested_sum, 1))
        assert_identical(sympy_product([nested_product, a], order), sp.Mul(nested_product, a))


def test_expressions_of_the_same_backend_hash_convert_each_to_itself() -> None:
    """The view remembers a conversion by the SymEngine hash: two different expressions of
    the same hash (a clash, set up here by moving one's entry under the other's hash) are
    each converted to themselves, alone and as arguments."""
    view = SympyView([x, y])
    view(to_backend(y))
    view._memo[hash(to_backend(x))] = view._memo.pop(hash(to_backend(y)))
    for expr in (x, y, x * y + 2 * x, x, 3 * x * y + x):
        assert_identical(view(to_backend(expr)), expr)
