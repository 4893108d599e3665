"""The guess of a collocation step (lagrangian.numerics.stage_prediction): the prediction
errors of the last steps extrapolated by the polynomial through them (exact for a polynomial
of lower degree, against its value computed by hand), no further than linearly when their
differences grow, and the table emptied when its guess did worse than the plain prediction
or the step size changes."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.numerics.stage_prediction import (
    HISTORY,
    KNOWN,
    corrected_guess,
    forget,
    remember,
)


def march(errors: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The table after the prediction errors ``errors`` (each (s, n)) of successive steps,
    the plain prediction zero, each step guessed first; returns (table, counters, the guess
    for the next step)."""
    s, n = errors[0].shape
    table, counters = np.zeros((HISTORY, s * n)), np.zeros(1, dtype=np.int64)
    plain, guess = np.zeros((s, n)), np.empty((s, n))
    for error in errors:
        corrected_guess(plain, table, counters, guess)
        remember(error, plain, guess, table, counters)
    corrected_guess(plain, table, counters, guess)
    return table, counters, guess


def test_a_polynomial_error_of_lower_degree_is_extrapolated_exactly() -> None:
    # two stages, two coordinates, each entry a cubic in the step number k (whole numbers:
    # exact in binary); the next value is the cubic's at k = 10
    def cubic(k: int) -> np.ndarray:
        return np.array([[k**3 - 2 * k, 5.0], [-(k**2) + 7 * k, 3 * k**3 + k**2]], dtype=float)

    _, counters, guess = march([cubic(k) for k in range(10)])
    assert counters[KNOWN] == HISTORY
    np.testing.assert_array_equal(guess, cubic(10))


def test_growing_differences_are_extrapolated_no_further_than_linearly() -> None:
    # differences that double with their order (a motion too fast for the step): the
    # polynomial through the last eight would add 2 + 4 + ... + 128 to D_n + nabla D_n; the
    # guess stops at the linear extrapolation D_n + nabla D_n
    table = np.array([[(-2.0) ** j] for j in range(HISTORY)])
    counters = np.array([HISTORY], dtype=np.int64)
    plain, guess = np.array([[10.0]]), np.empty((1, 1))
    corrected_guess(plain, table, counters, guess)
    assert guess[0, 0] == 10.0 + 1.0 - 2.0
    # decreasing ones are all taken
    table = np.array([[0.5**j] for j in range(HISTORY)])
    corrected_guess(plain, table, counters, guess)
    assert guess[0, 0] == 10.0 + sum(0.5**j for j in range(HISTORY))


def test_a_guess_worse_than_the_plain_prediction_empties_the_table() -> None:
    table, counters = np.zeros((HISTORY, 1)), np.zeros(1, dtype=np.int64)
    plain = np.zeros((1, 1))
    for k in range(4):
        remember(np.array([[1.0 + k]]), plain, plain, table, counters)
    assert counters[KNOWN] == 4
    # the solution 0.5 from the plain prediction 0, from the guess 5: the guess missed more
    remember(np.array([[0.5]]), plain, np.array([[5.0]]), table, counters)
    assert counters[KNOWN] == 1 and table[0, 0] == 0.5
    guess = np.empty((1, 1))
    corrected_guess(plain, table, counters, guess)
    assert guess[0, 0] == 0.5  # D_n alone


@pytest.mark.parametrize("known", [0, 3])
def test_forget_leaves_the_plain_prediction(known: int) -> None:
    table, counters = np.ones((HISTORY, 2)), np.array([known], dtype=np.int64)
    forget(counters)
    plain, guess = np.array([[1.5, -2.0]]), np.empty((1, 2))
    corrected_guess(plain, table, counters, guess)
    np.testing.assert_array_equal(guess, plain)
