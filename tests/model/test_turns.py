"""Turns of a frame made without SymPy's matrix bookkeeping: the unit axis n / |n| from the
sum of the squares of its entries, as from the matrix's dot product; and a chain of frames
composed with one canonical Builder gives the rotations each composed alone."""

from __future__ import annotations

import pytest
import sympy as sp

from lagrangian.model.rotation import rotation_sequence, unit_axis
from lagrangian.symbolic.canonical import Builder

a, b, c = sp.symbols("a b c")


@pytest.mark.parametrize(
    "axis",
    [(0, 1, 0), (0, 3, 4), (1, 1, 1), (sp.sin(a), 0, sp.cos(a)), (a, b, 1), (1.0, 0, 0)],
)
def test_a_unit_axis_is_n_over_its_length(axis: tuple) -> None:
    n = sp.ImmutableMatrix([sp.sympify(e) for e in axis])
    length_squared = sp.expand(n.dot(n))
    expected = n if length_squared == 1 else n / sp.sqrt(length_squared)
    assert sp.srepr(unit_axis(axis)) == sp.srepr(expected)


def test_a_chain_composed_with_one_builder_is_each_frame_composed_alone() -> None:
    builder = Builder()
    turns = [[("z", a)], [("x", -b)], [("y", c), ("z", -a)], [((0, 1, 1), b)]]
    shared, alone = None, None
    for rotations in turns:
        shared = rotation_sequence(rotations, shared, builder=builder)
        alone = rotation_sequence(rotations, alone)
        assert sp.srepr(shared.matrix) == sp.srepr(alone.matrix)
