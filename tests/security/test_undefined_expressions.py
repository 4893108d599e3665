"""Undefined or singular expressions are refused at parse time with their field, never turned
into 0 (SymPy's log(x, 0) = log(x)/log(0) = 0) or kept to hang a simulation later."""

import pytest

from lagrangian.errors import ExpressionError
from lagrangian.io.load import loads

MODEL = "name: probe\ncoordinates: [x]\nparameters: {k: 1}\nkinetic: x_dot**2/2\npotential: {}\n"


@pytest.mark.parametrize(
    ("potential", "reason"),
    [
        ("x/log(0, x)", r"log\(0\) is undefined"),
        ("log(x, 0)", "base 0"),
        ("log(x, 1)", "base 1"),
        ("k*log(0)", r"log\(0\)"),
        ("1/(sin(x)**2 + cos(x)**2 - 1)", "identically zero"),
        ("x/(exp(x)*exp(-x) - 1)", "division by zero"),  # SymPy cancels it first
    ],
)
def test_undefined_expressions_are_refused_with_their_field(potential, reason):
    with pytest.raises(ExpressionError, match=reason) as refused:
        loads(MODEL.replace("{}", potential))
    assert "potential" in str(refused.value)


@pytest.mark.parametrize("potential", ["log(x, 2)", "k/(x**2 + 1)", "log(x)", "x/(1 + x - x)"])
def test_defined_expressions_still_parse(potential):
    assert loads(MODEL.replace("{}", potential)).potential != 0


@pytest.mark.parametrize(
    "potential",
    [
        "(" + " + ".join(f"sin({i}*x)" for i in range(1, 40)) + ")**30",  # 10**19 terms
        "(x + y + z + w + 1)**40",  # C(44, 4) = 135,751 monomials
    ],
)
def test_an_expression_that_would_expand_past_the_budget_is_refused(potential):
    with pytest.raises(ExpressionError, match="more than 100,000 terms"):
        loads(MODEL.replace("{}", potential).replace("[x]", "[x, y, z, w]"))


def test_a_long_product_in_one_variable_is_not_refused():
    # (x + 1)(x + 2)...(x + 29) has 30 terms multiplied out, not 2**29
    product = "*".join(f"(x + {i})" for i in range(1, 30))
    assert loads(MODEL.replace("{}", product)).potential != 0
