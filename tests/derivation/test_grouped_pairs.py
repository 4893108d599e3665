"""The grouped forcing collected from the pairs the algebra built it from
(:meth:`TrigAlgebra.grouped_terms`, :func:`collect.collect_pairs`) must be the expression
:func:`collect.collect_state` makes by walking every factor of the grouped sum: on the
polynomials of the bicycle's equations and on random trigonometric polynomials, with
numbers, shared coefficients of either sign and sum coefficients."""

from __future__ import annotations

import random

import symengine as se

from lagrangian.derivation.collect import collect_pairs, collect_state
from lagrangian.derivation.terms import EulerLagrangeTerms
from lagrangian.derivation.trig_polynomial import TrigAlgebra, forget_algebras
from lagrangian.examples import BENCHMARKS

q1, q2, u1, u2, lam, a, b, m = se.symbols("q1 q2 u1 u2 lam a b m")
STATE = [q1, q2, u1, u2]
MOVING = [se.sin(q1), se.cos(q1), se.cos(q2), u1, u2, q2]
CONSTANT = [se.sin(lam), se.cos(lam), a, b, m, se.Integer(2), se.Rational(-1, 2), a + b]


def _random_expression(rng: random.Random) -> se.Basic:
    terms = []
    for _ in range(rng.randint(1, 12)):
        factors = rng.sample(MOVING, rng.randint(0, 3)) + rng.sample(CONSTANT, rng.randint(1, 3))
        terms.append(rng.choice([1, -1]) * se.Mul(*factors))
    return se.expand(se.Add(*terms))


def _check(algebra: TrigAlgebra, p: dict, state: list) -> bool:
    grouped, pairs = algebra.grouped_terms(p)
    assert grouped == algebra.grouped(p)
    if pairs is None:
        return False
    walked = collect_state(grouped, set(state))
    assert collect_pairs(grouped, pairs) == walked
    assert str(collect_pairs(grouped, pairs)) == str(walked)
    return True


def test_random_polynomials() -> None:
    rng = random.Random(5)
    algebra = TrigAlgebra(STATE)
    read = 0
    for _ in range(300):
        p = algebra.shortest(algebra.finish(algebra.convert(_random_expression(rng))))
        read += _check(algebra, p, STATE)
    assert read > 250  # most come with their pairs


def test_opposite_sum_coefficients() -> None:
    """Sum coefficients whose negatives are others' (a - b and -a + b; SymEngine writes
    -(a - b) as a product, so collecting shares neither under the other, in any order)."""
    rng = random.Random(7)
    sums = [a - b, b - a, a * m - b, b - a * m, m - a + b]
    algebra = TrigAlgebra(STATE)
    opposite = 0
    for _ in range(100):
        monomials = rng.sample([*MOVING, u1 * u2, q2 * u1, se.sin(q1) * u2], rng.randint(3, 9))
        expr = se.expand(se.Add(*[k * rng.choice(sums) for k in monomials]))
        p = algebra.shortest(algebra.finish(algebra.convert(expr)))
        coefficients = {c for _, c in algebra._grouped_pairs(p) if c.is_Add}
        opposite += any(se.expand(-c) in coefficients for c in coefficients)
        assert _check(algebra, p, STATE)
    assert opposite > 50


def test_bicycle_forcing(monkeypatch) -> None:
    """Every polynomial the bicycle's tidying groups, collected both ways."""
    seen = []
    grouped_terms = TrigAlgebra.grouped_terms

    def recorded(self, p):
        seen.append((self, p))
        return grouped_terms(self, p)

    monkeypatch.setattr(TrigAlgebra, "grouped_terms", recorded)
    forget_algebras()
    EulerLagrangeTerms(BENCHMARKS["whipple_bicycle"]())  # not remembered, as lg.derive is
    monkeypatch.undo()
    assert len(seen) > 5
    assert all([_check(algebra, p, list(algebra.state)) for algebra, p in seen])
