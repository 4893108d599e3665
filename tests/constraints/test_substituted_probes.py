"""The constraints' values at a point by one substitution of all of them: against each
expression substituted on its own, against the compiled functions (PointFunction) the
projection used before, and the compiled fallback where SymEngine cannot evaluate them; the
rows of the constraint Jacobian the generic point's projection evaluated, against the
forms' coefficients evaluated there."""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.dependence import _jacobian_at, dependence
from lagrangian.constraints.pfaffian import backend, pfaffian_form
from lagrangian.constraints.projection import _arguments, _Equations, project
from lagrangian.derivation.backend import to_backend
from lagrangian.symbolic.probe import PointFunction, values_at
from lagrangian.symbolic.symbols import velocity


def test_values_together_are_each_ones_own_substitution():
    """A 30-link Cartesian chain's Jacobian entries (many 0, many repeated) and b, with
    SymPy entries among them, over all its symbols: the mapping SymEngine copies once."""
    n = 30
    xs, ys = sp.symbols(f"x1:{n + 1}"), sp.symbols(f"y1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    coordinates = [c for pair in zip(xs, ys) for c in pair]
    entries = []
    for i in range(n):
        rod = (xs[i] - (xs[i - 1] if i else 0)) ** 2 + (ys[i] - (ys[i - 1] if i else 0)) ** 2
        form = pfaffian_form(lg.Holonomic(rod - lengths[i] ** 2), coordinates)
        entries += [*form.coefficients, form.time_coefficient]
    entries += [to_backend(e) for e in entries[:7]] + [3, sp.Rational(1, 3)]
    rng = random.Random(3)
    point = {s: rng.uniform(0.3, 1.3) for s in (*coordinates, *lengths)}
    one_by_one = [float(sp.sympify(e).xreplace(point)) for e in entries]
    assert values_at(entries, point) == pytest.approx(one_by_one, rel=1e-14, abs=1e-14)


def test_not_finite_or_not_real_values_are_none_and_unevaluable_ones_refused():
    x = sp.Symbol("x")
    assert values_at([x, 1 / x], {x: 0.0}) is None
    assert values_at([sp.sqrt(x)], {x: -1.0}) is None
    assert values_at([], {x: 1.0}).shape == (0,)
    with pytest.raises(ValueError, match="cannot evaluate"):
        values_at([se.Abs(to_backend(x)).diff(to_backend(x))], {x: 2.0})


def test_the_bicycles_contact_height_as_the_compiled_functions_give_it():
    """The generic point's residual and slopes by substitution against PointFunction."""
    system = lg.examples.whipple_bicycle()
    height = next(c for c in system.constraints if type(c).__name__ == "ContactHeight")
    equations = [backend(height.expression)]
    rng = random.Random(5)
    start = {s: rng.uniform(0.3, 1.3) for s in (*system.coordinates, *system.parameters)}
    symbols = _arguments(equations, start)
    unknowns = [to_backend(q) for q in system.coordinates]
    at = _Equations(equations, unknowns, symbols)
    residual = PointFunction(se.DenseMatrix(1, 1, equations), symbols)
    whole = se.DenseMatrix(1, 1, equations).jacobian(se.Matrix(unknowns))
    slopes = PointFunction(whole, symbols)
    for _ in range(4):
        point = {s: rng.uniform(-1, 1) for s in symbols}
        h, jacobian = at(point)
        assert h == pytest.approx(residual(point).ravel(), rel=1e-12, abs=1e-12)
        assert np.allclose(jacobian, slopes(point), rtol=1e-12, atol=1e-12)
    assert at.substituted is not None and at.compiled is None


def test_what_symengine_cannot_evaluate_is_projected_compiled():
    """|x| - 1 = 0: SymEngine leaves d|x|/dx unevaluated; the compiled functions take over."""
    x, y = sp.symbols("x y")
    found = project([sp.Abs(x) + y**2 - 1], [x, y], {x: 0.4, y: 0.2})
    assert found.satisfied
    assert abs(found.values[x]) + found.values[y] ** 2 == pytest.approx(1.0, abs=1e-8)
    at = _Equations([backend(sp.Abs(x) - 1)], [to_backend(x)], [x])
    h, jacobian = at({x: -2.0})
    assert at.substituted is None and at.compiled is not None
    assert h == pytest.approx([1.0]) and jacobian.ravel() == pytest.approx([-1.0])


@pytest.mark.parametrize("build", ["whipple_bicycle", "cartesian_chain"])
def test_the_projected_rows_of_the_jacobian_are_the_forms_values(build):
    """The rows of A the generic point's projection evaluated last, against every form's
    coefficients evaluated there."""
    if build == "cartesian_chain":
        xs, ys, lengths = sp.symbols("x1:7"), sp.symbols("y1:7"), sp.symbols("l1:7")
        rods = [
            lg.Holonomic(
                (xs[i] - (xs[i - 1] if i else 0)) ** 2
                + (ys[i] - (ys[i - 1] if i else 0)) ** 2
                - lengths[i] ** 2
            )
            for i in range(6)
        ]
        x1, y1 = xs[0], ys[0]
        system = lg.System(
            coordinates=[c for pair in zip(xs, ys) for c in pair],
            parameters=dict.fromkeys(lengths, 1.0),
            constraints=[*rods, lg.VelocityConstraint(y1 * velocity(x1) - x1 * velocity(y1))],
        )
    else:
        system = lg.examples.whipple_bicycle()
    found = dependence(system)
    forms = [pfaffian_form(c, system.coordinates) for c in system.constraints]
    a, b = _jacobian_at(forms, system.coordinates, found.point)
    assert np.allclose(found.jacobian, a, rtol=1e-13, atol=1e-13)
    assert np.array_equal(found.rates, b.ravel())
