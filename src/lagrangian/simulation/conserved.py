"""Conserved quantities along a trajectory, and how far the integration let them drift.

    p_j = dL/dq_dot_j,    d/dt p_j = dL/dq_j + Q_j - dF/dq_dot_j + sum_k lambda_k dh_k/dq_j,

so the momentum of a cyclic coordinate (:func:`lagrangian.analysis.cyclic_coordinates`) is
a constant of the motion unless a constraint involves that coordinate.  Those momenta are
found automatically; any other quantity (a Noether charge, an angular momentum written in
Cartesian coordinates, a first integral known from the physics) is passed by name as a
model-file expression or a SymPy expression of the coordinates, ``NAME_dot``, the parameters
and ``t``.  Each becomes a column of the Trajectory (``Trajectory.conserved``) whose spread is
in ``Trajectory.drift()``.

>>> import lagrangian as lg
>>> sorted(conserved_expressions(lg.derive(lg.examples.planet()), None, {}))
['p_theta']
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.analysis.momenta import CyclicCoordinate, cyclic_coordinates
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import ExpressionError, Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulation.crossings import state_expression
from lagrangian.symbolic.caches import IdentityCache

_CYCLIC: IdentityCache[EquationsOfMotion, tuple[CyclicCoordinate, ...]] = IdentityCache()
_COMPILED: IdentityCache[EquationsOfMotion, dict[Any, NumericFunction]] = IdentityCache()
_INVOLVED: IdentityCache[System, frozenset[sp.Symbol]] = IdentityCache()

#: What ``simulate(..., conserved=...)`` accepts: quantity name -> expression text or SymPy.
Requested = Mapping[str, Any]


def conserved_expressions(
    eom: EquationsOfMotion, system: System | None, requested: Requested
) -> dict[str, sp.Expr]:
    """The momenta of the cyclic coordinates (``p_NAME``) that no constraint involves, then
    the ``requested`` quantities, by name.

    Raises SimulationInputError naming every requested quantity that cannot be read or uses
    a name the system does not have.
    """
    found = {f"p_{c.coordinate.name}": c.momentum for c in _free_cyclic(eom, system)}
    problems: list[Problem] = []
    for name, value in requested.items():
        field = f"conserved.{name}"
        try:
            found[str(name)] = state_expression(eom, value, field)
        except ExpressionError as error:
            problems.extend(error.problems)
        except SimulationInputError as error:
            problems.append(Problem(field, str(error), "write it with the system's names"))
    raise_if_problems(problems, "Some conserved quantities cannot be used", SimulationInputError)
    return found


def momentum_obstructions(
    eom: EquationsOfMotion, system: System | None, parameters: Mapping[str, float]
) -> dict[str, tuple[str, ...]]:
    """The momentum columns ``p_NAME`` that are not conserved at the ``parameters`` (by
    name), each with what changes it (``force``, ``dissipation``: the obstructions of
    :class:`lagrangian.analysis.momenta.CyclicCoordinate`, asked again at these values
    only when something can change a momentum)."""
    free = [c for c in _free_cyclic(eom, system) if c.obstructions]
    if not free:
        return {}
    at_values = {c.coordinate: c for c in cyclic_coordinates(eom, dict(parameters))}
    return {
        f"p_{c.coordinate.name}": c.obstructions
        for c in free
        if not at_values[c.coordinate].conserved
    }


def _free_cyclic(eom: EquationsOfMotion, system: System | None) -> list[CyclicCoordinate]:
    """The cyclic coordinates that no constraint involves.

    The coordinates absent from L and from every constraint are found first, from the
    symbols of each (one pass over the constraints per System); the analysis of cyclic
    coordinates, which asks every constraint for its force along every coordinate, runs only
    when one remains.  A gas of hard disks, whose coordinates all meet a wall, skips it."""
    involved = _constrained_symbols(system)
    used = eom.lagrangian.free_symbols
    free = {
        q
        for q, q_dot in zip(eom.coordinates, eom.velocities)
        if q not in used and q not in involved and q_dot not in involved
    }
    if not free:
        return []
    return [c for c in _cyclic(eom) if c.coordinate in free]


def _cyclic(eom: EquationsOfMotion) -> tuple[CyclicCoordinate, ...]:
    """The cyclic coordinates (cached per equations).

    analysis.cyclic_coordinates also finds a coordinate whose terms in L cancel, at the cost
    of every Euler-Lagrange step (0.2 s on a 10-link pendulum): too much to pay on every
    simulation for a case that rare (``analyze`` reports it; name it in ``conserved``), so
    only coordinates absent from L are asked for."""
    return _CYCLIC.get(eom, cyclic_coordinates)


def compile_conserved(
    eom: EquationsOfMotion, expressions: Mapping[str, sp.Expr]
) -> NumericFunction | None:
    """One NumPy function of (q, q_dot, t, p) returning every quantity (None when there are
    none); compiled once per EquationsOfMotion and set of quantities."""
    if not expressions:
        return None
    cached = _COMPILED.get(eom, lambda _: {})
    key = tuple((name, sp.srepr(expr)) for name, expr in expressions.items())
    if key not in cached:
        cached[key] = _compile(eom, expressions)
    return cached[key]


def _compile(eom: EquationsOfMotion, expressions: Mapping[str, sp.Expr]) -> NumericFunction:
    groups = (list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters))
    return NumericFunction(groups, list(expressions.values()), (len(expressions),))


def conserved_columns(
    function: NumericFunction | None,
    names: tuple[str, ...],
    q: np.ndarray,
    q_dot: np.ndarray,
    t: np.ndarray,
    p: np.ndarray,
) -> dict[str, np.ndarray]:
    """Each quantity at every row of a trajectory, by name."""
    if function is None or not names:
        return {}
    if len(t) == 0:
        return {name: np.zeros(0) for name in names}
    values = function(q, q_dot, t, np.broadcast_to(p, (len(t), len(p))))
    return {name: values[:, i] for i, name in enumerate(names)}


def _constrained_symbols(system: System | None) -> frozenset[sp.Symbol]:
    """Every symbol a constraint of ``system`` uses (their coordinates' momenta are not
    conserved: the constraint force acts along them); computed once per System."""
    if system is None or not system.constraints:
        return frozenset()
    return _INVOLVED.get(system, _symbols_of_constraints)


def _symbols_of_constraints(system: System) -> frozenset[sp.Symbol]:
    return frozenset().union(*(c.expression.free_symbols for c in system.constraints))
