"""derive(system) -> EquationsOfMotion: the Euler–Lagrange equations of a System.

    d/dt dL/dq_dot_j - dL/dq_j + dF/dq_dot_j = Q_j,    L = T - V - U

(Goldstein, Classical Mechanics, 3rd ed., §1.4-1.5.)

The matrix form is built from structure (Jacobians, Christoffel symbols) in SymEngine
(:mod:`lagrangian.derivation.terms`); the step-by-step form differentiates L itself when asked
for (:mod:`lagrangian.derivation.steps`).

A derivation is remembered for the last ``RECENT_SYSTEMS`` System objects (by identity), so
``simulate(system)`` twice and ``analyze(system)`` derive once.  Those Systems and their
equations stay alive until newer ones push them out (:func:`forget_derivations` lets them go
at once); a System is immutable, so a remembered derivation is never stale.
"""

from __future__ import annotations

import math
from typing import Any

from lagrangian.derivation.backend import Backend, cycle_collection_paused
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.derivation.terms import EulerLagrangeTerms, euler_lagrange_terms
from lagrangian.errors import require
from lagrangian.limits import configured_seconds
from lagrangian.limits import time_limit as limited_to
from lagrangian.model import System
from lagrangian.model.system import require_system
from lagrangian.size_limits import active_operations, check_operations, configured_operations
from lagrangian.size_limits import size_limit as sized_to
from lagrangian.symbolic.caches import RecentCache
from lagrangian.symbolic.frozen import FrozenMapping, frozen
from lagrangian.symbolic.symbols import t

#: How many Systems (the most recently derived) keep their EquationsOfMotion remembered.
RECENT_SYSTEMS = 32

_RECENT: RecentCache[System, EquationsOfMotion] = RecentCache(RECENT_SYSTEMS)


def derive(
    system: System, *, time_limit: float | None = None, size_limit: float | None = None
) -> EquationsOfMotion:
    """The equations of motion of ``system`` (derived once per System object), within
    ``time_limit`` seconds (TimeLimitError; default ``$LAGRANGIAN_TIME_LIMIT`` or
    :data:`lagrangian.limits.DEFAULT_SECONDS`) and with no entry of M or the forcing larger
    than ``size_limit`` operations (SizeLimitError; default ``$LAGRANGIAN_SIZE_LIMIT`` or
    :data:`lagrangian.size_limits.DEFAULT_OPERATIONS`).

    >>> import sympy as sp
    >>> from lagrangian.model import System
    >>> x, x_dot = sp.symbols("x x_dot"); m, k = sp.symbols("m k")
    >>> eom = derive(System(coordinates=[x], parameters=[m, k],
    ...                     kinetic=m * x_dot**2 / 2, potential=k * x**2 / 2))
    >>> eom.mass_matrix, eom.forcing
    (Matrix([[m]]), Matrix([[-k*x]]))
    """
    # a bad limit is refused even when the result is remembered
    configured_seconds(time_limit)
    configured_operations(size_limit)
    # the limits apply only to a derivation that is not remembered yet
    return _RECENT.get(
        require_system(system, "derive(system)"),
        lambda fresh: _derive_within(fresh, time_limit, size_limit),
    )


def _derive_within(
    system: System, seconds: float | None, operations: float | None
) -> EquationsOfMotion:
    with limited_to(seconds, what="derive"), sized_to(operations), cycle_collection_paused():
        return equations_of_motion(system)


def equations_of(subject: Any, argument: str) -> EquationsOfMotion:
    """The equations of motion of ``subject``, a System (derived once, :func:`derive`) or its
    EquationsOfMotion; anything else is an ArgumentError naming ``argument``."""
    if isinstance(subject, System):
        return derive(subject)
    require(
        subject,
        (System, EquationsOfMotion),
        argument,
        "build one with lagrangian.System(...) or lagrangian.load(path), or derive it with "
        "lagrangian.derive(system)",
    )
    return subject


def forget_derivations() -> None:
    """Drop every remembered derivation (the Systems and equations it kept alive)."""
    _RECENT.clear()


def equations_of_motion(system: System) -> EquationsOfMotion:
    """The EquationsOfMotion of ``system``, derived now (:func:`derive` remembers them)."""
    terms = euler_lagrange_terms(system)
    _check_sizes(terms)
    return EquationsOfMotion(
        coordinates=tuple(system.coordinates),
        velocities=system.velocities,
        accelerations=system.accelerations,
        parameters=frozen(system.parameters),
        time=t,
        mass_matrix=terms.view.symmetric_matrix(terms.mass),
        forcing=terms.view.vector(terms.forcing),
        coordinate_orders=FrozenMapping(terms.orders),
        system=system,
        name=system.name,
    )


def _check_sizes(terms: EulerLagrangeTerms) -> None:
    """Every entry of M and the forcing within the size limit (SizeLimitError naming the
    entry), before they are converted for the user: converting, printing and compiling an
    expression cost far more time and memory than computing it.  The message naming an
    entry is written only for an entry over the limit (a 200-link chain has 20,300 entries,
    and writing each name costs more than counting the entry)."""
    limit = active_operations()
    if math.isinf(limit):
        return
    q, counted = terms.coordinates, TreeOperations()
    for j, row in enumerate(terms.mass):
        for k in range(j, len(row)):
            count = counted(row[k])
            if count > limit:
                check_operations(count, f"derive: the mass matrix entry M[{q[j]}, {q[k]}]")
    for j, entry in enumerate(terms.forcing):
        count = counted(entry)
        if count > limit:
            check_operations(count, f"derive: the forcing of the equation of {q[j]}")


class TreeOperations:
    """The operations of SymEngine expressions counted over their trees as SymEngine's
    ``count_ops`` counts them (n - 1 for a sum or product of n arguments, one for a power or
    a function, none for an atom), each distinct subexpression counted once across calls and
    its count remembered (atoms too: a chain's lengths and velocities recur in every term):
    a chain's mass sums m_k + ... + m_n recur in n entries of M each, and counting every
    entry afresh would walk n^3/6 masses."""

    def __init__(self) -> None:
        self._known: dict[Backend, int] = {}

    def __call__(self, expr: Backend) -> int:
        known = self._known
        count = known.get(expr)
        if count is not None:
            return count
        args = expr.args
        if not args:
            known[expr] = 0
            return 0
        count = len(args) - 1 if (expr.is_Add or expr.is_Mul) else 1
        get = known.get
        for arg in args:
            inner = get(arg)
            count += self(arg) if inner is None else inner
        known[expr] = count
        return count
