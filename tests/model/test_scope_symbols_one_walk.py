"""A constraint's names are checked and its free symbols found in one walk
(lagrangian.model.validation.NameScope.symbols_if_fine): the symbols are SymPy's free symbols
wherever the full check finds no problem (unless a part binds symbols or is a
function of time: the full check decides), and None wherever it finds one; and the probe's
random values are drawn in the order of the symbols' printed names."""

from __future__ import annotations

import random

import pytest
import sympy as sp

from lagrangian.examples import BENCHMARKS
from lagrangian.model.validation import STATE, NameScope
from lagrangian.symbolic.probe import random_values
from lagrangian.symbolic.symbols import acceleration, velocity

x, y, th, m, g, L = sp.symbols("x y theta m g L")
xd, thd = velocity(x), velocity(th)
SCOPE_VALUES = {"coordinates": (x, y, th), "parameters": {m: 1.0, g: 9.81, L: 0.5}}

FINE = [
    xd * sp.cos(th) - L * thd,
    x**2 + y**2 - L**2,
    sp.sqrt(1 - sp.sin(th) ** 2) * (xd + sp.Rational(1, 3)) + sp.pi * sp.exp(-th),
    sp.Float(2.5) * m * g + sp.sin(sp.sin(x + y)) ** 3,
    sp.Integer(7),
]
NOT_FINE = [
    x + sp.Symbol("unknown"),
    sp.Derivative(sp.Function("f")(x), x),
    acceleration(x) + y,
    x * sp.nan,
    sp.Matrix([x, y]),
    "x + y",
]


def _problems(value: object) -> list:
    found: list = []
    NameScope(SCOPE_VALUES).check(value, "field", STATE, found)
    return found


@pytest.mark.parametrize("value", FINE)
def test_the_symbols_of_a_value_the_check_passes_are_its_free_symbols(value: sp.Expr) -> None:
    assert not _problems(value)
    assert NameScope(SCOPE_VALUES).symbols_if_fine(value, STATE) == value.free_symbols


@pytest.mark.parametrize("value", NOT_FINE, ids=str)
def test_a_value_the_check_refuses_has_no_symbols(value: object) -> None:
    assert _problems(value)
    assert NameScope(SCOPE_VALUES).symbols_if_fine(value, STATE) is None


@pytest.mark.parametrize(
    "value",
    [
        sp.Integral(x * sp.Symbol("s"), (sp.Symbol("s"), 0, 1)),  # binds s; x is free
        sp.Function("f")(x),  # a function of time
    ],
    ids=str,
)
def test_what_the_walk_cannot_tell_is_left_to_the_full_check(value: sp.Expr) -> None:
    assert not _problems(value)
    assert NameScope(SCOPE_VALUES).symbols_if_fine(value, STATE) is None


def test_a_scope_that_has_checked_parts_before_still_finds_every_symbol() -> None:
    scope = NameScope(SCOPE_VALUES)
    scope.check(sp.cos(th) * L, "first", STATE, [])  # its parts are then known fine
    value = xd * sp.cos(th) * L - thd
    assert scope.symbols_if_fine(value, STATE) == value.free_symbols


def test_the_bicycles_constraints_symbols_are_their_free_symbols() -> None:
    system = BENCHMARKS["whipple_bicycle"]()
    values = {"coordinates": system.coordinates, "parameters": system.parameters}
    scope = NameScope(values)
    for constraint in system.constraints:
        found = scope.symbols_if_fine(constraint.expression, STATE)
        assert found == constraint.expression.free_symbols


def test_random_values_are_drawn_in_the_order_of_the_printed_names() -> None:
    rng = random.Random(3)
    names = ["b", "a_1", "a_10", "a_2", "B", "_c", "theta_dot", "Ω", "x"]
    symbols = [sp.Symbol(n) for n in names] + [sp.Dummy("a"), sp.Symbol("q", positive=True)]
    rng.shuffle(symbols)
    drawn = random_values(symbols, random.Random(5))
    reference = random.Random(5)
    expected = {s: reference.uniform(0.3, 1.3) for s in sorted(symbols, key=str)}
    assert list(drawn.items()) == list(expected.items())
