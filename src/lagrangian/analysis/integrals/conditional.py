"""The parameter relations under which a system may have more first integrals: a 2-D
oscillator with springs k1 and k2 conserves its angular momentum (and the Fradkin tensor) only
when k1 = k2.

The candidates are the exchanges of two parameters that, with two coordinates exchanged too,
or an angle turned by a right angle, or nothing else, leave L and the forces unchanged: k1 <->
k2 with x <-> y; I1 <-> I2 of a rigid body with psi -> psi + pi/2.  Setting such
a pair equal gives the system a discrete symmetry it lacks otherwise, the usual source of
extra integrals (an isotropic oscillator, a symmetric top).  The search for first integrals is
then run again with the one parameter replaced by the other
(:func:`lagrangian.analysis.integrals.search.first_integrals`); whatever it finds beyond the
integrals of every parameter value holds under the relation, and is checked not to hold
without it (dI/dt on the equations with both parameters free does not vanish).

>>> import lagrangian as lg, sympy as sp
>>> x, y = lg.coordinates("x y")
>>> k1, k2, m = sp.symbols("k1 k2 m")
>>> oscillator = lg.System(coordinates=[x, y], parameters={m: 1, k1: 1, k2: 2},
...     kinetic=m * (lg.velocity(x) ** 2 + lg.velocity(y) ** 2) / 2,
...     potential=(k1 * x**2 + k2 * y**2) / 2)
>>> candidate_relations(oscillator)
(Eq(k1, k2),)
>>> from lagrangian.analysis.arguments import numeric_values
>>> relation_holds(sp.Eq(k1, k2), numeric_values(lg.derive(oscillator)))
False
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from itertools import combinations

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of
from lagrangian.analysis.integrals.function_basis import angles
from lagrangian.analysis.integrals.lie_symmetries import search_problem
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero

#: Relative difference below which two parameter values count as equal.
EQUAL = 1e-12


def candidate_relations(
    subject: Subject, parameters: Values | None = None, deadline: float | None = None
) -> tuple[sp.Equality, ...]:
    """The relations p_a = p_b (a before b by name) whose exchange a <-> b, with at most one
    exchange of two coordinates or one angle turned by pi/2, leaves L and the forces
    unchanged (module docstring); the
    search stops at the ``deadline`` (``time.monotonic()``) when one is given."""
    eom = equations_of(subject)
    problem = search_problem(eom, parameters)
    q, v = eom.coordinates, eom.velocities
    n = len(q)
    maps: list[tuple[dict[sp.Symbol, sp.Expr], list[int]]] = []
    for i, j in [(0, 0), *combinations(range(n), 2)]:
        order = list(range(n))
        order[i], order[j] = order[j], order[i]
        moved: dict[sp.Symbol, sp.Expr] = {q[k]: q[order[k]] for k in range(n)}
        moved.update({v[k]: v[order[k]] for k in range(n)})
        maps.append((moved, order))
    for angle in angles(problem.lagrangian, q):  # I1 <-> I2 of a body turned by a right angle
        maps.append(({angle: angle + sp.pi / 2}, list(range(n))))
    found = []
    for a, b in combinations(problem.parameters, 2):
        if deadline is not None and time.monotonic() > deadline:
            break
        for moved, order in maps:
            exchange = {a: b, b: a, **moved}
            if _unchanged(problem.lagrangian, problem.forces, exchange, order):
                found.append(sp.Eq(a, b))
                break
    return tuple(found)


def _unchanged(
    lagrangian: sp.Expr, forces: tuple[sp.Expr, ...], moved: dict, order: list[int]
) -> bool:
    if not is_zero(lagrangian.xreplace(moved) - lagrangian):
        return False
    return all(is_zero(forces[order[k]].xreplace(moved) - forces[k]) for k in range(len(order)))


def relation_holds(relation: sp.Equality, values: Mapping[sp.Symbol, sp.Expr]) -> bool:
    """True when the parameter ``values`` meet ``relation`` (both sides have values and they
    agree to 1e-12 relative)."""
    sides = [to_sympy(side).xreplace(dict(values)) for side in (relation.lhs, relation.rhs)]
    if any(side.free_symbols for side in sides):
        return False  # a parameter without a value: generic
    left, right = (complex(sp.N(side)) for side in sides)
    return abs(left - right) <= EQUAL * max(1.0, abs(left), abs(right))
