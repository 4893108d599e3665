"""SumPrinter writes what SymPy's StrPrinter writes, KeptLatexPrinter what its LatexPrinter
writes and OrderedPresentationPrinter and KeptPresentationPrinter what its presentation MathML
printer writes, character for character; Dotted writes what that printer writes of the
expression with its velocities and accelerations renamed (``xreplace``).

The reference is StrPrinter itself, with SumPrinter's one rule on top (a sum of more than
SORTED_TERMS terms, and a product holding one, in SymPy's order): every example's
expressions, a chain long enough for that rule, hand-picked corner cases of StrPrinter, and
expressions Hypothesis builds. Each is printed by a fresh printer and by one printer shared
over the whole corpus, so that what one expression leaves in the printer's memory cannot
change the text of another.
"""

from __future__ import annotations

import re
from types import SimpleNamespace
from typing import Any

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sympy.physics import units
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.str import StrPrinter

import lagrangian as lg
from lagrangian import examples
from lagrangian.render.latex import KeptLatexPrinter, symbol_names
from lagrangian.render.mathml import (
    NAMED_ENTITIES,
    Dotted,
    KeptPresentationPrinter,
    OrderedPresentationPrinter,
)
from lagrangian.render.text import SORTED_TERMS, SumPrinter


class ReferencePrinter(StrPrinter):
    """StrPrinter with the long-sum rule of SumPrinter, and nothing kept between calls."""

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> str:
        order = order or self.order
        if order is None and len(expr.args) > SORTED_TERMS:
            order = "none"
        return super()._print_Add(expr, order)

    def _print_Mul(self, expr: sp.Mul) -> str:
        if self.order is None and any(a.is_Add and len(a.args) > SORTED_TERMS for a in expr.args):
            self._settings["order"] = "none"
            try:
                return super()._print_Mul(expr)
            finally:
                self._settings["order"] = None
        return super()._print_Mul(expr)


ORDERS: list[dict[str, Any] | None] = [None, {"order": "none"}]


def _expressions(eom: lg.EquationsOfMotion) -> list[sp.Basic]:
    exprs: list[sp.Basic] = [
        eom.kinetic_energy,
        eom.potential_energy,
        eom.velocity_potential,
        eom.dissipation_function,
        eom.lagrangian,
        *eom.equations,
        *eom.mass_matrix,
        *eom.forcing,
        *eom.coriolis,
        *eom.time_terms,
        *eom.gravity,
        *eom.generalized_forces,
        *eom.dissipation_forces,
    ]
    for s in eom.steps:
        exprs += [s.dL_dvelocity, s.ddt_dL_dvelocity, s.dL_dcoordinate, s.dF_dvelocity, s.equation]
    return exprs


def _presentation(expr: sp.Basic, printer: OrderedPresentationPrinter | None = None) -> str:
    """The MathML, or the name of the error SymPy's printer raises on ``expr``."""
    try:
        if printer is None:
            return str(sp.mathml(expr, printer="presentation"))
        return printer.doprint(expr)
    except Exception as error:  # SymPy cannot write it: the same failure is the same output
        return type(error).__name__


def _assert_same(exprs: list[sp.Basic], names: dict[sp.Symbol, str] | None = None) -> None:
    for options in ORDERS:
        shared = SumPrinter(options)
        for expr in exprs:
            expected = ReferencePrinter(options).doprint(expr)
            assert SumPrinter(options).doprint(expr) == expected, expr
            assert shared.doprint(expr) == expected, expr
    shared_mathml = OrderedPresentationPrinter()
    shared_kept = KeptPresentationPrinter()
    for expr in exprs:
        expected = _presentation(expr)
        assert _presentation(expr, OrderedPresentationPrinter()) == expected, expr
        assert _presentation(expr, shared_mathml) == expected, expr
        assert _presentation(expr, KeptPresentationPrinter()) == expected, expr
        assert _presentation(expr, shared_kept) == expected, expr
    settings = {"symbol_names": names or {}}
    shared_latex = KeptLatexPrinter(settings)
    for expr in exprs:
        expected = sp.latex(expr, symbol_names=names or {})
        assert KeptLatexPrinter(settings).doprint(expr) == expected, expr
        assert shared_latex.doprint(expr) == expected, expr


class LowPrecedence(sp.Function):
    """A function written with a sum's precedence (precedence_Mul looks for one)."""

    precedence = PRECEDENCE["Add"]


x, y, z, t = sp.symbols("x y z t")
a, b = sp.symbols("a b", positive=True)
A, B = sp.symbols("A B", commutative=False)
f = sp.Function("f")
CORNER_CASES: list[sp.Basic] = [
    sp.Integer(0),
    sp.Integer(-3),
    sp.Rational(-2, 3),
    sp.Float(0.25),
    sp.Float(-1.5) * x,
    x + sp.Float("0.1", 30),
    x + sp.Float(0.1),
    x + sp.Float(0.1, 30),
    -x,
    -x - y,
    1 - x,
    2 - 3 * x,
    -1 + x,
    sp.pi - x,
    x / 2,
    -x / 2,
    -3 * x / 4,
    x**2 / (2 * y),
    x / (y * z),
    1 / x,
    -1 / x,
    1 / (x * y),
    1 / (x**2 * y),
    (x * y) ** -1,
    sp.Pow(x * y, -1, evaluate=False),
    x ** sp.Rational(-1, 2),
    x ** sp.Rational(3, 2),
    x ** (-y),
    x ** (-2 * y),
    x**y * z ** (-y),
    sp.sqrt(x),
    sp.sqrt(2) * x,
    2 * sp.sqrt(3) / 3,
    sp.exp(x) + x,
    sp.E**x * y,
    sp.exp(-x) * sp.sin(x),
    (x + y) ** 2,
    (x + y) ** -2,
    (x - y) ** 3 * (x + 1),
    sp.sin(x - y) * sp.cos(y - x),
    sp.sin(x) ** 2 + sp.cos(x) ** 2 * y,
    sp.atan2(y, x) + sp.Abs(x),
    f(t) + f(t).diff(t) * x,
    sp.Derivative(f(t), t, 2) - x,
    sp.I * x + y,
    -sp.I * x,
    (1 + sp.I) * x,
    sp.oo * x,
    -sp.oo * x,
    sp.zoo * x,
    x + sp.O(x**3),
    A * B + B * A,
    -2 * x * A * B,
    sp.Mul(2, x, 3, evaluate=False),
    sp.Mul(-2, sp.zoo, x, evaluate=False) + y,
    sp.Mul(-3, x, sp.Float(2.0), evaluate=False) - y,
    -sp.Float(2.5) * x * y + z,
    -sp.oo * x * y - z,
    sp.Mul(1, x, evaluate=False),
    sp.Mul(x, sp.Pow(2, 3, evaluate=False), evaluate=False),
    sp.Add(x, x, evaluate=False),
    sp.Piecewise((x, x > 0), (-x, True)),
    sp.Mod(x, 3) * y + x,
    3 * units.meter * x / units.second + units.speed_of_light * y,
    sp.Eq(x, y),
    sp.Matrix([[x + y, -x], [x / 2, y**2]]),
    sp.Tuple(x + 1, -y),
    a * b - sp.Symbol("a") * b,
    sp.Dummy("d") + x,
    # sorted, then in SymPy's order inside a product with a long sum, then sorted again
    sp.sin(x**2 + x + 1) * y,
    sp.Add(*sp.symbols(f"m1:{SORTED_TERMS + 5}")) * sp.sin(x**2 + x + 1) * (x**2 + x + 1),
    sp.sin(x**2 + x + 1) * (x**2 + x + 1) * z,
    sp.Add(*sp.symbols(f"m1:{SORTED_TERMS + 5}")) * (x - y) + x * y,
    sp.Add(*sp.symbols(f"m1:{SORTED_TERMS + 5}")) / 2 + sp.Add(*sp.symbols("k1:4")) * x,
    sum(sp.Rational(k, 7) * x**k for k in range(-3, 8)),
    sum((-1) ** k * sp.Symbol(f"x{k}") ** (k % 3 + 1) for k in range(SORTED_TERMS + 3)),
    # products of plain factors after at most a -1 (SumPrinter._plain_product), and products
    # next to them that are not: the same factors in other products and precedences
    x * y * (x + z) * sp.cos(x - y) - x * z * (x + z) * sp.sin(x - y),
    -x * y * (x + z) * sp.cos(x - y) + x * y**2 * (x + z),
    -x * (x + z) + x * y * (x + z) ** 2 / z - 2 * x * (x + z),
    -x * sp.Add(*sp.symbols(f"m1:{SORTED_TERMS + 5}")) * y + x * sp.sin(x) * y,
    -x * y * A * B + x * y * B,
    -x * y * LowPrecedence(x) + x * y * LowPrecedence(y) + LowPrecedence(x) * z,
    -x * sp.Mod(x, 3) * LowPrecedence(y) + x * sp.Mod(x, 3),
    -x * sp.Pow(2, 3, evaluate=False) * y + x * y,
]


def test_corner_cases_of_the_string_printer() -> None:
    _assert_same(CORNER_CASES)


@pytest.mark.parametrize("name", sorted(examples.CATALOG))
def test_every_example_prints_as_sympy_does(name: str) -> None:
    eom = lg.derive(examples.get(name)())
    _assert_same(_expressions(eom), symbol_names(eom.coordinates))


@pytest.mark.parametrize(
    "links",
    [
        12,
        # the m_1 + ... + m_n of its first links are written unsorted
        pytest.param(SORTED_TERMS + 3, marks=pytest.mark.slow),
    ],
)
def test_a_chain_prints_as_sympy_does(links: int) -> None:
    eom = lg.derive(examples.get("n_link_pendulum")(links))
    first = eom.steps[0]
    names = symbol_names(eom.coordinates)
    _assert_same(
        [
            *eom.equations,
            eom.lagrangian,
            first.dL_dvelocity,
            first.ddt_dL_dvelocity,
            first.dL_dcoordinate,
            *eom.mass_matrix.row(0),
            *eom.forcing,
        ],
        names,
    )


SYMBOLS = sp.symbols("x y z m1 m2 theta1 theta2")
atoms = st.one_of(
    st.sampled_from(SYMBOLS),
    st.integers(-4, 4).map(sp.Integer),
    st.fractions(min_value=-3, max_value=3, max_denominator=5).map(sp.Rational),
)


def _combine(children: st.SearchStrategy[sp.Expr]) -> st.SearchStrategy[sp.Expr]:
    pair = st.tuples(children, children)
    return st.one_of(
        pair.map(lambda p: p[0] + p[1]),
        pair.map(lambda p: p[0] - p[1]),
        pair.map(lambda p: p[0] * p[1]),
        pair.map(lambda p: p[0] / p[1] if p[1] != 0 else p[0]),
        st.tuples(children, st.integers(-3, 3)).map(lambda p: p[0] ** p[1] if p[0] != 0 else p[0]),
        children.map(sp.sin),
        children.map(sp.cos),
        children.map(sp.sqrt),
        children.map(lambda e: -e),
    )


expressions = st.recursive(atoms, _combine, max_leaves=12)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(expressions, min_size=1, max_size=4))
def test_generated_expressions_print_as_sympy_does(exprs: list[sp.Expr]) -> None:
    _assert_same(exprs)


def _dotted_reference(dotted: Dotted, expr: Any) -> str:
    """What Dotted writes, from ``xreplace`` and SymPy's own printer."""
    text = str(sp.mathml(sp.sympify(expr).xreplace(dotted.swap), printer="presentation"))
    text = re.sub(r"<mi>lgdotted[a-z]+</mi>", lambda m: dotted.markup.get(m[0], m[0]), text)
    for entity, code in NAMED_ENTITIES.items():
        text = text.replace(entity, code)
    return text


def _written(write: Any, *args: Any) -> str:
    """What ``write(*args)`` returns, or the name of the error it raises."""
    try:
        return str(write(*args))
    except Exception as error:  # the same failure is the same output
        return type(error).__name__


def _assert_dotted(coordinates: Any, exprs: list[Any]) -> None:
    shared = Dotted(coordinates)
    for expr in exprs:
        expected = _written(_dotted_reference, shared, expr)
        assert _written(Dotted(coordinates), expr) == expected, expr
        assert _written(shared, expr) == expected, expr


@pytest.mark.parametrize("name", sorted(examples.CATALOG))
def test_every_example_is_dotted_as_sympy_prints_it(name: str) -> None:
    eom = lg.derive(examples.get(name)())
    _assert_dotted(eom, [*_expressions(eom), eom.mass_matrix, eom.forcing])


def test_a_chain_is_dotted_as_sympy_prints_it() -> None:
    eom = lg.derive(examples.get("n_link_pendulum")(12))
    first = eom.steps[0]
    exprs = [*eom.equations, eom.lagrangian, first.ddt_dL_dvelocity, eom.mass_matrix]
    _assert_dotted(eom, [*exprs, eom.forcing, sp.Matrix(eom.accelerations)])


DOTTED = SimpleNamespace(
    coordinates=sp.symbols("theta1 theta2"),
    velocities=sp.symbols("theta1_dot theta2_dot"),
    accelerations=sp.symbols("theta1_ddot theta2_ddot"),
)
# the velocities and accelerations in place of x, y and z
RENAMED = dict(zip(SYMBOLS[:3], (*DOTTED.velocities, DOTTED.accelerations[0])))


def test_corner_cases_are_dotted_as_sympy_prints_them() -> None:
    _assert_dotted(DOTTED, [sp.sympify(e).xreplace(RENAMED) for e in CORNER_CASES])


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(expressions, min_size=1, max_size=4))
def test_generated_expressions_are_dotted_as_sympy_prints_them(exprs: list[sp.Expr]) -> None:
    _assert_dotted(DOTTED, [e.xreplace(RENAMED) for e in exprs])
