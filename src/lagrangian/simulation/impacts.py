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

#: The most unilateral constraints one impact may involve (their active sets are enumerated).
MAX_CONTACTS = 12
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
) -> tuple[np.ndarray, np.ndarray]:
    """(q_dot+, Lambda) of the impact (module docstring) at the velocities ``v``.

    ``jacobian`` holds the rows a_j of every constraint and ``rates`` their g_dot- = a_j v + b_j;
    ``bilateral`` and ``touching`` index them; ``restitution`` is e of each touching one.
    Lambda has one entry per row of ``jacobian`` (0 for those not involved).  SimulationError
    when no active set solves the problem (dependent constraints) or there are too many.
    """
    if len(touching) > MAX_CONTACTS:
        raise SimulationError(
            f"{len(touching)} unilateral constraints touch at one impact, more than "
            f"{MAX_CONTACTS}: impacts of that many contacts at once are not supported"
        )
    b = rates - jacobian @ v
    e = dict(zip(touching, restitution, strict=True))
    scale = max(float(np.max(np.abs(rates), initial=0.0)), 1e-300)
    for size in range(len(touching) + 1):
        for chosen in itertools.combinations(touching, size):
            solved = _with_impulses(mass, jacobian, b, rates, [*bilateral, *chosen], e, v)
            if solved is None:
                continue
            after, impulses = solved
            if _complementary(jacobian, b, rates, after, impulses, chosen, touching, e, scale):
                return after, impulses
    raise SimulationError(
        "no impulses resolve the impact: the constraints touching are dependent there"
    )


def _with_impulses(
    mass: np.ndarray,
    jacobian: np.ndarray,
    b: np.ndarray,
    rates: np.ndarray,
    rows: list[int],
    e: dict[int, float],
    v: np.ndarray,
) -> tuple[np.ndarray, np.ndarray] | None:
    """q_dot+ and Lambda with an impulse on ``rows`` (each meeting its velocity condition), or
    None when that system is singular."""
    n, k = len(v), len(rows)
    a = jacobian[rows]
    matrix = np.zeros((n + k, n + k))
    matrix[:n, :n], matrix[:n, n:], matrix[n:, :n] = mass, -a.T, a
    target = np.array([-e.get(j, 0.0) * rates[j] - b[j] for j in rows])
    try:
        z = np.linalg.solve(matrix, np.concatenate((mass @ v, target)))
    except np.linalg.LinAlgError:
        return None
    impulses = np.zeros(len(jacobian))
    impulses[rows] = z[n:]
    return z[:n], impulses


def _complementary(
    jacobian: np.ndarray,
    b: np.ndarray,
    rates: np.ndarray,
    after: np.ndarray,
    impulses: np.ndarray,
    chosen: tuple[int, ...],
    touching: Sequence[int],
    e: dict[int, float],
    scale: float,
) -> bool:
    """Whether the impulses of ``chosen`` push and no other touching contact closes."""
    tolerance = SIGN_TOLERANCE * (scale + float(np.max(np.abs(impulses), initial=0.0)))
    if any(impulses[i] < -tolerance for i in chosen):
        return False
    others = [i for i in touching if i not in chosen]
    leaving = jacobian[others] @ after + b[others] if others else np.zeros(0)
    return all(w >= -tolerance for w in leaving + np.array([e[i] * rates[i] for i in others]))
