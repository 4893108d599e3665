"""Where the Newton iteration of a collocation step starts: the stage velocities of the step
before extrapolated, corrected by the extrapolation of what that prediction missed at the
steps before.  The rule is shared by the NumPy stepper
(:mod:`lagrangian.simulation.variational.stepper`) and the compiled march
(:mod:`lagrangian.numerics.fast.collocation`, which compiles these functions).

The plain prediction P_i = sum_j E_ij V_j^prev (the previous step's collocation polynomial at
this step's nodes, :meth:`lagrangian.simulation.variational.collocation.Tableau.extrapolation`)
misses the solution by D = V - P, O(h^s) (about 1e-6 of the stage positions for gauss6 on a
double pendulum at h = 0.01, 3e-5 for gauss4).  Over steps of one size D is a smooth function
of time (each stage's own sequence), so the D of the last k steps extrapolate it, by the
polynomial through them in Newton's backward form (Hairer, Nørsett & Wanner, Solving ODEs I,
III.1):

    V_guess = P + sum_{j<k} nabla^j D_n,     nabla^0 D_n = D_n,
    nabla^j D_n = nabla^(j-1) D_n - nabla^(j-1) D_(n-1),     k <= HISTORY,

the differences kept in a table updated once a step.  On that double pendulum the guess then
misses by about 1e-9 of the stage positions (median): within SMALL_CORRECTION, so Newton's
first correction, whose error is of its square, ends most steps at one evaluation of the
stages (:mod:`lagrangian.numerics.stage_newton`).  The solution is that of the equations
whatever the start; only the number of iterations changes.  The table starts again at a step
of another size (:func:`step_ratio`), and when its guess missed by more than the plain
prediction did; a guess leaves out the differences of order 2 and more when their sum exceeds
|D_n| + |nabla D_n|, so that a motion too fast for the step, whose differences grow with their
order, is extrapolated no further than linearly.

A guess this close has a residual of the stage equations of about 1e-7 of their terms: above
RESIDUAL_GUARD (1e-8), the residual the iteration accepts.  Newton's first correction, made
with the Jacobian at the guess, leaves a residual of the order of the square of the one
before it, so the iteration takes the residual before that correction against
:data:`NEWTON_RESIDUAL_GUARD` = RESIDUAL_GUARD^(1/2) instead (its correction still below
SMALL_CORRECTION of the stage positions, whose square is below rounding): a step whose guess
is good to 1e-7 of its terms ends at one evaluation of the stages, where RESIDUAL_GUARD asked
for a second (an eighth of the steps of the double pendulum at dt = 0.01, gauss6).

>>> import numpy as np
>>> table, counters = np.zeros((HISTORY, 1)), np.zeros(1, dtype=np.int64)
>>> plain, guess = np.array([[1.0]]), np.empty((1, 1))
>>> for n in range(4):  # D_n = (n + 4)^2 / 64 at one stage of one coordinate
...     corrected_guess(plain, table, counters, guess)
...     remember(plain + (n + 4) ** 2 / 64, plain, guess, table, counters)
>>> corrected_guess(plain, table, counters, guess); float(guess[0, 0]) == 1 + 64 / 64
True
"""

from __future__ import annotations

import numpy as np

from lagrangian.numerics.discrete_lagrangian import RESIDUAL_GUARD

#: The most steps whose prediction errors are extrapolated (the polynomial's degree + 1).
HISTORY = 8
#: counters[KNOWN]: how many differences of the table hold (0 .. HISTORY).
KNOWN = 0
#: Steps whose sizes differ by less than this fraction are of one size (their nodes
#: t0 + k dt differ by rounding): they share one extrapolation and keep the table.
EQUAL_STEPS = 1e-9
#: The residual of the stage equations, relative to their terms, accepted before a
#: correction by the Jacobian at the same iterate (Newton's step, not a reused Jacobian):
#: the residual that correction leaves is of its square, within RESIDUAL_GUARD.
NEWTON_RESIDUAL_GUARD = RESIDUAL_GUARD**0.5


def step_ratio(dt: float, previous: float) -> float:
    """dt / previous, exactly 1 for steps of one size (within EQUAL_STEPS): the ratio of
    the extrapolation to this step's nodes; another ratio starts the table again.

    >>> step_ratio(0.01, 0.01 * (1 + 1e-12)), step_ratio(0.02, 0.01)
    (1.0, 2.0)
    """
    ratio = dt / previous
    return 1.0 if abs(ratio - 1.0) <= EQUAL_STEPS else ratio


def corrected_guess(
    plain: np.ndarray, table: np.ndarray, counters: np.ndarray, guess: np.ndarray
) -> None:
    """guess <- plain + sum_{j<k} nabla^j D_n (module docstring); ``plain`` and ``guess``
    (s, n), ``table`` (HISTORY, s n) its rows the differences.  The differences of order 2
    and more are left out when their sum exceeds |D_n| + |nabla D_n| (largest entries): a
    polynomial that does not hold, whose differences grow."""
    s, n = plain.shape
    known = counters[KNOWN]
    bound, higher = 0.0, 0.0
    for e in range(s * n if known > 1 else 0):
        bound = max(bound, abs(table[0, e]))
        higher = max(higher, abs(table[1, e]))
    bound += higher
    higher = 0.0
    for i in range(s):
        for x in range(n):
            total = 0.0
            for j in range(2, known):
                total += table[j, i * n + x]
            guess[i, x] = total
            higher = max(higher, abs(total))
    whole = higher <= bound
    for i in range(s):
        for x in range(n):
            low = plain[i, x]
            for j in range(min(known, 2)):
                low += table[j, i * n + x]
            guess[i, x] = low + guess[i, x] if whole else low


def remember(
    solved: np.ndarray,
    plain: np.ndarray,
    guess: np.ndarray,
    table: np.ndarray,
    counters: np.ndarray,
) -> None:
    """Add the prediction error D = solved - plain of the step just solved to the difference
    ``table``, after emptying it when ``guess`` missed by more than ``plain`` (module
    docstring)."""
    s, n = plain.shape
    missed_plain, missed_guess = 0.0, 0.0
    for i in range(s):
        for x in range(n):
            missed_plain = max(missed_plain, abs(solved[i, x] - plain[i, x]))
            missed_guess = max(missed_guess, abs(solved[i, x] - guess[i, x]))
    if not missed_guess <= missed_plain:  # NaN too
        counters[KNOWN] = 0
    orders = min(counters[KNOWN] + 1, table.shape[0])
    for i in range(s):
        for x in range(n):
            e = i * n + x
            newer = solved[i, x] - plain[i, x]
            for j in range(orders):
                older = table[j, e]
                table[j, e] = newer
                newer = newer - older
    counters[KNOWN] = orders


def forget(counters: np.ndarray) -> None:
    """Empty the table (a step of another size: its prediction errors are others)."""
    counters[KNOWN] = 0
