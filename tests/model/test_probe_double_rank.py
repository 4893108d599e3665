"""generic_rank evaluates a matrix in double precision (SymEngine) and gives the rank that the
same random point evaluated by SymPy to 30 digits gives; where the double values are not
finite and real it falls back to that evaluation."""

from __future__ import annotations

import random

import numpy as np
import sympy as sp

import lagrangian as lg
from lagrangian.symbolic.probe import (
    DIGITS,
    SEED,
    generic_rank,
    numeric_rank,
    random_values,
)


def thirty_digit_rank(matrix: sp.MatrixBase) -> int:
    """The rank at the probe's point, the entries evaluated by SymPy to 30 digits."""
    point = random_values(matrix.free_symbols, random.Random(SEED))
    exact = {s: sp.Float(v, DIGITS) for s, v in point.items()}
    numbers = np.array(matrix.xreplace(exact).evalf(DIGITS).tolist(), dtype=complex)
    return numeric_rank(numbers.real)


def test_chain_mass_matrix_has_full_rank_as_at_thirty_digits() -> None:
    mass = lg.derive(lg.examples.n_link_pendulum(12)).mass_matrix
    assert generic_rank(mass) == thirty_digit_rank(mass) == 12


def test_rank_deficient_products_are_found() -> None:
    # u v^T has rank 1 whatever u and v; the sum of two has rank 2 (3 x 3, entries of order 1)
    x, y, z = sp.symbols("x y z")
    u = sp.Matrix([sp.cos(x), sp.sin(y), x * z])
    v = sp.Matrix([1 + y, sp.exp(z), sp.sqrt(x)])
    w = sp.Matrix([z, 1, sp.cos(y)])
    assert generic_rank(u * v.T) == thirty_digit_rank(u * v.T) == 1
    assert generic_rank(u * v.T + w * u.T) == thirty_digit_rank(u * v.T + w * u.T) == 2


def test_values_not_real_fall_back_to_thirty_digits() -> None:
    # sqrt(x - 5) is imaginary on the probe's interval: the 30-digit values' real parts count
    x = sp.Symbol("x")
    matrix = sp.Matrix([[sp.sqrt(x - 5), 1], [2 * sp.sqrt(x - 5), 1]])
    assert generic_rank(matrix) == thirty_digit_rank(matrix) == 1


def test_given_values_fix_the_point() -> None:
    x, y = sp.symbols("x y")
    matrix = sp.Matrix([[x, y], [y, x]])
    assert generic_rank(matrix) == 2
    assert generic_rank(matrix, {x: 0.5, y: 0.5}) == 1
    assert generic_rank(matrix, {x: sp.Rational(1, 2), y: sp.Float(0.5)}) == 1


def test_a_derived_matrix_is_evaluated_from_its_kept_symengine_entries() -> None:
    # the SymEngine entries a derivation converted M from give the same numbers as M's own
    # (SymPy's, to 30 digits), without converting M back
    from lagrangian.symbolic.probe import _double_values
    from lagrangian.symbolic.sympy_view import backend_entries

    eom = lg.derive(lg.examples.n_link_pendulum(6))
    matrix = eom.mass_matrix
    assert backend_entries(matrix) is not None  # the case this test is about
    point = random_values(matrix.free_symbols, random.Random(SEED))
    exact = {s: sp.Float(v, DIGITS) for s, v in point.items()}
    reference = np.array(matrix.xreplace(exact).evalf(DIGITS).tolist(), dtype=float)
    assert np.allclose(_double_values(matrix, point), reference, rtol=1e-13, atol=1e-13)
    assert generic_rank(matrix) == thirty_digit_rank(matrix) == 6
