"""The constraint Jacobian and rates at the generic point of :func:`dependence`, evaluated in
SymEngine, against the constraints differentiated in SymPy and evaluated there; redundancy of
constraints with |x| (whose derivative SymEngine leaves unevaluated); a Jacobian with no real
value at any configuration refused."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.dependence import dependence
from lagrangian.errors import ConstraintError
from lagrangian.model import t, velocity

x, y, phi, r = sp.symbols("x y phi r")
Q = [x, y, phi]


def test_the_jacobian_and_rates_are_the_constraints_derivatives_at_the_point() -> None:
    ring = x**2 + y**2 - r**2 * (1 + t**2) + sp.sqrt(1 + x**2 * sp.sin(phi) ** 2)
    knife = velocity(x) * sp.sin(phi) - velocity(y) * sp.cos(phi) + t * sp.sqrt(1 + x**2)
    system = lg.System(
        coordinates=Q,
        parameters={r: 1.3},
        constraints=[lg.Holonomic(ring), lg.VelocityConstraint(knife)],
    )
    found = dependence(system)
    exact = {s: sp.Float(v, 30) for s, v in found.point.items()}
    at_rest = {velocity(q): 0 for q in Q}
    jacobian = [[ring.diff(q) for q in Q], [knife.diff(velocity(q)) for q in Q]]
    rates = [ring.diff(t), knife.xreplace(at_rest)]
    expected = np.array(sp.Matrix(jacobian).xreplace(exact).evalf(30).tolist(), dtype=float)
    np.testing.assert_allclose(found.jacobian, expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(
        found.rates, [float(sp.N(b.xreplace(exact), 30)) for b in rates], rtol=1e-12
    )
    assert abs(float(sp.N(ring.xreplace(exact)))) < 1e-8  # the point is on the constraint


def test_a_constraint_with_an_absolute_value_twice_is_redundant() -> None:
    system = lg.System(
        coordinates=Q,
        constraints=[lg.Holonomic(sp.Abs(x) + y - 2), lg.Holonomic(2 * sp.Abs(x) + 2 * y - 4)],
    )
    assert dependence(system).redundant == (1,)


def test_a_jacobian_without_a_real_value_is_refused() -> None:
    system = lg.System(
        coordinates=Q,
        constraints=[lg.VelocityConstraint(velocity(x) * sp.sqrt(-1 - y**2) + velocity(y))],
    )
    with pytest.raises(ConstraintError, match="not defined at a generic configuration"):
        dependence(system)


def test_values_at_substitutes_all_entries_as_each_alone() -> None:
    """The values of many entries, substituted as one matrix, are each entry's own value;
    an entry not real at the point gives None, and no entries give an empty array."""
    import symengine as se

    from lagrangian.symbolic.probe import values_at

    a, b = sp.symbols("a b")
    entries = [se.Integer(0), se.sympify(a * b), se.sin(se.Symbol("a")) + 3, se.Integer(2)]
    point = {a: 0.7, b: -1.3}
    expected = [0.0, 0.7 * -1.3, float(np.sin(0.7)) + 3, 2.0]
    np.testing.assert_allclose(values_at(entries, point), expected, rtol=1e-15)
    assert values_at([se.sqrt(se.Symbol("b"))], point) is None
    assert values_at([], point).shape == (0,)
