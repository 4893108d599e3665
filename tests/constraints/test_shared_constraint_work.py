"""The work the constraints' forms share or leave out, against the work done in full: the
constraint expressions converted to SymEngine with one memo for consecutive constraints
against each converted on its own; a velocity constraint at rest with its speed terms left
out against the whole expression substituted; the projection compiled over the symbols the
equations involve against the constraints' values at the point it finds."""

from __future__ import annotations

import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.pfaffian import (
    SHARED_BY,
    _at_rest,
    _shared_subexpressions,
    backend,
    fast_state,
    pfaffian_form,
)
from lagrangian.constraints.projection import project
from lagrangian.derivation.backend import to_backend
from lagrangian.symbolic.caches import forget_all
from lagrangian.symbolic.native import to_symengine_sharing
from lagrangian.symbolic.symbols import t, velocity


def test_constraints_converted_with_a_shared_memo_are_those_converted_alone():
    system = lg.examples.BENCHMARKS["whipple_bicycle"]()
    for constraint in system.constraints:
        alone = to_symengine_sharing(constraint.expression, {})
        shared = backend(constraint.expression)
        assert shared == alone
        assert str(shared) == str(alone)


def test_a_new_shared_memo_after_shared_by_constraints():
    forget_all()  # the count of constraints sharing the memo starts here
    u = sp.symbols(f"u0:{SHARED_BY + 1}")
    first = _shared_subexpressions().value
    for k in range(SHARED_BY):
        backend(sp.sin(u[k]) + u[k] ** 2)
    assert _shared_subexpressions().value is first and sp.sin(u[0]) in first
    backend(sp.sin(u[SHARED_BY]))
    assert _shared_subexpressions().value is not first


def test_at_rest_leaves_out_the_terms_with_a_speed_factor():
    x, y, th, r, w = sp.symbols("x y theta r w")
    q = (x, y, th)
    xd, yd, thd = (velocity(s) for s in q)
    cases = [
        xd - r * sp.cos(th) * thd,  # every term moves
        xd * sp.sin(th) - yd * sp.cos(th) + r * w * sp.cos(w * t),  # rheonomic: b != 0
        xd**2 + x * yd + sp.sin(t) * th,  # a square of a speed goes through substitution
        sp.sqrt(1 + x**2) * (xd + yd),  # one product, the speeds inside a sum
        thd,  # a speed alone
    ]
    speeds = list(fast_state(q).speeds)
    for case in cases:
        c = to_backend(case)
        expected = c.xreplace(dict.fromkeys(speeds, se.Integer(0)))
        assert _at_rest(c, speeds) == expected
        assert sp.srepr(sp.sympify(_at_rest(c, speeds))) == sp.srepr(sp.sympify(expected))


def test_a_velocity_constraints_time_coefficient_is_c_at_rest():
    x, y, th, w = sp.symbols("x y theta w")
    q = (x, y, th)
    xd, yd = velocity(x), velocity(y)
    c = xd * sp.sin(th) - yd * sp.cos(th) + w * sp.cos(w * t) * x
    form = pfaffian_form(lg.VelocityConstraint(c), q)
    assert sp.expand(form.time_coefficient - c.subs({xd: 0, yd: 0})) == 0
    assert form.coefficients[:2] == (sp.sin(th), -sp.cos(th))


def test_the_projection_compiles_the_symbols_its_equations_involve():
    x, y, l, unused = sp.symbols("x y l unused")
    start = {x: 2.0, y: 0.5, l: 1.5, unused: 7.0, t: 0.0}
    found = project([x**2 + y**2 - l**2, x - 2 * y], [x, y], start)
    assert found.satisfied
    values = found.values
    assert abs(values[x] ** 2 + values[y] ** 2 - 1.5**2) < 1e-8
    assert abs(values[x] - 2 * values[y]) < 1e-8
    assert values[unused] == 7.0 and values[l] == 1.5
