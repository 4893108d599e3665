"""The coefficients of the trigonometric polynomials (lagrangian.derivation.trig_polynomial)
are numbers by parameter monomial: each coefficient built back is checked, as the same
expression, against SymEngine's expansion of the product it came from (integers,
fractions, floats, negative powers of parameters, a parameter factor that is no
polynomial)."""

from __future__ import annotations

from fractions import Fraction

import pytest
import symengine as se

from lagrangian.derivation.trig_polynomial import TrigAlgebra

x, y, a, b, k, m = se.symbols("x y a b k m")
STATE = (x, y)
# each the product whose expansion the algebra has to give, by power of x and y
PRODUCTS = {
    "integers": (a * x + 2 * b * y - 3) * (a * x - b * y + a * b),
    "fraction": se.Rational(1, 2) * m * x * (x + se.Rational(2, 3) * a) * (3 * y - a / 5),
    "float": se.RealDouble(0.5) * m * x * (x + 2 * a) + se.RealDouble(1.25) * a * x**2,
    "float cancelling": se.RealDouble(0.5) * m * x + se.RealDouble(0.5) * m * x - m * x + y,
    "inverse": (1 / m) * (m * x + a * x) * (k * y + m),
    "inverse squared": (a * x + 1) / m**2 * (m**3 * y + m * x),
    "square root": se.sqrt(k / m) * x * (se.sqrt(k / m) * x + a),
    "inverse sum": x / (a + b) * (a * x + b * y + (a + b) ** 2),
    "function": se.exp(a) * x * (se.exp(a) * y + se.exp(a + b) + 2 * x),
}


def _by_state_monomial(expr: se.Expr) -> dict[tuple[int, int], se.Expr]:
    """SymEngine's expansion of ``expr`` summed by the powers of x and y (the other factors
    of each term its coefficient)."""
    expanded = se.expand(expr)
    parts: dict[tuple[int, int], list[se.Expr]] = {}
    for term in expanded.args if expanded.is_Add else (expanded,):
        powers = term.as_powers_dict()
        key = tuple(int(powers.get(s, 0)) for s in STATE)
        parts.setdefault(key, []).append(term / (x ** key[0] * y ** key[1]))
    return {key: se.Add(*terms) for key, terms in parts.items()}


@pytest.mark.parametrize("name", PRODUCTS)
def test_each_coefficient_built_is_the_expansion_of_the_product(name: str) -> None:
    expr = PRODUCTS[name]
    algebra = TrigAlgebra(STATE)
    # the product formed by the algebra, factor by factor
    factors = expr.args if expr.is_Mul else (expr,)
    polynomial = algebra.convert(factors[0])
    for factor in factors[1:]:
        polynomial = algebra.multiply(polynomial, algebra.convert(factor))
    polynomial = algebra.finish(polynomial)
    expected = _by_state_monomial(expr)
    found = {}
    for key, coefficient in polynomial.items():
        powers = dict(zip(key[::2], key[1::2]))
        state_key = tuple(powers.get(algebra.index.get(s, -1), 0) for s in STATE)
        found[state_key] = algebra.built(coefficient)
    assert found.keys() == expected.keys()
    for key, coefficient in expected.items():
        assert found[key] == coefficient  # the same expression, not only equal in value
        assert str(found[key]) == str(coefficient)
    rebuilt = se.Add(*[x**i * y**j * c for (i, j), c in expected.items()])
    assert algebra.expression(polynomial) == rebuilt


def test_the_numbers_are_python_numbers_floats_kept_floats() -> None:
    algebra = TrigAlgebra(STATE)
    half = algebra.finish(algebra.convert(se.Rational(1, 2) * m * x))
    assert [list(c.values()) for c in half.values()] == [[Fraction(1, 2)]]
    one = algebra.finish(algebra.convert(se.RealDouble(1.0) * m * x))
    ((value,),) = (c.values() for c in one.values())
    assert isinstance(value, float)
    assert algebra.expression(one) == se.RealDouble(1.0) * m * x  # 1.0 m x, not m x
    assert algebra.finish(algebra.convert(m * (1 / m) * x - x)) == {}


def test_a_cancelled_parameter_leaves_the_monomial_of_the_others() -> None:
    algebra = TrigAlgebra(STATE)
    product = algebra.finish(algebra.multiply(algebra.convert(m * x), algebra.convert(a / m)))
    assert [list(c) for c in product.values()] == [list(algebra.coefficient(a))]
    assert algebra.expression(product) == a * x


def test_pythagoras_with_parameters_in_the_coefficients() -> None:
    algebra = TrigAlgebra(STATE)
    expr = m / k * se.cos(x) ** 2 * (a + 1) + (a * m / k + m / k) * se.sin(x) ** 2
    assert algebra.expression(algebra.finish(algebra.convert(expr))) == se.expand(m / k * (a + 1))


def test_an_integer_and_a_float_coefficient_are_built_apart() -> None:
    """2 and 2.0 are equal dict keys: a coefficient 2.0 built after a coefficient 2 (or the
    other way round) must still come back a double (an integer), as SymEngine writes it."""
    for first, second in ((se.Integer(2), se.RealDouble(2.0)), (se.RealDouble(2.0), se.Integer(2))):
        algebra = TrigAlgebra(STATE)
        built = [
            algebra.expression(algebra.finish(algebra.convert(number * m * x)))
            for number in (first, second)
        ]
        assert [type(e.args[0]) for e in built] == [type(first), type(second)]
        assert built == [se.expand(first * m * x), se.expand(second * m * x)]
