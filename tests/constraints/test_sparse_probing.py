"""The constraints probed and converted from the symbols each involves: the projection's
Jacobian against SymEngine's whole Jacobian at random points, the redundancy check of many
independent rows against the row-by-row rank of the same matrix, the Pfaffian forms of a
Cartesian chain against SymPy's own derivatives, and a rolling contact's forms and gamma
converted by the conversion that made the contact's constraints, against fresh conversions;
the conversion shared by the constraints on the same coordinates, unless a name clashes."""

from __future__ import annotations

import random
from dataclasses import replace

import numpy as np
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.dependence import dependence, generic_point
from lagrangian.constraints.pfaffian import SHARED_BY, acceleration_terms, pfaffian_form
from lagrangian.constraints.projection import _Equations
from lagrangian.derivation.backend import SympyView, to_backend
from lagrangian.model.contact import MADE
from lagrangian.symbolic.caches import forget_all
from lagrangian.symbolic.probe import numeric_rank
from lagrangian.symbolic.symbols import t, velocity


def _chain(n: int, extra: list[sp.Expr] = ()) -> lg.System:
    """n bobs in the plane on rods (x_i - x_(i-1))^2 + (y_i - y_(i-1))^2 = l_i^2."""
    xs, ys = sp.symbols(f"x1:{n + 1}"), sp.symbols(f"y1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    rods = [
        lg.Holonomic(
            (xs[i] - (xs[i - 1] if i else 0)) ** 2
            + (ys[i] - (ys[i - 1] if i else 0)) ** 2
            - lengths[i] ** 2
        )
        for i in range(n)
    ]
    return lg.System(
        coordinates=[c for pair in zip(xs, ys) for c in pair],
        parameters={s: 1.0 + 0.1 * k for k, s in enumerate(lengths)},
        constraints=[*rods, *(lg.Holonomic(e) for e in extra)],
    )


def test_the_projections_residual_and_jacobian_are_the_whole_ones():
    system = _chain(6)
    equations = [to_backend(c.expression) for c in system.constraints]
    unknowns = [to_backend(q) for q in system.coordinates]
    symbols = sorted({*system.coordinates, *system.parameters}, key=str)
    at = _Equations(equations, unknowns, symbols)
    whole = se.DenseMatrix(len(equations), 1, equations).jacobian(se.Matrix(unknowns))
    rng = random.Random(7)
    for _ in range(3):
        point = {s: rng.uniform(-2, 2) for s in symbols}
        values = {to_backend(s): v for s, v in point.items()}
        expected = np.array([[float(e.subs(values)) for e in row] for row in whole.tolist()])
        h, jacobian = at(point)
        assert np.allclose(jacobian, expected, rtol=1e-14, atol=1e-14)
        assert np.allclose(h, [float(e.subs(values)) for e in equations], rtol=1e-14)


def test_independent_rows_decided_at_once_as_row_by_row():
    system = _chain(8)
    found = dependence(system)
    assert found.redundant == ()
    rows = list(found.rows)
    assert [numeric_rank(found.jacobian[rows[: k + 1]]) for k in range(len(rows))] == list(
        range(1, len(rows) + 1)
    )


def test_a_redundant_rod_is_still_found():
    x1, y1 = sp.symbols("x1 y1")
    system = _chain(3, extra=[2 * (x1**2 + y1**2 - sp.Symbol("l1") ** 2)])
    assert dependence(system).redundant == (3,)


def test_the_chains_forms_are_sympys_derivatives():
    system = _chain(4)
    q = system.coordinates
    for constraint in system.constraints:
        h = constraint.expression
        form = pfaffian_form(constraint, q)
        assert form.coefficients == tuple(sp.diff(h, s) for s in q)
        rate = sum(sp.diff(h, s) * velocity(s) for s in q)
        assert sp.expand(form.velocity_expression - rate) == 0
    point = generic_point(system)
    assert all(abs(float(c.expression.subs(point))) < 1e-8 for c in system.constraints)


def test_a_rolling_contacts_forms_go_on_with_the_conversion_that_made_it():
    forget_all()  # the records below are the new System's, whatever an earlier test emptied
    system = lg.examples.rolling_coin.__wrapped__()  # built anew, not the remembered System
    q = tuple(system.coordinates)
    forms = [pfaffian_form(c, q) for c in system.constraints]
    made = [MADE.peek(c) for c in system.constraints]
    assert all(m is not None for m in made)
    assert [f.view for f in forms] == [m.conversion for m in made if m is not None]
    gamma = acceleration_terms(forms, q)
    # the same gamma from a conversion that converted nothing before
    names = {t, *q, *(velocity(s) for s in q), *system.parameters}
    fresh = acceleration_terms([replace(f, view=SympyView(names)) for f in forms], q)
    assert [sp.srepr(g) for g in gamma] == [sp.srepr(g) for g in fresh]


def test_constraints_on_the_same_coordinates_share_one_conversion():
    """The forms of a chain's rods come from one conversion, each with the user's symbols;
    a constraint whose symbol takes a name another symbol has there gets its own, with its
    own symbol (kappa positive and kappa without assumptions are two symbols of one name);
    after SHARED_BY constraints the next ones share a new conversion."""
    forget_all()  # the count of shared constraints starts here, whatever ran before
    u, w = sp.symbols("u1:4"), sp.symbols("w1:4")  # coordinates of this test alone
    q = (*u, *w)
    rods = [(u[i] - u[i - 1]) ** 2 + (w[i] - w[i - 1]) ** 2 - 1 for i in (1, 2)]
    forms = [pfaffian_form(lg.Holonomic(h), q) for h in rods]
    assert forms[0].view is forms[1].view
    for h, form in zip(rods, forms):
        assert form.coefficients == tuple(sp.diff(h, s) for s in q)
    plain, positive = sp.Symbol("kappa"), sp.Symbol("kappa", positive=True)
    first = pfaffian_form(lg.Holonomic(u[0] - plain * w[0]), q)
    second = pfaffian_form(lg.Holonomic(u[0] + positive * w[0]), q)
    assert first.view is forms[0].view and second.view is not first.view
    assert first.coefficients[3] == -plain and second.coefficients[3] == positive
    assert first.coefficients[3].free_symbols == {plain}
    assert second.coefficients[3].free_symbols == {positive}
    # four constraints so far: the next SHARED_BY - 4 share the first conversion
    more = [pfaffian_form(lg.Holonomic(u[0] - k * w[1]), q) for k in range(SHARED_BY - 3)]
    assert all(f.view is first.view for f in more[:-1]) and more[-1].view is not first.view
