"""Derivatives of monomials with constant sines and cosines (derivation/trig_polynomial.py):
the state part's derivative remembered and the constant part multiplied back must give the
polynomial of SymEngine's own derivative, also where the rate of an angle holds a constant
angle's cosine (its square is then reduced), and the same as the whole monomial's
derivative taken generator by generator."""

from __future__ import annotations

import random

import symengine as se

from lagrangian.derivation.trig_polynomial import TrigAlgebra

q1, q2, lam, mu, m = se.symbols("q1 q2 lam mu m")
STATE = [q1, q2]
FACTORS = [
    se.sin(q1),
    se.cos(q1),
    se.sin(q2 + lam),
    se.cos(q2 + lam),
    se.sin(q1 * se.cos(lam)),
    se.cos(q1 * se.cos(lam)),
    q2,
    se.sin(lam),
    se.cos(lam),
    se.cos(mu),
    m,
]


def _products(rng: random.Random, count: int) -> list:
    return [
        se.Mul(*[rng.choice(FACTORS) ** rng.randint(1, 3) for _ in range(rng.randint(1, 5))])
        for _ in range(count)
    ]


def test_derivative_is_symengines_polynomial() -> None:
    rng = random.Random(7)
    algebra = TrigAlgebra(STATE)
    for expr in _products(rng, 150):
        for q in STATE:
            got = algebra.finish(algebra.derivative(algebra.convert(expr), q))
            want = algebra.finish(algebra.convert(se.expand(expr.diff(q))))
            assert got == want, (expr, q)


def test_derivative_same_as_generator_by_generator() -> None:
    rng = random.Random(11)
    algebra = TrigAlgebra(STATE)
    for expr in _products(rng, 150):
        p = algebra.convert(expr)
        for q in STATE:
            got = algebra.finish(algebra.derivative(p, q))
            whole = [algebra.scale(algebra._key_derivative(k, q), c) for k, c in p.items()]
            assert got == algebra.finish(algebra.add(whole)), (expr, q)
