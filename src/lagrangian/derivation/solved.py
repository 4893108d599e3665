"""The equations of motion solved for their highest derivatives, and whether they can be.

    M q_ddot = forcing   ->   q_ddot = M^-1 forcing            (coordinates with inertia)
    forcing_j = 0        ->   q_dot_j = ...                    (first-order coordinates)

Both are pure functions of an :class:`~lagrangian.derivation.eom.EquationsOfMotion` value
(its ``mass_matrix``, ``forcing`` and ``coordinate_orders``), computed on first request and
cached per equations object.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.frozen import FrozenMapping
from lagrangian.symbolic.probe import generic_rank
from lagrangian.symbolic.symbols import acceleration, velocity

if TYPE_CHECKING:
    from lagrangian.derivation.eom import EquationsOfMotion

_REGULAR: IdentityCache[EquationsOfMotion, bool] = IdentityCache()
_SOLVED: IdentityCache[EquationsOfMotion, FrozenMapping[sp.Symbol, sp.Expr]] = IdentityCache()


def mass_matrix_is_regular(eom: EquationsOfMotion) -> bool:
    """True when every coordinate has inertia and M has full rank at a generic point
    (:func:`lagrangian.symbolic.probe.generic_rank`)."""
    return _REGULAR.get(eom, _full_rank)


def _full_rank(eom: EquationsOfMotion) -> bool:
    orders = eom.coordinate_orders.values()
    return all(order == 2 for order in orders) and generic_rank(eom.mass_matrix) == len(orders)


def explicit_solution(eom: EquationsOfMotion) -> FrozenMapping[sp.Symbol, sp.Expr]:
    """q_ddot of the second-order coordinates and q_dot of the first-order ones, solved."""
    return _SOLVED.get(eom, _solve_equations)


def _solve_equations(eom: EquationsOfMotion) -> FrozenMapping[sp.Symbol, sp.Expr]:
    """Solve forcing = 0 for the first-order velocities, then M q_ddot = forcing."""
    coordinates, orders = eom.coordinates, eom.coordinate_orders
    second = [j for j, q in enumerate(coordinates) if orders[q] == 2]
    first = [j for j, q in enumerate(coordinates) if orders[q] == 1]
    forcing = list(eom.forcing)
    solved: dict[sp.Symbol, sp.Expr] = {}
    if first:
        unknowns = [velocity(coordinates[j]) for j in first]
        a, b = sp.linear_eq_to_matrix([forcing[j] for j in first], unknowns)
        solved.update({u: sp.simplify(v) for u, v in zip(unknowns, a.LUsolve(b))})
        forcing = [f.xreplace(solved) for f in forcing]
    if second:
        mass = sp.Matrix([[eom.mass_matrix[j, k] for k in second] for j in second])
        values = _solve_linear(mass, sp.Matrix([forcing[j] for j in second]))
        solved.update({acceleration(coordinates[j]): v for j, v in zip(second, values)})
    return FrozenMapping(solved)


def _solve_linear(mass: sp.Matrix, rhs: sp.Matrix) -> list[sp.Expr]:
    """M x = rhs; a diagonal M is divided directly, small ones solved by LU and simplified."""
    if mass.is_diagonal():
        return [sp.expand(rhs[i] / mass[i, i]) for i in range(mass.rows)]
    return [sp.simplify(v) if mass.rows <= 3 else v for v in mass.LUsolve(rhs)]
