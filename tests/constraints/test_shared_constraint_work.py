"""The work the constraints' forms share or leave out, against the work done in full: the
constraint expressions converted to SymEngine with one memo for consecutive constraints
against each converted on its own; a velocity constraint at rest with its speed terms left
out against the whole expression substituted; the projection compiled over the symbols the
equations involve against the constraints' values at the point it finds; a large gamma
stopped at the size limit as it is converted, with the count that counting it first gives."""

from __future__ import annotations

import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.pfaffian import (
    SHARED_BY,
    _at_rest,
    _Shared,
    _shared_subexpressions,
    backend,
    fast_state,
    pfaffian_form,
)
from lagrangian.constraints.projection import project
from lagrangian.derivation.backend import to_backend
from lagrangian.errors import SizeLimitError
from lagrangian.size_limits import operations, size_limit
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
    shared = _Shared(dict)
    first = shared.next()
    assert all(shared.next() is first for _ in range(SHARED_BY - 1))
    assert shared.next() is not first
    # backend converts with the memo shared at the time
    u = sp.Symbol("u_shared_memo")
    backend(sp.sin(u) + u**2)
    assert sp.sin(u) in _shared_subexpressions().value


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


def test_a_gamma_left_as_built_is_stopped_at_the_size_limit_as_it_is_converted():
    x, y, th, ph, r = sp.symbols("x y theta phi r")
    q = (x, y, th, ph)
    xd, thd, phd = velocity(x), velocity(th), velocity(ph)
    # partial derivatives past TIDY_OPS: gamma is left as built
    wobble = (1 + sp.sin(th) * sp.cos(ph) + sp.cos(th + ph) + sp.sin(ph) ** 2) ** 4
    slip = sp.expand((xd - r * sp.cos(th) * thd + r * sp.sin(ph) * phd) * wobble)
    system = lg.System(
        coordinates=q,
        parameters=[r],
        particles=[lg.Particle("p", 1, (x, y))],
        constraints=[lg.VelocityConstraint(slip)],
    )
    lg.derive(system)
    with size_limit(2000), pytest.raises(SizeLimitError) as stopped:
        lg.constrained_equations(system)
    message = str(stopped.value)
    assert "the acceleration term gamma of constraints[0] has " in message
    assert "more than the size limit of 2,000" in message
    counted = int(message.split(" has ")[1].split(" operations")[0].replace(",", ""))
    gamma = lg.constrained_equations(system).gamma  # nothing kept of the refused attempt
    assert counted > 2000 and abs(counted - operations(gamma[0])) <= 0.01 * counted


def test_the_projection_takes_a_dummy_by_its_name_as_the_conversion_does():
    x, d = sp.Symbol("x"), sp.Dummy("d")
    found = project([x - d], [x], {x: 0.5, d: 0.25})
    assert found.satisfied and abs(found.values[x] - 0.25) < 1e-12
