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

from typing import Any

import sympy as sp

from lagrangian.derivation.backend import cycle_collection_paused
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.derivation.terms import EulerLagrangeTerms, euler_lagrange_terms
from lagrangian.errors import require
from lagrangian.limits import configured_seconds
from lagrangian.limits import time_limit as limited_to
from lagrangian.model import System
from lagrangian.model.system import require_system
from lagrangian.size_limits import configured_operations
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
    return EquationsOfMotion(
        coordinates=tuple(system.coordinates),
        velocities=system.velocities,
        accelerations=system.accelerations,
        parameters=frozen(system.parameters),
        time=t,
        mass_matrix=converted_mass_matrix(terms),
        forcing=converted_forcing(terms),
        coordinate_orders=FrozenMapping(terms.orders),
        system=system,
        name=system.name,
    )


# Every entry of M and the forcing is converted for the user within the size limit
# (SizeLimitError naming the entry): printing and compiling an expression cost far more time
# and memory than computing it.  Its operations are counted as it is converted, each
# subexpression once, and the conversion stops before a subexpression past the limit.


def converted_mass_matrix(terms: EulerLagrangeTerms) -> sp.ImmutableMatrix:
    """M of ``terms`` converted to SymPy, each entry within the size limit."""
    q = terms.coordinates
    return terms.view.symmetric_matrix(
        terms.mass, lambda j, k: f"derive: the mass matrix entry M[{q[j]}, {q[k]}]"
    )


def converted_forcing(terms: EulerLagrangeTerms) -> sp.ImmutableMatrix:
    """The forcing of ``terms`` converted to SymPy, each entry within the size limit."""
    q = terms.coordinates
    return terms.view.vector(
        terms.forcing, lambda j: f"derive: the forcing of the equation of {q[j]}"
    )
