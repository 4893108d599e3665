"""distinct_parts and free_symbols (lagrangian.symbolic.expressions) against SymPy's own walks."""

from __future__ import annotations

import sympy as sp

from lagrangian.symbolic.expressions import distinct_parts, free_symbols

x, y, z, u = sp.symbols("x y z u")
f = sp.Function("f")
SHARED = sp.sqrt(1 - sp.sin(x) ** 2 * sp.cos(y) ** 2)
EXPRESSIONS = [
    sp.Integer(3),
    x,
    sp.sin(x + 1) * (x + 1) + sp.cos(x + 1) ** 2,
    sp.expand((SHARED * sp.cos(z) + x * SHARED + y / SHARED) * (x + y + z)),
    f(x) + sp.Derivative(f(x), x) * y,
    sp.Integral(u * x, (u, 0, 1)) + y,  # u is bound
    sp.Piecewise((x, y > 0), (z, True)),
    sp.Subs(f(u), u, x) + sp.Lambda(u, u + z)(y),
]


def _first_appearances(value: sp.Basic) -> list[sp.Basic]:
    seen: set[sp.Basic] = set()
    order = []
    for part in sp.preorder_traversal(value):
        if part not in seen:
            seen.add(part)
            order.append(part)
    return order


def test_distinct_parts_are_the_preorder_walk_s_first_appearances() -> None:
    for value in EXPRESSIONS:
        assert distinct_parts(value) == _first_appearances(value)


def test_a_shared_part_is_entered_once() -> None:
    value = sp.expand((SHARED + x) ** 4)
    parts = distinct_parts(value)
    assert len(parts) == len(set(parts))
    assert len(parts) < sum(1 for _ in sp.preorder_traversal(value))


def test_free_symbols_are_sympy_s_bound_ones_left_out() -> None:
    for value in EXPRESSIONS:
        assert free_symbols(value) == value.free_symbols
    assert u not in free_symbols(sp.Integral(u * x, (u, 0, 1)))
