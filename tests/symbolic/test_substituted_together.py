"""One substitution for many expressions (``probe.substituted``): each entry comes out as its
own substitution would give it, in order, whatever the entries share; and the probes built on
it (a matrix's values at a point, a compiled function of a point) agree with SymPy."""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

from lagrangian.symbolic.probe import PointFunction, generic_rank, substituted, together

x, y, z = sp.symbols("x y z")


def _entries() -> list[sp.Expr]:
    shared = sp.sqrt(1 + x**2 * sp.sin(y) ** 2)  # a part most entries hold, as a wheel's tilt
    rng = random.Random(7)
    pool = [x, y, z, sp.cos(x - y), shared, 1 / shared, sp.Integer(3), sp.Rational(-1, 2)]
    out = [sp.Integer(0), x, x]  # a zero and a repeated entry keep their places
    for _ in range(40):
        out.append(sp.Add(*[sp.Mul(*rng.sample(pool, 3)) for _ in range(rng.randint(1, 4))]))
    return out


def test_each_entry_comes_out_as_its_own_substitution_in_order() -> None:
    entries = [se.sympify(e) for e in _entries()]
    for mapping in (
        {se.Symbol("x"): se.RealDouble(0.7), se.Symbol("y"): se.RealDouble(-1.1)},
        {se.Symbol("x"): se.Symbol("_arg0_"), se.Symbol("z"): se.Symbol("_arg2_")},
    ):
        assert list(substituted(entries, mapping)) == [e.xreplace(mapping) for e in entries]
    assert substituted([], {se.Symbol("x"): se.Integer(1)}) == ()
    assert together(entries).free_symbols == {se.Symbol(n) for n in "xyz"}


def test_a_function_of_a_point_agrees_with_sympy() -> None:
    entries = _entries()
    point = {x: 0.41, y: -0.83, z: 1.27}
    got = PointFunction(sp.Matrix(len(entries), 1, entries), [z, x, y])(point)
    expected = [complex(sp.N(e.xreplace(point))).real for e in entries]
    np.testing.assert_allclose(got.ravel(), expected, rtol=1e-13, atol=1e-14)
    assert PointFunction(sp.Matrix([[1 / x]]), [x])({x: 0.0}) is None


@pytest.mark.parametrize("kept", [1, 2, 3])
def test_a_generic_rank_counts_the_independent_rows(kept: int) -> None:
    rows = [[x, sp.sin(y), z**2], [sp.cos(x), y, 1], [x * y, z, sp.sqrt(1 + x**2)]][:kept]
    rows += [[2 * a - b for a, b in zip(rows[0], rows[-1])]]  # a combination of the others
    assert generic_rank(sp.Matrix(rows)) == kept
