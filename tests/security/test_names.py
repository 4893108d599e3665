"""Names are identifiers in Python's normal form: lookalikes cannot merge two names, and no
name can carry a newline or a quote into generated code."""

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.io.load import loads


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("q\nrun(x)", "is not a name"),
        ("x y", "is not a name"),
        ("2x", "is not a name"),
        ("k'", "is not a name"),
        ("ｘ", "FULLWIDTH LATIN SMALL LETTER X.*write x$"),
        ("ﬁ", "neither ASCII nor Greek.*write fi$"),  # the fi ligature
        ("ℓ", "neither ASCII nor Greek.*write l$"),
        ("х", "CYRILLIC SMALL LETTER HA.*write x$"),  # beside the Latin x, prints the same
        ("𝐱", "MATHEMATICAL BOLD SMALL X.*write x$"),
        ("ϑ", "read as 'θ'.*write θ$"),
        ("lambda", "Python keyword.*write lambda_ or lam$"),
    ],
)
def test_a_name_that_is_not_an_identifier_is_refused(name, message):
    q = sp.Symbol(name)
    with pytest.raises(ModelError, match=message):
        lg.System(coordinates=[q], kinetic=sp.Symbol(name + "_dot") ** 2 / 2)


def test_lookalikes_do_not_merge_in_a_model_file():
    text = "coordinates: [x, ｘ]\nkinetic: x_dot**2/2 + ｘ_dot**2/2\n"
    with pytest.raises(ModelError, match=r"FULLWIDTH LATIN SMALL LETTER X.*write x"):
        loads(text)


@pytest.mark.parametrize("lookalike", ["х", "𝐱", "ｘ"])  # Cyrillic, bold, fullwidth
def test_a_lookalike_in_an_expression_is_refused_with_the_ascii_name(lookalike):
    text = f"coordinates: [x]\nkinetic: x_dot**2/2\npotential: {lookalike}**2\n"
    with pytest.raises(ModelError, match=f"'{lookalike}' has a letter that is neither ASCII nor"):
        loads(text)


def test_a_python_keyword_is_refused_as_a_coordinate_with_the_fix():
    text = "coordinates: [lambda]\nkinetic: lambda_dot**2/2\npotential: lambda**2\n"
    with pytest.raises(ModelError, match=r"coordinates.*'lambda' is a Python keyword.*lam"):
        loads(text)


def test_greek_and_subscripted_names_are_names():
    theta, theta_2 = sp.symbols("θ theta_2")
    system = lg.System(
        coordinates=[theta, theta_2],
        kinetic=sp.Symbol("θ_dot") ** 2 / 2 + sp.Symbol("theta_2_dot") ** 2 / 2,
    )
    assert len(lg.derive(system).equations) == 2
