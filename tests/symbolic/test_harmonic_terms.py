"""The predicted harmonics of powers of sums of sines and cosines, against SymPy's own
product-to-sum expansion (``fu.TR8``) counted term by term."""

import pytest
import sympy as sp
from sympy.simplify.fu import TR8

from lagrangian.symbolic.expressions import harmonic_terms

a, b, c, d = sp.symbols("a b c d")


@pytest.mark.parametrize("n", [2, 3, 4, 6])
@pytest.mark.parametrize(
    "base", [sp.sin(a) + sp.cos(b), sp.sin(a) + sp.sin(b) + sp.cos(c)], ids=["two", "three"]
)
def test_the_prediction_is_within_a_third_of_the_expanded_count(base, n):
    counted = len(sp.Add.make_args(sp.expand(TR8(sp.expand(base**n)))))
    predicted = harmonic_terms(base**n)
    assert counted / 1.5 <= predicted <= 1.5 * counted, (counted, predicted)


def test_a_power_of_forty_predicts_far_more_than_its_monomials():
    power = (sp.sin(a) + sp.sin(b) + sp.sin(c) + sp.cos(d)) ** 40
    assert harmonic_terms(power, 10**7) > 500_000  # 12,341 monomials


def test_a_polynomial_counts_its_monomials():
    x, y = sp.symbols("x y")
    assert harmonic_terms((x + y + 1) ** 2) == 6
