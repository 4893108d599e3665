"""Sums of the trigonometric polynomials (lagrangian.derivation.trig_polynomial), made in
place: a sum or a sine form equals the sum of the numbers it stands for, and leaves the
polynomials it was made of as they were (their coefficients are shared); a coefficient
scaled by a fraction keeps its whole numbers as integers; a state monomial's coefficient is
factored when SymEngine's expansion of it has at most FACTORED_TERMS terms."""

from __future__ import annotations

import copy
import math
from fractions import Fraction

import symengine as se
from hypothesis import given, settings
from hypothesis import strategies as st

from lagrangian.derivation.trig_polynomial import FACTORED_TERMS, TrigAlgebra, _add_into, _scaled

x, y, m, a = se.symbols("x y m a")
ANGLES = (x, y)
_term = st.tuples(
    st.integers(-3, 3), st.integers(0, 3), st.integers(0, 3), st.integers(0, 2), st.booleans()
)
_polynomial = st.lists(_term, min_size=1, max_size=5)


def _expression(terms: list) -> se.Expr:
    """sum n sin(x)**i cos(x)**j cos(y)**k (times m or a)."""
    return se.Add(
        *[
            n * (m if weighted else a) * se.sin(x) ** i * se.cos(x) ** j * se.cos(y) ** k
            for n, i, j, k, weighted in terms
        ]
    )


def _value(expr: se.Expr, at: dict) -> float:
    return float(expr.xreplace({s: se.Float(v) for s, v in at.items()}))


POINTS = ({x: 0.3, y: -1.1, m: 1.7, a: 0.4}, {x: -2.4, y: 0.9, m: -0.6, a: 2.5})


@settings(max_examples=60, deadline=None)
@given(st.lists(_polynomial, min_size=1, max_size=4))
def test_sums_and_sine_forms_keep_their_value_and_their_parts(parts: list) -> None:
    algebra = TrigAlgebra(ANGLES)
    polys = [algebra.finish(algebra.convert(_expression(terms))) for terms in parts]
    before = copy.deepcopy(polys)
    total = algebra.add(polys)
    finished = algebra.finish(total)
    sines = algebra.sine_form(finished)
    again = algebra.sine_form(finished)
    assert polys == before  # no coefficient of a part summed into
    assert sines == again
    for at in POINTS:
        expected = sum(_value(_expression(terms), at) for terms in parts)
        for form in (total, sines):
            found = _value(algebra.expression(form), at)
            assert math.isclose(found, expected, rel_tol=1e-9, abs_tol=1e-9)


def test_a_fraction_times_whole_numbers_gives_integers() -> None:
    algebra = TrigAlgebra(ANGLES)
    p = algebra.convert(4 * m * x + 3 * a * y + se.RealDouble(0.5) * m * y)
    half = TrigAlgebra.scale(p, Fraction(-1, 2))
    numbers = sorted((v for c in half.values() for v in c.values()), key=float)
    assert numbers == [-2, Fraction(-3, 2), -0.25]
    assert [type(v) for v in numbers] == [int, Fraction, float]
    expected = -2 * m * x - se.Rational(3, 2) * a * y - se.RealDouble(0.25) * m * y
    assert se.expand(algebra.expression(half)) == expected


def _grouped_is_factored(algebra: TrigAlgebra, p: dict) -> bool:
    """True when the coefficient of x in grouped(p) came out factored: x m (...), not
    x (m c0 + ...)."""
    grouped = algebra.grouped(algebra.finish(p))
    return grouped.is_Mul and m in grouped.args


def test_a_coefficient_is_factored_up_to_the_terms_of_its_expansion() -> None:
    cs = se.symbols(f"c0:{FACTORED_TERMS + 1}")
    for count, factored in ((FACTORED_TERMS, True), (FACTORED_TERMS + 1, False)):
        algebra = TrigAlgebra(ANGLES)
        p = algebra.convert(se.expand(m * x * se.Add(*cs[:count])))
        assert _grouped_is_factored(algebra, p) is factored
    # sqrt(2)**2 m a and 2 m a: two parameter monomials, one term once built
    for count, factored in ((FACTORED_TERMS - 1, True), (FACTORED_TERMS, False)):
        algebra = TrigAlgebra(ANGLES)
        root = algebra.multiply(
            algebra.convert(se.sqrt(2) * m * x), algebra.convert(se.sqrt(2) * a)
        )
        rest = algebra.convert(se.expand(m * x * (2 * a + se.Add(*cs[:count]))))
        assert len(algebra.add([root, rest])[(algebra.index[x], 1)]) == count + 2
        assert _grouped_is_factored(algebra, algebra.add([root, rest])) is factored


def test_a_term_taken_negated_is_minus_one_times_it() -> None:
    """The sine form's -cos^2 terms are subtracted, not multiplied by -1: the same numbers of
    the same types (integers, fractions, floats, signed zeros), added to a new monomial or to
    one already summed."""
    numbers = [3, -2, Fraction(5, 7), 0.1, -0.0, 2.5e-17]
    c = dict(enumerate(numbers))
    for known in ({}, {(): {0: 1, 3: 0.2, 4: 0.0, 7: Fraction(1, 3)}}):
        result = copy.deepcopy(known)
        _add_into(result, set(), (), c, -1)
        expected = dict(copy.deepcopy(known).get((), {}))
        for k, v in c.items():
            expected[k] = expected.get(k, 0) + -1 * v
        assert result[()] == expected
        assert [type(v) for v in result[()].values()] == [type(v) for v in expected.values()]
        assert [math.copysign(1, v) for v in result[()].values()] == [
            math.copysign(1, v) for v in expected.values()
        ]
    assert _scaled(c, -1) == {k: -1 * v for k, v in c.items()}
