"""Impacts on unilateral constraints: the impulsive Lagrange equations with Newton's law of
restitution, several contacts at once as a linear complementarity problem.

At an impact the positions are continuous and the velocities jump.  Integrating the equations
of motion M q_ddot = forcing + A^T lambda over the vanishing duration of the impact leaves only
the impulses Lambda of the constraint forces (Pfeiffer & Glocker, *Multibody Dynamics with
Unilateral Contacts*, 1996, ch. 7; Brogliato, *Nonsmooth Mechanics*, 3rd ed., 2016, §4.2):

    M(q) (q_dot+ - q_dot-) = A^T Lambda,
    a_j q_dot+ + b_j = 0                                   every bilateral constraint j,
    w_i = g_dot_i+ + e_i g_dot_i- >= 0,  Lambda_i >= 0,  w_i Lambda_i = 0
                                                           every unilateral constraint i touching,

with g_dot = a q_dot + b the rate of a constraint (a its Jacobian row, b = dg/dt) and e_i its
coefficient of restitution (Newton's law: a single contact leaves with g_dot+ = -e g_dot-).  An
impulse only pushes (Lambda_i >= 0) and acts only on a contact that would otherwise close
(complementarity).  The problem is solved by its active sets: for each set S of touching
constraints that take an impulse, the linear system

    [ M    -A_W^T ] [ q_dot+   ]   [ M q_dot-            ]
    [ A_W    0    ] [ Lambda_W ] = [ -e_S g_dot_S- - b_W ],     W = bilateral + S,

(e = 0 for the bilateral rows) is solved, and the first S whose impulses push and whose other
contacts do not close is the answer (the sets are tried smallest first: a lone impact is one
solve).  With e = 1 and scleronomic constraints the kinetic energy is the same after as before;
with e < 1 it is lost, never gained.

>>> import numpy as np
>>> mass = np.diag([1.0, 3.0])                       # two carts on a line, x1 < x2
>>> jacobian = np.array([[-1.0, 1.0]])               # g = x2 - x1 >= 0
>>> v = np.array([2.0, 0.0])                         # cart 1 runs into cart 2
>>> after, impulses = resolve(mass, jacobian, jacobian @ v, [], [0], [1.0], v)
>>> after, impulses          # elastic: v1 = (m1 - m2)/(m1 + m2) v, v2 = 2 m1/(m1 + m2) v
(array([-1.,  1.]), array([3.]))
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from lagrangian.errors import SimulationError

#: Up to this many touching contacts the active sets are enumerated (smallest first: a lone
#: impact is one solve); beyond it Lemke's pivoting solves the complementarity problem.
ENUMERATED_CONTACTS = 8
#: Slack of the sign conditions, relative to the size of the velocities and impulses.
SIGN_TOLERANCE = 1e-10


class ImpactRecord(NamedTuple):
    """One impact as an integration records it: the time, the unilateral constraints that took
    an impulse (names) and their impulses, the states [q; q_dot] before and after, and the
    constraints that came to rest in it (their bounces accumulate: the contact persists)."""

    t: float
    constraints: tuple[str, ...]
    impulses: tuple[float, ...]
    before: np.ndarray
    after: np.ndarray
    rest: tuple[str, ...] = ()


def resolve(
    mass: np.ndarray,
    jacobian: np.ndarray,
    rates: np.ndarray,
    bilateral: Sequence[int],
    touching: Sequence[int],
    restitution: Sequence[float],
    v: np.ndarray,
    inverse_mass: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(q_dot+, Lambda) of the impact (module docstring) at the velocities ``v``.

    ``jacobian`` holds the rows a_j of the constraints and ``rates`` their g_dot- = a_j v + b_j;
    ``bilateral`` and ``touching`` index them; ``restitution`` is e of each touching one;
    ``inverse_mass`` is M^-1 when the caller has it (a constant mass matrix).  Lambda has one
    entry per row of ``jacobian`` (0 for those not involved).

    Solved in the velocities' jump dq_dot = M^-1 A^T Lambda: with the Delassus matrix
    W = A M^-1 A^T of the rows involved the conditions read W Lambda = -(1 + e) g_dot- on the
    rows that take an impulse (e = 0 for the bilateral ones), a problem the size of the
    contacts, not of the coordinates.  SimulationError when no active set solves it (dependent
    constraints).
    """
    rows = [*bilateral, *touching]
    a = jacobian[rows]
    mobility = inverse_mass @ a.T if inverse_mass is not None else np.linalg.solve(mass, a.T)
    delassus = a @ mobility
    e = np.array([0.0] * len(bilateral) + list(restitution))
    wanted = -(1.0 + e) * rates[rows]  # the change of each rate its impulse must bring
    scale = max(float(np.max(np.abs(rates[rows]), initial=0.0)), 1e-300)
    local = _local_impulses(delassus, wanted, len(bilateral), scale)
    impulses = np.zeros(len(jacobian))
    impulses[rows] = local
    return v + mobility @ local, impulses


def _local_impulses(
    delassus: np.ndarray, wanted: np.ndarray, free: int, scale: float
) -> np.ndarray:
    """The impulses of the rows of ``delassus`` (the first ``free`` bilateral, any sign; the
    others pushing, each on a contact that would otherwise close): enumerated active sets for
    a few contacts, Lemke's method on the contacts' Schur complement for many."""
    contacts = len(wanted) - free
    if contacts == 1 and not free and delassus[0, 0] > 0:
        # one contact alone, Lambda = -(1 + e) g_dot- / (a M^-1 a^T): the enumeration's
        # answer (no impulse when it does not close) without its checks
        closing = wanted[0] > SIGN_TOLERANCE * scale
        return wanted / delassus[0, 0] if closing else np.zeros(1)
    if contacts <= ENUMERATED_CONTACTS:
        for size in range(contacts + 1):
            for chosen in itertools.combinations(range(free, len(wanted)), size):
                found = _with_impulses(delassus, wanted, [*range(free), *chosen], scale, free)
                if found is not None:
                    return found
    else:
        found = _complementary_by_pivoting(delassus, wanted, free, scale)
        if found is not None:
            return found
    raise SimulationError(
        "no impulses resolve the impact: the constraints touching are dependent there"
    )


def _with_impulses(
    delassus: np.ndarray, wanted: np.ndarray, chosen: list[int], scale: float, free: int
) -> np.ndarray | None:
    """The impulses with ``chosen`` rows taking one (each meeting its velocity condition),
    when they push and no other contact closes; None when they do not, or the rows are
    dependent."""
    impulses = np.zeros(len(wanted))
    if len(chosen) == 1:  # a lone contact: no factorization
        (k,) = chosen
        if delassus[k, k] == 0:
            return None
        impulses[k] = wanted[k] / delassus[k, k]
    elif chosen:
        try:
            impulses[chosen] = np.linalg.solve(delassus[np.ix_(chosen, chosen)], wanted[chosen])
        except np.linalg.LinAlgError:
            return None
    return impulses if _complementary(delassus, wanted, impulses, chosen, scale, free) else None


def _complementary(
    delassus: np.ndarray,
    wanted: np.ndarray,
    impulses: np.ndarray,
    chosen: list[int],
    scale: float,
    free: int,
) -> bool:
    """Whether the chosen contacts' impulses push and every other contact leaves: the rate
    change W Lambda is at least the one -(1 + e) g_dot- that Newton's law asks (the first
    ``free`` rows are bilateral, always chosen)."""
    tolerance = SIGN_TOLERANCE * (scale + float(np.max(np.abs(impulses), initial=0.0)))
    others = np.ones(len(wanted), dtype=bool)
    others[chosen] = False
    contacts = [i for i in chosen if i >= free]  # the bilateral impulses take any sign
    pushing = np.all(impulses[contacts] >= -tolerance) if contacts else True
    return bool(pushing and np.all((delassus @ impulses - wanted)[others] >= -tolerance))


def _complementary_by_pivoting(
    delassus: np.ndarray, wanted: np.ndarray, free: int, scale: float
) -> np.ndarray | None:
    """The impulses by Lemke's method (Cottle, Pang & Stone, *The Linear Complementarity
    Problem*, 1992, §4.4) after the bilateral rows are solved out (their Schur complement):

        w = S Lambda_c + r >= 0,  Lambda_c >= 0,  w . Lambda_c = 0,

    S = W_cc - W_cb W_bb^-1 W_bc, r = -wanted_c + W_cb W_bb^-1 wanted_b.  S is positive
    semi-definite, for which Lemke's method ends with a solution when one exists."""
    b, c = slice(0, free), slice(free, len(wanted))
    if free:
        try:
            through = np.linalg.solve(delassus[b, b], np.column_stack((delassus[b, c], wanted[b])))
        except np.linalg.LinAlgError:
            return None
        schur = delassus[c, c] - delassus[c, b] @ through[:, :-1]
        offset = -wanted[c] + delassus[c, b] @ through[:, -1]
    else:
        schur, offset = delassus[c, c], -wanted[c]
    pushes = lemke(schur, offset, SIGN_TOLERANCE * scale)
    if pushes is None:
        return None
    impulses = np.zeros(len(wanted))
    impulses[c] = pushes
    if free:
        impulses[b] = through[:, -1] - through[:, :-1] @ pushes
    chosen = [*range(free), *(free + i for i in np.flatnonzero(pushes > 0))]
    return impulses if _complementary(delassus, wanted, impulses, chosen, scale, free) else None


def lemke(matrix: np.ndarray, offset: np.ndarray, tolerance: float) -> np.ndarray | None:
    """z >= 0 with w = matrix z + offset >= 0 and w . z = 0 (Lemke's complementary pivoting
    with the covering vector 1), or None when the pivoting ends on a ray.

    >>> lemke(np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, -1.0]), 1e-12)
    array([0.33333333, 0.33333333])
    """
    k = len(offset)
    if np.all(offset >= -tolerance):
        return np.zeros(k)
    # tableau of w - M z - z0 1 = q: basis starts with every w
    tableau = np.hstack((np.eye(k), -matrix, -np.ones((k, 1)), offset[:, None]))
    basis = list(range(k))
    entering = 2 * k  # z0
    row = int(np.argmin(offset))
    for _ in range(50 * (k + 1)):
        tableau[row] /= tableau[row, entering]
        others = np.arange(k) != row
        tableau[others] -= np.outer(tableau[others, entering], tableau[row])
        leaving, basis[row] = basis[row], entering
        if leaving == 2 * k:  # z0 left the basis: a solution
            z = np.zeros(k)
            for r, var in enumerate(basis):
                if k <= var < 2 * k:
                    z[var - k] = tableau[r, -1]
            return z
        entering = leaving + k if leaving < k else leaving - k  # the complement
        column = tableau[:, entering]
        positive = column > tolerance
        ratios = np.where(positive, tableau[:, -1] / np.where(positive, column, 1.0), np.inf)
        if not np.isfinite(ratios).any():
            return None  # a ray: no solution along this path
        row = int(np.argmin(ratios))
    return None
