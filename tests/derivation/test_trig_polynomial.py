"""Trigonometric polynomials grouped by monomial (lagrangian.derivation.trig_polynomial): the
identities a rotation obeys cancel, long expressions keep their values, and the three routes
to M and C q_dot of 3-D bodies (entry by entry, grouped polynomials with the Christoffel
symbols, nested with Kane's projection) agree at random states."""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.derivation import kinetic
from lagrangian.derivation.assemble import assemble
from lagrangian.derivation.trig import combine_and_collect, combine_trig
from lagrangian.derivation.trig_polynomial import Sum, TrigAlgebra, _spliced, expanded_terms
from lagrangian.model import rotation
from lagrangian.model.rotation import body_angular_velocity, rotation_sequence
from lagrangian.symbolic.symbols import velocity

a, b, c, m, k = se.symbols("a b c m k")


def _turn(axis: int, angle: se.Expr) -> se.DenseMatrix:
    cos, sin = se.cos(angle), se.sin(angle)
    rows = {
        0: [[1, 0, 0], [0, cos, -sin], [0, sin, cos]],
        1: [[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]],
        2: [[cos, -sin, 0], [sin, cos, 0], [0, 0, 1]],
    }[axis]
    return se.DenseMatrix(rows)


def _value(expr: se.Expr, values: dict) -> float:
    return float(expr.subs(values))


def test_the_transpose_of_a_rotation_product_is_its_inverse_monomial_by_monomial() -> None:
    """R = Rz(a) Rx(b) Ry(c): every entry of R^T R reduces to 0 or 1."""
    R = _turn(2, a) * _turn(0, b) * _turn(1, c)
    product = R.T * R
    algebra = TrigAlgebra([a, b, c])
    for i in range(3):
        for j in range(3):
            reduced = algebra.expression(algebra.finish(algebra.convert(product[i, j])))
            assert reduced == (1 if i == j else 0)


def _long_polynomial(seed: int) -> se.Expr:
    """A trigonometric polynomial of a few hundred terms in three angles and two parameters."""
    rng = random.Random(seed)
    atoms = [se.sin(a), se.cos(a), se.sin(b), se.cos(b), se.sin(c), se.cos(c), m, k]
    terms = []
    for _ in range(600):
        factors = [rng.choice(atoms) for _ in range(rng.randint(1, 5))]
        terms.append(rng.randint(-3, 3) * se.Mul(*factors))
    return se.Add(*terms)


@pytest.mark.parametrize("seed", [1, 2])
def test_a_long_expression_keeps_its_value(seed: int) -> None:
    expr = _long_polynomial(seed)
    rng = random.Random(seed)
    for reduced in (combine_trig(expr), combine_and_collect(expr, {a, b, c})):
        for _ in range(3):
            values = {s: rng.uniform(-2, 2) for s in (a, b, c, m, k)}
            assert _value(reduced, values) == pytest.approx(_value(expr, values), rel=1e-9)


def test_one_record_of_the_factors_for_many_collections_changes_none_of_them() -> None:
    """combine_and_collect of long polynomials, short ones and sums with nothing to combine,
    all with one record of how their factors sort (the equations of one system share it),
    gives each what it gives alone, structure and all."""
    state = {a, b, c}
    x = se.Symbol("x")
    expressions = [
        _long_polynomial(4),
        _long_polynomial(5),
        m * se.sin(a) * se.cos(b) + k * se.sin(a) ** 2 * se.cos(b) + m * k * se.cos(a) ** 2,
        m * x * se.sin(a) - k * x * se.sin(a) + m * se.cos(a - b) * (m + k),
    ]
    shared: dict[se.Expr, object] = {}
    for expr in expressions:
        alone = combine_and_collect(expr, state)
        remembered = combine_and_collect(expr, state, shared)
        assert remembered == alone and str(remembered) == str(alone)
        assert remembered.args == alone.args


def test_a_long_multiple_of_sin2_plus_cos2_minus_1_is_zero() -> None:
    """The reduced form is canonical: Q (sin^2 b + cos^2 b - 1) vanishes however long Q."""
    q = _long_polynomial(3)
    assert combine_trig(q * (se.sin(b) ** 2 + se.cos(b) ** 2 - 1)) == 0
    assert combine_and_collect(q * (se.sin(a) ** 2 + se.cos(a) ** 2 - 1), {a, b, c}) == 0


@pytest.mark.parametrize("seed", [6, 7])
def test_a_reduction_is_the_same_whatever_else_the_monomial_holds(seed: int) -> None:
    """The powers of sines and cosines of a monomial reduce the same with any other factors
    (state symbols, velocities, sines to the first power): the reduced monomial times those
    factors, expanded, in both canonical forms; and the value is kept."""
    rng = random.Random(seed)
    x, v = se.symbols("x v")
    algebra = TrigAlgebra([a, b, x, v])
    trig = [se.sin(a), se.cos(a), se.sin(b), se.cos(b)]
    for _ in range(40):
        part = se.Mul(*[f ** rng.randint(0, 5) for f in trig])
        others = [x ** rng.randint(0, 2) * v ** rng.randint(0, 2), se.sin(b) * x, m * v**3]
        alone = algebra.finish(algebra.convert(part))
        for other in others:
            whole = algebra.finish(algebra.convert(se.expand(other * part)))
            expected = se.expand(other * algebra.expression(alone))
            assert algebra.expression(whole) == expected
            sine = algebra.expression(algebra.sine_form(whole))
            if not other.has(se.sin(b)):
                assert sine == se.expand(other * algebra.expression(algebra.sine_form(alone)))
            values = {s: rng.uniform(-2, 2) for s in (a, b, x, v, m)}
            for form in (expected, sine):
                assert _value(form, values) == pytest.approx(_value(other * part, values))


def test_a_part_spliced_into_other_powers_is_their_sorted_union() -> None:
    """The terms of a reduction put into the monomial's other powers by bisection: the
    pairs of both sorted by generator index, wherever the part's generators fall."""
    rng = random.Random(11)
    for _ in range(300):
        indices = rng.sample(range(12), rng.randint(1, 9))
        cut = rng.randint(0, len(indices))
        others = sorted((i, rng.randint(1, 3)) for i in indices[:cut])
        part = sorted((i, rng.randint(1, 4)) for i in indices[cut:])
        flat = [tuple(x for pair in pairs for x in pair) for pairs in (others, part)]
        expected = tuple(x for pair in sorted(others + part) for x in pair)
        assert _spliced(flat[0], [i for i, _ in others], flat[1]) == expected


def test_a_sum_in_place_leaves_its_terms_alone() -> None:
    """Products and polynomials summed into one :class:`Sum` (the coefficients met once
    kept, shared) give their sum expanded and reduced, and the polynomials they came from are
    unchanged (a shared coefficient is copied before it is added to)."""
    x, v = se.symbols("x v")
    algebra = TrigAlgebra([a, x, v])
    first = algebra.finish(algebra.convert(m * se.sin(a) * v + k * se.cos(a) * x + m))
    second = algebra.finish(algebra.convert(k * se.sin(a) * v - m * x * se.cos(a) + 2 * k))
    before = [{key: dict(c) for key, c in p.items()} for p in (first, second)]
    total = Sum()
    total.add(first)
    total.add(second)
    algebra.accumulate_product(total, first, second)
    algebra.accumulate(total, second, next(iter(algebra.convert(v))), 3)
    expected = se.expand(
        algebra.expression(first) * (1 + algebra.expression(second))
        + (1 + 3 * v) * algebra.expression(second)
    )
    summed = algebra.expression(algebra.finish(algebra.gather(total)))
    assert summed == algebra.expression(algebra.finish(algebra.convert(expected)))
    values = {a: 0.7, x: -1.3, v: 0.4, m: 2.1, k: 0.3}
    assert _value(summed, values) == pytest.approx(_value(expected, values))
    assert [first, second] == before


def test_the_expanded_terms_are_bounded_on_the_tree() -> None:
    rng = random.Random(5)
    atoms = [se.sin(a), se.cos(b), m, k, a]
    for _ in range(20):
        expr = se.Integer(1)
        for _ in range(rng.randint(1, 4)):
            factor = se.Add(*[rng.choice(atoms) * rng.randint(1, 3) for _ in range(3)])
            expr = expr * factor + rng.choice(atoms)
        expanded = se.expand(expr)
        actual = len(expanded.args) if expanded.is_Add else 1
        assert expanded_terms(expr, 10**9) >= actual
        assert expanded_terms(expr, 2) <= 2


def _relative_chain() -> lg.System:
    """Two rods on ZXY joints, the second turned relative to the first (joint angles)."""
    angles = sp.symbols("a1 b1 c1 a2 b2 c2")
    m1, m2, l1, l2, g, I1, J1, I2, J2 = sp.symbols("m1 m2 l1 l2 g I1 J1 I2 J2")
    R1 = rotation_sequence([("z", angles[0]), ("x", angles[1]), ("y", angles[2])]).matrix
    turns2 = [("z", angles[3]), ("x", angles[4]), ("y", angles[5])]
    R2 = rotation_sequence(turns2, parent=R1).matrix
    down = sp.Matrix([0, 0, -1])
    return lg.System(
        coordinates=list(angles),
        parameters=[m1, m2, l1, l2, g, I1, J1, I2, J2],
        gravity=(0, 0, -g),
        rigid_bodies=[
            lg.RigidBody(
                "rod1",
                m1,
                sp.diag(I1, I1, J1),
                tuple(R1 * down * l1 / 2),
                rotations=[("z", angles[0]), ("x", angles[1]), ("y", angles[2])],
            ),
            lg.RigidBody(
                "rod2",
                m2,
                sp.diag(I2, I2, J2),
                tuple(R1 * down * l1 + R2 * down * l2 / 2),
                parent="rod1",
                rotations=turns2,
            ),
        ],
    )


def _numbers(form: kinetic.KineticForm, values: dict) -> tuple[np.ndarray, np.ndarray]:
    mass = np.array([[_value(e, values) for e in row] for row in form.mass_matrix])
    return mass, np.array([_value(e, values) for e in kinetic.coriolis_vector(form)])


def test_the_three_routes_to_m_and_c_agree(monkeypatch: pytest.MonkeyPatch) -> None:
    asm = assemble(_relative_chain())
    monkeypatch.setattr(kinetic, "STRUCTURED_PRODUCTS", 10**9)
    entry_by_entry = kinetic.kinetic_form(asm)
    assert not entry_by_entry.grouped
    monkeypatch.setattr(kinetic, "STRUCTURED_PRODUCTS", 0)
    grouped = kinetic.kinetic_form(asm)
    monkeypatch.setattr(kinetic, "NESTED_PRODUCTS", 0)
    nested = kinetic.kinetic_form(asm)
    assert grouped.grouped and nested.grouped
    rng = random.Random(7)
    symbols = {
        s
        for form in (entry_by_entry, grouped, nested)
        for e in [*(e for row in form.mass_matrix for e in row), *kinetic.coriolis_vector(form)]
        for s in e.free_symbols
    }
    for _ in range(3):
        values = {s: rng.uniform(-1.2, 1.2) if s in asm.q else rng.uniform(0.5, 2) for s in symbols}
        reference = _numbers(entry_by_entry, values)
        for form in (grouped, nested):
            for ours, theirs in zip(_numbers(form, values), reference):
                np.testing.assert_allclose(ours, theirs, rtol=1e-11, atol=1e-11)


def test_a_long_chain_keeps_its_angular_velocity_nested(monkeypatch: pytest.MonkeyPatch) -> None:
    """Three ZXY joints (9 turning rotations): omega_b stays as the products give it, the
    same numbers as expanded."""
    angles = sp.symbols("a1:10")
    turns = [(axis, angle) for axis, angle in zip("zxy" * 3, angles)]
    orientation = rotation_sequence(turns)
    nested = body_angular_velocity(orientation, angles)
    monkeypatch.setattr(rotation, "EXPANDED_TURNS", 100)
    expanded = body_angular_velocity(orientation, angles)
    assert sp.count_ops(nested) < sp.count_ops(expanded)
    rng = random.Random(3)
    values = {s: rng.uniform(-1, 1) for s in angles}
    values.update({velocity(s): rng.uniform(-1, 1) for s in angles})
    difference = (nested - expanded).xreplace(values)
    assert max(abs(float(e)) for e in difference) < 1e-12
