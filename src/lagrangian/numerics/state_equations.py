"""The state of a system and the linear system its right-hand side solves.

All coordinates of order 2 (M regular): the state is x = [q; q_dot] and

    M(q, q_dot, t) q_ddot = forcing(q, q_dot, t),    dx/dt = [q_dot; q_ddot].

Coordinates F of order 1 have no inertia (a charge through a resistor only, as in the RC + RL
circuit): their rows and columns of M vanish, and their equations 0 = forcing_F are linear in
their own velocities.  Writing forcing = f0 + J q_dot_F with J = d forcing / d q_dot_F and f0
the forcing at q_dot_F = 0, the second-order coordinates S and F together give

    [M_SS  -J_S] [q_ddot_S]   [f0_S]
    [ 0    -J_F] [q_dot_F ] = [f0_F],

one linear system for z = [q_ddot_S; q_dot_F]; the state is x = [q; q_dot_S].

>>> import lagrangian as lg
>>> equations = state_equations(lg.derive(lg.examples.rc_rl_circuit()))
>>> equations.second, equations.first
((1,), (0,))
>>> equations.matrix
Matrix([
[L, 0],
[0, R]])
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import SimulationInputError


@dataclass(frozen=True)
class StateEquations:
    """matrix z = vector with z = [q_ddot_S; q_dot_F], S and F coordinate indices."""

    second: tuple[int, ...]
    first: tuple[int, ...]
    matrix: sp.ImmutableMatrix
    vector: sp.ImmutableMatrix


def state_equations(eom: EquationsOfMotion) -> StateEquations:
    """The linear system of :class:`StateEquations` for ``eom`` (see the module docstring).

    Raises SimulationInputError for algebraic coordinates (order 0) and for first-order equations
    that are not linear in their velocities, which are not supported yet.
    """
    orders = [eom.coordinate_orders[q] for q in eom.coordinates]
    _refuse_algebraic(eom, orders)
    second = tuple(j for j, order in enumerate(orders) if order == 2)
    first = tuple(j for j, order in enumerate(orders) if order == 1)
    mass, forcing = eom.mass_matrix, eom.forcing
    if not first:
        return StateEquations(second, first, mass, forcing)
    rates = [eom.velocities[j] for j in first]
    jacobian = forcing.jacobian(rates)
    _require_linear(eom, mass, jacobian, first, rates)
    f0 = forcing.xreplace(dict.fromkeys(rates, sp.Integer(0)))
    s, f = list(second), list(first)
    matrix = sp.Matrix.vstack(
        sp.Matrix.hstack(mass.extract(s, s), -jacobian.extract(s, list(range(len(f))))),
        sp.Matrix.hstack(sp.zeros(len(f), len(s)), -jacobian.extract(f, list(range(len(f))))),
    )
    vector = sp.Matrix.vstack(f0.extract(s, [0]), f0.extract(f, [0]))
    return StateEquations(second, first, sp.ImmutableMatrix(matrix), sp.ImmutableMatrix(vector))


def _refuse_algebraic(eom: EquationsOfMotion, orders: list[int]) -> None:
    algebraic = [q.name for q, order in zip(eom.coordinates, orders) if order == 0]
    if algebraic:
        raise SimulationInputError(
            f"{_the_coordinates(algebraic)} algebraic (order 0: no inertia and no "
            "dissipation), so its equation is a constraint rather than an equation of motion; "
            "simulating such differential-algebraic systems is not supported yet. Give it "
            "an inertia or a dissipation term, or eliminate it by hand."
        )


def _require_linear(
    eom: EquationsOfMotion,
    mass: sp.ImmutableMatrix,
    jacobian: sp.Matrix,
    first: tuple[int, ...],
    rates: list[sp.Symbol],
) -> None:
    """First-order coordinates must have no inertia and appear linearly in the forcing."""
    names = [eom.coordinates[j].name for j in first]
    coupled = any(mass[i, j] != 0 or mass[j, i] != 0 for j in first for i in range(mass.rows))
    nonlinear = bool((jacobian.free_symbols | mass.free_symbols) & set(rates))
    if coupled or nonlinear:
        raise SimulationInputError(
            f"The equations of the first-order coordinates ({', '.join(names)}) are not "
            "linear in their velocities, or those coordinates have inertia; only first-order "
            "equations linear in the velocities, like a resistor's R q_dot, are supported yet."
        )


def _the_coordinates(names: list[str]) -> str:
    """'The coordinate y is' or 'The coordinates y, z are'."""
    if len(names) == 1:
        return f"The coordinate {names[0]} is"
    return f"The coordinates {', '.join(names)} are"
