"""The symbolic probe: zero tests and generic ranks against identities known by hand."""

import numpy as np
import pytest
import symengine as se
import sympy as sp

from lagrangian.symbolic import probe
from lagrangian.symbolic.probe import (
    PointFunction,
    all_zero,
    depends_on,
    evaluate,
    generic_rank,
    is_zero,
    numeric_rank,
)

x, y, z = sp.symbols("x y z")


def test_identities_are_zero():
    assert is_zero(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1)
    assert is_zero(sp.exp(x) * sp.exp(-x) - 1)
    assert is_zero(sp.cosh(x) ** 2 - sp.sinh(x) ** 2 - 1)
    # a large expression that cancels: the probes decide without simplify
    big = sp.expand((x + y + z) ** 8) - sp.expand((x + y + z) ** 4) ** 2
    assert is_zero(big)


def test_float_zero_is_zero():
    # sp.Float(0.0) == 0 is False in SymPy; a derivation that multiplies by 0.0 must still read 0
    assert is_zero(sp.Float(0.0))
    assert is_zero(sp.Float(0.0) * x)
    assert all_zero([0, sp.Float(0.0), sp.sin(x) - sp.sin(x)])


def test_non_zero_is_not_zero():
    assert not is_zero(x - 1)
    assert not is_zero(sp.Float(1e-20))  # a constant is decided exactly, not by a tolerance
    assert not is_zero(sp.sin(x) ** 2 - sp.cos(x) ** 2)
    # differs from zero only by 1e-12 of its size: still found
    assert not is_zero(x * (1 + sp.Rational(1, 10**12)) - x)
    assert not all_zero([0, x])


def test_symengine_input_is_decided_like_sympy_input():
    # the same answers for the same expressions, whichever library made them
    cases = [
        sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1,
        10**12 * (sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1),  # cancels under a large factor
        sp.expand((x + y + z) ** 8) - sp.expand((x + y + z) ** 4) ** 2,
        x - 1,
        sp.sin(x) ** 2 - sp.cos(x) ** 2,
        x * (1 + sp.Rational(1, 10**12)) - x,
        sp.sqrt(1 - (x * y) ** 2) - sp.sqrt((1 - x * y) * (1 + x * y)),
        sp.sqrt(x - 2),  # imaginary at every probe point: not decided by the first one
    ]
    for expr in cases:
        assert is_zero(se.sympify(expr)) == is_zero(expr), expr


def test_symengine_input_found_non_zero_without_sympy(monkeypatch: pytest.MonkeyPatch):
    # a value at the first probe point settles it: the expression is never converted
    def refuse(value):
        raise AssertionError(f"converted to SymPy: {value}")

    monkeypatch.setattr(probe, "sympy_object", refuse)
    a, b = se.symbols("a b")
    height = se.expand((a + b) ** 6 * se.sin(a) - (a + b) ** 6 * se.cos(b) ** 2)
    assert not is_zero(height)
    assert not is_zero(a * (1 + se.Rational(1, 10**12)) - a)
    with pytest.raises(AssertionError, match="converted"):  # a zero is confirmed as before
        is_zero(se.sin(a) ** 2 + se.cos(a) ** 2 - 1)


def test_generic_rank():
    assert generic_rank(sp.Matrix([[x, y], [2 * x, 2 * y]])) == 1
    assert generic_rank(sp.Matrix([[sp.cos(x), -sp.sin(x)], [sp.sin(x), sp.cos(x)]])) == 2
    assert generic_rank(sp.zeros(2, 3)) == 0
    assert generic_rank(sp.Matrix(0, 3, [])) == 0
    # the Jacobian of a closed four-bar loop has rank 2 in 3 coordinates
    q1, q2, q3 = sp.symbols("q1 q2 q3")
    loop = sp.Matrix(
        [
            sp.cos(q1) + sp.cos(q2) + sp.cos(q3) - 1,
            sp.sin(q1) + sp.sin(q2) + sp.sin(q3),
        ]
    )
    assert generic_rank(loop.jacobian([q1, q2, q3])) == 2
    # a point that makes it singular, given by the caller
    singular = sp.Matrix([[x, y], [y, x]])
    assert generic_rank(singular, {x: 0.5, y: 0.5}) == 1


def test_numeric_rank_tolerance():
    a = np.array([[1.0, 0.0], [0.0, 1e-15]])
    assert numeric_rank(a) == 1
    assert numeric_rank(np.eye(3)) == 3
    assert numeric_rank(np.zeros((0, 2))) == 0


def test_evaluate_and_depends_on():
    assert abs(evaluate(sp.sqrt(x), {x: 4.0}) - 2.0) < 1e-25
    assert evaluate(sp.sqrt(x), {x: -1.0}) is None  # not real
    assert evaluate(1 / x, {x: 0.0}) is None  # not finite
    assert depends_on(x * y, [y]) and not depends_on(x * y, [z])


def test_point_function():
    f = PointFunction(sp.Matrix([[x * y, sp.log(x)]]), [x, y])
    assert np.allclose(f({x: 2.0, y: 3.0}), [[6.0, np.log(2.0)]])
    assert f({x: -1.0, y: 1.0}) is None
