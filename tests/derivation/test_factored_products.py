"""A grouped coefficient's common factors read off the powers of its parts
(:meth:`TrigAlgebra._factored_products`: the constant monomial's and each term's, side by
side) must be the expression :func:`collect.factor_common` makes of the products
multiplied out: on the parts the bicycle's derivation groups, on random polynomials with
constant angles, numbers (doubles too), irregular parameter factors and a constant
generator SymEngine merges with another, and on parts whose products SymEngine would combine."""

from __future__ import annotations

import random

import symengine as se

from lagrangian.derivation.collect import factor_common, factor_products
from lagrangian.derivation.terms import EulerLagrangeTerms
from lagrangian.derivation.trig_polynomial import TrigAlgebra, forget_algebras
from lagrangian.examples import BENCHMARKS

q1, q2, u1, u2, lam, mu, a, b, m = se.symbols("q1 q2 u1 u2 lam mu a b m")
STATE = [q1, q2, u1, u2]
MOVING = [se.sin(q1), se.cos(q1), se.cos(q2), u1, u2]
CONSTANT = [
    se.sin(lam),
    se.cos(lam),
    se.cos(mu),
    se.sqrt(se.cos(lam)),  # a generator of its own, merged with cos(lam) into one power
    a,
    b,
    m,
    a + b,
    se.sqrt(2),
    se.sqrt(a),
    se.Integer(3),
    se.Rational(-1, 2),
    se.RealDouble(2.0),
]


def _reference(parts: list[tuple[se.Basic, se.Basic]]) -> se.Basic:
    terms = [f * t for f, c in parts for t in (c.args if c.is_Add else (c,))]
    return factor_common(terms)


def _same(algebra: TrigAlgebra, parts: list[tuple[se.Basic, se.Basic]]) -> None:
    made, reference = algebra._factored_products(parts), _reference(parts)
    assert made == reference
    assert str(made) == str(reference)


def _recorded_parts(monkeypatch, run) -> list[tuple[TrigAlgebra, list]]:
    seen = []
    factor_parts = TrigAlgebra._factor_parts

    def recorded(self, parts):
        seen.append((self, list(parts)))
        return factor_parts(self, parts)

    monkeypatch.setattr(TrigAlgebra, "_factor_parts", recorded)
    run()
    monkeypatch.undo()
    return seen


def test_bicycle_parts(monkeypatch) -> None:
    """Every group of parts the bicycle's derivation factors (M, C q_dot, the forcing)."""
    forget_algebras()
    seen = _recorded_parts(monkeypatch, lambda: EulerLagrangeTerms(BENCHMARKS["whipple_bicycle"]()))
    assert len(seen) > 100
    for algebra, parts in seen:
        _same(algebra, parts)


def _random_expression(rng: random.Random) -> se.Basic:
    terms = []
    for _ in range(rng.randint(1, 10)):
        factors = rng.sample(MOVING, rng.randint(0, 2)) + rng.sample(CONSTANT, rng.randint(1, 4))
        terms.append(rng.choice([1, -1, 2]) * se.Mul(*factors))
    return se.expand(se.Add(*terms))


def test_random_parts(monkeypatch) -> None:
    rng = random.Random(11)
    algebra = TrigAlgebra(STATE)

    def group_all() -> None:
        for _ in range(200):
            algebra.grouped(algebra.finish(algebra.convert(_random_expression(rng))))

    seen = _recorded_parts(monkeypatch, group_all)
    assert sum(len(parts) > 1 for _, parts in seen) > 100
    for _, parts in seen:
        _same(algebra, parts)


def test_parts_symengine_would_combine() -> None:
    """A constant monomial with a number, or with a base of a term, and a zero coefficient:
    the products are made as they are."""
    algebra = TrigAlgebra(STATE)
    cos = se.cos(lam)
    for parts in (
        [(2 * cos, a * m + b), (se.sin(lam), 3 * a * m)],
        [(cos, a * cos + b), (se.sin(lam), a)],
        [(cos, se.Integer(0)), (se.sin(lam), a * b)],
        [(cos**2, -a * b), (se.Integer(1), 4 * a * b * m)],
    ):
        _same(algebra, parts)


def test_factor_products_is_factor_common() -> None:
    split = [(se.Integer(-2), {a: se.Integer(2), m: se.Integer(1)}), (se.Integer(4), {a: b})]
    products = [(-2 * a**2, m), (4, a**b)]
    assert factor_products(split, products) == factor_common([-2 * a**2 * m, 4 * a**b])
    assert factor_products(split[:1], products[:1]) == -2 * a**2 * m
