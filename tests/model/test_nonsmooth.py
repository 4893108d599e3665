"""Almost-everywhere derivatives of Abs, sign and Heaviside, against the rules by hand."""

import sympy as sp

from lagrangian.symbolic.nonsmooth import derivative, piecewise_smooth

x, y, t = sp.symbols("x y t")


def test_derivative_rules():
    assert derivative(sp.Abs(x), x) == sp.sign(x)
    assert derivative(3 * sp.Abs(x**2 - y), x) == 6 * x * sp.sign(x**2 - y)
    assert derivative(sp.sign(x) * x, x) == sp.sign(x)
    assert derivative(sp.Heaviside(t - y) * t**2, t) == 2 * t * sp.Heaviside(t - y)
    assert derivative(sp.sin(x), x) == sp.cos(x)  # smooth: SymPy's own
    # the result keeps SymPy's classes: it compares with what a user writes
    assert type(derivative(sp.Abs(x) * y, y)) is sp.Abs


def test_leftovers_of_the_complex_rules_are_resolved():
    assert piecewise_smooth(sp.Abs(x).diff(x)) == sp.sign(x)  # re/im form
    assert piecewise_smooth(sp.Derivative(sp.Abs(x * y), x)) == y * sp.sign(x * y)
    assert piecewise_smooth(sp.DiracDelta(x) * y + x) == x
    xi = sp.Symbol("xi")
    subs = y * sp.Subs(sp.Derivative(sp.sign(xi), xi), xi, x * y)
    assert piecewise_smooth(subs) == 0
    assert piecewise_smooth(x + 1) == x + 1
