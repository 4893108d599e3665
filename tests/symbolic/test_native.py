"""SymPy functions that SymEngine has no class for go into it as function symbols, so that
SymEngine never calls back into SymPy (where a time limit's exception would kill the process),
and come back as the SymPy functions they were."""

from __future__ import annotations

import symengine as se
import sympy as sp
from symengine.lib.symengine_wrapper import PyFunction

import lagrangian as lg
from lagrangian.symbolic.native import restore_functions, to_symengine, to_symengine_sharing
from lagrangian.symbolic.objects import sympy_object

x, y = sp.symbols("x y")


def test_functions_symengine_lacks_become_function_symbols_and_come_back():
    expr = sp.Heaviside(x**3, evaluate=False) * sp.besselj(1, y) + sp.sin(x) + sp.Abs(y)
    fast = to_symengine(expr)
    assert not fast.atoms(PyFunction)
    assert sympy_object(fast) == expr


def test_their_derivatives_are_taken_in_symengine_and_resolved_in_sympy():
    fast = to_symengine(sp.besselj(1, x**2)).diff(se.Symbol("x"))
    assert not fast.atoms(PyFunction)
    back = restore_functions(sp.sympify(fast, strict=True)).doit()
    assert sp.simplify(back - sp.besselj(1, x**2).diff(x)) == 0


def test_expressions_without_such_functions_are_left_as_they_are():
    assert to_symengine(sp.sin(x) + 2) == se.sin(se.Symbol("x")) + 2
    assert to_symengine(3) == 3
    assert restore_functions(sp.Heaviside(x)) == sp.Heaviside(x)


def test_a_step_of_a_high_power_derives_at_once():
    # SymPy's derivative, DiracDelta(x**999), splits x**999 into real and imaginary parts
    # for minutes; the almost-everywhere derivative of a step is 0
    system = lg.loads(
        '{"coordinates": ["x"], "kinetic": "x_dot**2/2", '
        '"potential": "Heaviside(x**999) + x**2*Heaviside(x - 1)"}',
        format="json",
    )
    eom = lg.derive(system, time_limit=20)
    assert eom.forcing[0] == -2 * x * sp.Heaviside(x - 1)


def test_a_product_multiplied_out_converts_as_a_whole_does_each_part_once():
    a, b, c = sp.symbols("a b c")
    rz = sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])
    rx = sp.Matrix([[1, 0, 0], [0, sp.cos(b), -sp.sin(b)], [0, sp.sin(b), sp.cos(b)]])
    entries = [*(rz * rx * rz.subs(a, c)), sp.Heaviside(x**3, evaluate=False) * (x + y) ** 2]
    memo: dict = {}
    shared = [to_symengine_sharing(e, memo) for e in entries]
    assert shared == [to_symengine(e) for e in entries]  # the same SymEngine expressions
    assert not shared[-1].atoms(PyFunction)  # a SymPy-only function as its stand-in
    # each distinct part converted once: the memo holds the distinct subexpressions only
    distinct = set().union(*(sp.preorder_traversal(e) for e in entries))
    assert len(memo) <= len(distinct)
    assert to_symengine_sharing(entries[0], memo) is shared[0]  # remembered, not made again
