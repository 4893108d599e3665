"""The rolling contacts' constraints come back from SymEngine as the expressions SymPy's own
constructors make of them (the shared SympyView skips SymPy's evaluation only where it would
change nothing), and the contact height is kept or left out as the numerical probe of
:mod:`lagrangian.symbolic.probe` decides (identically zero or not)."""

from __future__ import annotations

from typing import Any

import pytest
import sympy as sp

from lagrangian.examples import BENCHMARKS
from lagrangian.model import RigidBody, RollingDisc, System, shape
from lagrangian.model.contact import ContactHeight, NoSlip
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.native import to_symengine
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.sympy_view import sympy_sum_power

x, y, psi, theta, phi, m, r = sp.symbols("x y psi theta phi m r")


def by_sympy(expr: Any, symbols: dict[str, sp.Symbol]) -> sp.Expr:
    """The SymEngine ``expr`` rebuilt by SymPy's own constructors, node by node (the
    reference: SymPy's general evaluation at every sum, product and power)."""
    if expr.is_Add:
        return sp.Add(*[by_sympy(a, symbols) for a in expr.args])
    if expr.is_Mul:
        return sp.Mul(*[by_sympy(a, symbols) for a in expr.args])
    if expr.is_Pow:
        return sp.Pow(*[by_sympy(a, symbols) for a in expr.args])
    leaf = to_sympy(expr)
    return leaf.xreplace({s: symbols.get(s.name, s) for s in leaf.free_symbols})


def test_the_bicycle_constraints_are_what_sympy_makes_of_their_terms() -> None:
    system = BENCHMARKS["whipple_bicycle"]()
    generated = [c for c in system.constraints if isinstance(c, (ContactHeight, NoSlip))]
    assert len(generated) == 5  # the front contact's height, two no-slip pairs
    for constraint in generated:
        expr = constraint.expression
        symbols = {s.name: s for s in expr.free_symbols}
        assert sp.srepr(by_sympy(to_symengine(expr), symbols)) == sp.srepr(expr)
    front = [c.expression for c in generated if c.contact.startswith("front")]
    assert all(e.has(sp.Pow) for e in front)  # the steered wheel's root sqrt(1 - a_z^2)


@pytest.mark.parametrize(
    ("base", "exponent"),
    [
        (1 - (x * y + sp.sin(psi)) ** 2, sp.S.Half),
        (x + y, sp.Rational(-3, 2)),
        (x**2 + y**2, sp.Rational(1, 3)),
        (x * y + sp.sin(psi), sp.Integer(2)),  # a square, a reciprocal: integer exponents
        (x + y, sp.Integer(-1)),
        (1 - (x * y) ** 2, sp.Integer(-3)),
        (x + y, sp.Integer(1)),  # SymPy's evaluation returns the sum itself
        (x + y, sp.Integer(0)),
        (x + sp.I * y, sp.Integer(2)),
        (x + sp.I * y, sp.S.Half),  # an imaginary term: SymPy's evaluation decides
        (2 + sp.sqrt(3), sp.S.Half),  # a number: likewise
        (x + sp.oo, sp.S.Half),
    ],
)
def test_a_power_of_a_sum_is_the_power_sympy_makes(base: sp.Expr, exponent: sp.Expr) -> None:
    root = sympy_sum_power(base, exponent, base.has(sp.I))
    expected = sp.Pow(base, exponent)
    assert sp.srepr(root) == sp.srepr(expected)
    assert root.is_commutative is expected.is_commutative is True
    assert root.is_positive == expected.is_positive
    assert is_zero(root - expected)


def test_a_root_is_made_through_sympy_when_its_sum_may_be_imaginary() -> None:
    """Told the sum has an imaginary term, the root is SymPy's own (which may evaluate)."""
    assert sympy_sum_power(sp.Integer(-4) + x - x, sp.S.Half, imaginary=True) == 2 * sp.I


def _coin(height: sp.Expr) -> System:
    coin = RigidBody(
        "coin",
        m,
        shape("disc", radius=r),
        (x, y, height),
        rotations=[("z", psi), ("x", theta), ("y", phi)],
    )
    return System(
        coordinates=[x, y, psi, theta, phi],
        parameters=[m, r],
        rigid_bodies=[coin],
        rolling=[RollingDisc("coin", r, "y")],
    )


def test_a_contact_height_that_holds_identically_is_left_out() -> None:
    written = _coin(r * sp.cos(theta))
    kinds = [type(c) for c in written.constraints]
    assert kinds == [NoSlip, NoSlip]


def test_a_contact_height_that_does_not_hold_is_a_constraint() -> None:
    z = sp.Symbol("z")
    coin = RigidBody(
        "coin", m, shape("disc", radius=r), (x, y, z), rotations=[("z", psi), ("x", theta)]
    )
    system = System(
        coordinates=[x, y, z, psi, theta],
        parameters=[m, r],
        rigid_bodies=[coin],
        rolling=[RollingDisc("coin", r, "y")],
    )
    heights = [c for c in system.constraints if isinstance(c, ContactHeight)]
    assert len(heights) == 1
    assert sp.simplify(heights[0].expression - (z - r * sp.cos(theta))) == 0
