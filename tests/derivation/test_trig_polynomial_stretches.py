"""The short ways of the trigonometric algebra (lagrangian.derivation.trig_polynomial) give
what its general ways give: products of monomials (joined end to end or merged) are the
sorted sum of their powers; a single squared cosine (in a product), or any number of
squared sines (in the sine form), reduced stretch by stretch of the monomial gives the terms,
in the same order, of the reduction through the powers' dict; a derivative lowers one
power in place; a product of two one-term polynomials is the product summed through a
:class:`Sum`; and the sine form of a polynomial with no sine squared is that polynomial."""

from __future__ import annotations

import random

import symengine as se

from lagrangian.derivation.trig_polynomial import Sum, TrigAlgebra, pairs

q1, q2, q3, u1, u2, m, lam = se.symbols("q1 q2 q3 u1 u2 m lam")
STATE = (q1, q2, q3, u1, u2)


def _algebra() -> TrigAlgebra:
    """An algebra whose generators interleave: sines and cosines of three angles and of a
    constant one, the velocities between them."""
    algebra = TrigAlgebra(STATE)
    for gen in (se.sin(q1), u1, se.cos(lam), se.sin(q2), u2, se.sin(q3), q1):
        algebra.convert(gen)
    return algebra


def _monomial(
    rng: random.Random, algebra: TrigAlgebra, top: int = 4, cosines: bool = True
) -> tuple[int, ...]:
    gens = [i for i, cosine in enumerate(algebra.cosine) if cosines or not cosine]
    indices = sorted(rng.sample(gens, rng.randint(0, 5)))
    return tuple(x for i in indices for x in (i, rng.randint(1, top)))


def _reduced_monomial(rng: random.Random, algebra: TrigAlgebra) -> tuple[int, ...]:
    """A monomial of a polynomial in the algebra's form: no cosine squared."""
    key = _monomial(rng, algebra)
    return tuple(x for i, e in pairs(key) for x in (i, 1 if algebra.cosine[i] else e))


def test_products_of_monomials_are_the_sorted_sum_of_their_powers() -> None:
    """Joined end to end or merged where their generators interleave (no cosine: nothing
    to reduce)."""
    rng = random.Random(5)
    algebra = _algebra()
    for _ in range(500):
        a, b = (_monomial(rng, algebra, cosines=False) for _ in range(2))
        powers = dict(pairs(a))
        for i, e in pairs(b):
            powers[i] = powers.get(i, 0) + e
        expected = tuple(x for pair in sorted(powers.items()) for x in pair)
        assert algebra.multiply_keys(a, b) == expected


def test_a_stretch_reduces_as_the_powers_dict_does() -> None:
    """Products (cosines squared, their powers in a's order then b's) and sine forms (one
    sine squared or several), with any other powers about them: the same terms in the same
    order, and each term's value is the monomial's."""
    rng = random.Random(8)
    algebra = _algebra()
    for _ in range(800):
        a, b = _monomial(rng, algebra), _monomial(rng, algebra)
        powers = dict(pairs(a))
        for i, e in pairs(b):
            powers[i] = powers.get(i, 0) + e
        if any(e > 1 and algebra.cosine[i] for i, e in powers.items()):
            assert algebra._made_product(a, b) == algebra._reduced(dict(powers))
        key = _monomial(rng, algebra)
        if any(e > 1 and algebra.sine[i] for i, e in pairs(key)):
            assert algebra._sine_reduction(key) == algebra._reduced(dict(pairs(key)), algebra.sine)


def test_derivatives_of_monomials_match_symengine() -> None:
    rng = random.Random(13)
    algebra = _algebra()
    values = {s: se.Float(rng.uniform(-1.5, 1.5)) for s in (*STATE, lam)}
    for _ in range(150):
        key = _monomial(rng, algebra, top=3)
        expr = algebra.monomial_expression(key)
        for symbol in (q1, q2, u1):
            found = algebra.expression(algebra.derivative({key: {0: 1}}, symbol))
            expected = expr.diff(symbol)
            assert abs(float((found - expected).xreplace(values))) < 1e-9


def test_a_product_of_two_terms_is_the_summed_product() -> None:
    rng = random.Random(21)
    algebra = _algebra()
    weights = [{0: 1}, {0: -2}, algebra.coefficient(3 * m), algebra.coefficient(m + 2)]
    for _ in range(400):
        a = {_reduced_monomial(rng, algebra): rng.choice(weights)}
        b = {_reduced_monomial(rng, algebra): rng.choice(weights)}
        summed = Sum()
        algebra.accumulate_product(summed, a, b)
        assert algebra.multiply(a, b) == algebra.gather(summed)


def test_a_polynomial_with_no_sine_squared_is_its_own_sine_form() -> None:
    algebra = _algebra()
    p = algebra.finish(algebra.convert(m * se.cos(q1) * se.sin(q2) * u1 + se.sin(q3) * u2**2))
    assert algebra.sine_form(p) is p
    assert algebra.shortest(p) is p
    squared = algebra.finish(algebra.convert(m * se.sin(q1) ** 2 * u1))
    assert algebra.expression(algebra.sine_form(squared)) == se.expand(
        m * u1 * (1 - se.cos(q1) ** 2)
    )
