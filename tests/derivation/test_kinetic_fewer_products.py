"""The kinetic form of a 3-D system formed with fewer products (derivation/kinetic.py): each
product of a pair of monomials on M's diagonal once with its weight doubled, the Christoffel
symbols summed before they multiply their velocity pair (the pairs holding the row's own
coordinate in closed form), two rows turned into one sum each.  Each is compared with the
textbook sum formed product by product with the algebra's plain multiply and add, as
finished polynomials (the reduced form is canonical: equal polynomials are the same)."""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import symengine as se

from lagrangian.derivation.kinetic import (
    _add_gram,
    _christoffel,
    _symbol,
    _turn,
)
from lagrangian.derivation.trig_polynomial import Sum, TrigAlgebra


def _gram(algebra, weight, first, second, n):
    shares = [[Sum() for _ in range(n)] for _ in range(n)]
    _add_gram(algebra, shares, algebra.convert(weight), first, second)
    return [[algebra.finish(algebra.gather(shares[j][k])) for k in range(n)] for j in range(n)]


def _textbook_gram(algebra, weight, first, second, n):
    """weight sum_r (first_rj second_rk + second_rj first_rk) (once when first is second),
    each product made apart and all added."""
    w = algebra.convert(weight)
    pairs = list(zip(first, second))
    pairs += [] if first is second else [(b, a) for a, b in pairs]
    return [
        [
            algebra.finish(
                algebra.add([algebra.multiply(w, algebra.multiply(a[j], b[k])) for a, b in pairs])
            )
            if k >= j
            else {}
            for k in range(n)
        ]
        for j in range(n)
    ]


def test_the_gram_matrix_with_the_diagonal_products_once_is_the_textbook_sum(
    bicycle_fork: tuple[Any, ...],
) -> None:
    asm, algebra, fork, _, rows = bicycle_fork
    n = len(asm.q)
    assert _gram(algebra, fork.mass, rows, rows, n) == _textbook_gram(
        algebra, fork.mass, rows, rows, n
    )
    # two different sets of rows (an inertia's off-diagonal I_ab: J_a^T J_b + J_b^T J_a)
    first, second = [rows[0]], [rows[2]]
    made = _gram(algebra, fork.mass, first, second, n)
    assert made == _textbook_gram(algebra, fork.mass, first, second, n)
    assert any(made[j][j] for j in range(n))  # the diagonal's doubled products were met


def _textbook_coriolis(algebra, mass, asm):
    """(C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l over all k, l."""
    n = len(asm.q)
    rates = [algebra.convert(v) for v in asm.q_dot]
    rows = []
    for j in range(n):
        parts = []
        for k in range(n):
            for ell in range(n):
                pair = algebra.multiply(rates[k], rates[ell])
                slope = algebra.derivative(mass[j][k], asm.q[ell])
                half = algebra.scale(algebra.derivative(mass[k][ell], asm.q[j]), Fraction(-1, 2))
                parts += [algebra.multiply(slope, pair), algebra.multiply(half, pair)]
        rows.append(algebra.finish(algebra.add(parts)))
    return rows


def test_the_christoffel_rows_are_the_textbook_sum_with_no_zero_term(
    bicycle_fork: tuple[Any, ...],
) -> None:
    """M is the bicycle fork's J^T J (entries in lean, pitch and steer)."""
    asm, algebra, fork, _, rows = bicycle_fork
    n = len(asm.q)
    gram = _gram(algebra, fork.mass, rows, rows, n)
    mass = [[gram[min(j, k)][max(j, k)] for k in range(n)] for j in range(n)]
    made = _christoffel(algebra, mass, asm)
    assert made == _textbook_coriolis(algebra, mass, asm)
    assert sum(map(len, made)) > 100
    assert all(value for row in made for c in row.values() for value in c.values())


def test_two_rows_turned_are_the_textbook_combination(bicycle_fork: tuple[Any, ...]) -> None:
    """(c a + s b, -s a + c b), each product made apart and added."""
    asm, algebra, _, world, _ = bicycle_fork
    yaw = next(s for s in asm.q if str(s) == "yaw")
    c, s = algebra.convert(se.cos(yaw)), algebra.convert(-se.sin(yaw))
    one, other = _turn(algebra, world[0], world[1], yaw, -1)
    assert one == [
        algebra.finish(algebra.add([algebra.multiply(c, a), algebra.multiply(s, b)]))
        for a, b in zip(world[0], world[1])
    ]
    minus_s = algebra.scale(s, -1)
    assert other == [
        algebra.finish(algebra.add([algebra.multiply(minus_s, a), algebra.multiply(c, b)]))
        for a, b in zip(world[0], world[1])
    ]


def test_a_symbol_of_two_equal_parts_is_their_textbook_sum_with_floats_too() -> None:
    """Two parts that are one polynomial (the derivatives of a translation's column of M)
    are taken once with the sum of their scales: the same as adding the scaled parts, exactly,
    with integer, fraction and float coefficients."""
    lean, steer, m, c = se.symbols("lean steer m c")
    algebra = TrigAlgebra([lean, steer])
    for number in (se.Integer(3), se.Rational(5, 7), se.RealDouble(0.1)):
        p = algebra.finish(
            algebra.convert(number * m * se.sin(lean) * se.cos(steer) + c * se.cos(lean) ** 2)
        )
        for scales in ((1, 1), (1, -1), (1, Fraction(-1, 2))):
            parts = [(p, scale) for scale in scales]
            textbook = algebra.finish(algebra.add([algebra.scale(q, k) for q, k in parts]))
            assert _symbol(algebra, parts) == textbook
    assert _symbol(algebra, [(p, 1), (dict(p), -1)]) == {}
