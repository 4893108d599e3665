"""The numerical checks of an inertia tensor: its symmetry compared entry by entry (the
differences built only where two entries differ) and its numbers read off the samples where
an entry is a parameter, its negative or an integer, the same doubles as the 30-digit
evaluation gives."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp

from lagrangian.model.inertia import _asymmetric, check_inertia
from lagrangian.model.rotation import evaluate_matrix

a, b, c, d = sp.symbols("a b c d")


def _by_30_digits(matrix: sp.Matrix, values: dict[sp.Symbol, float]) -> np.ndarray:
    exact = {s: sp.Float(v, 30) for s, v in values.items()}
    return np.array([complex(e.xreplace(exact).evalf(30)) for e in matrix]).real.reshape(3, 3)


@pytest.mark.parametrize("seed", range(20))
def test_entries_read_off_are_the_30_digit_values(seed: int) -> None:
    rng = random.Random(seed)
    choices = [a, -b, c, -d, sp.Integer(0), sp.Integer(-3), sp.Integer(7)]
    matrix = sp.Matrix(3, 3, [rng.choice(choices) for _ in range(9)])
    values = {s: rng.uniform(-1e3, 1e3) * 10 ** rng.randint(-12, 12) for s in (a, b, c, d)}
    values[d] = rng.randint(-(10**17), 10**17)  # an integer value, beyond a double's 2**53
    found = evaluate_matrix(matrix, values)
    assert found is not None
    assert np.array_equal(found, _by_30_digits(matrix, values))


def test_an_entry_not_read_off_is_evaluated() -> None:
    matrix = sp.Matrix([[a * b, 0, 0], [0, a / 3, 0], [0, 0, a + b]])
    values = {a: 0.1, b: 0.7}
    assert np.array_equal(evaluate_matrix(matrix, values), _by_30_digits(matrix, values))
    assert evaluate_matrix(matrix, {a: 0.1}) is None  # b has no value


@pytest.mark.parametrize(
    ("matrix", "asymmetric"),
    [
        (sp.Matrix([[a, b, 0], [b, a, 0], [0, 0, c]]), False),
        (sp.Matrix([[a, b * (c + 1), 0], [b * c + b, a, 0], [0, 0, c]]), False),  # written apart
        (sp.Matrix([[a, b, 0], [c, a, 0], [0, 0, c]]), True),
        (sp.Matrix([[a, 0, b], [0, a, 0], [-b, 0, c]]), True),
    ],
)
def test_symmetry_is_compared_entry_by_entry(matrix: sp.Matrix, asymmetric: bool) -> None:
    values = {a: 2.0, b: 0.5, c: 1.5}
    assert _asymmetric(matrix, values) is asymmetric
    problems = check_inertia(matrix, "I", values)
    assert any("not symmetric" in p.message for p in problems) is asymmetric


@pytest.mark.parametrize("shape", [(2, 3), (3, 2)])
def test_a_tensor_not_square_is_a_problem_named_with_its_shape(shape: tuple[int, int]) -> None:
    problems = check_inertia(sp.ones(*shape), "rigid_bodies[0].inertia", {})
    assert [p.field for p in problems] == ["rigid_bodies[0].inertia"]
    assert f"{shape[0]}x{shape[1]}, not square" in problems[0].message
    assert "3x3" in problems[0].fix
