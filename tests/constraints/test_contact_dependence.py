"""Unilateral constraints are inequalities: the equality constraints are checked together,
each contact on its own with them.  A gas's walls and disk contacts, which can never all
close at once, give the multiplier form (not solved jointly); contacts that can close
together are still solved (two stacked balls: Newton's third law by hand); a contact implied
by an equality constraint, or one that can never close, is refused by name."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.constraints import constrained_equations
from lagrangian.errors import ConstraintError
from lagrangian.examples.gas import hard_disk_gas


def test_a_gas_has_its_multiplier_form_though_its_contacts_never_all_close() -> None:
    gas = hard_disk_gas(3, radius=0.08)
    equations = constrained_equations(gas)
    assert len(equations.multipliers) == 3 * 4 + 3 == equations.constraint_jacobian.rows
    assert equations.explicit is None  # 15 contacts on 6 coordinates: no joint solution
    # M q_ddot = forcing + A^T lambda: along x1 push the left and right walls (unit normals)
    # and disks 2 and 3 (the gradient 2 (x1 - x_j) of their gaps)
    x1, x2, x3 = gas.coordinates[:3]
    lam = equations.multipliers
    by_hand = lam[0] - lam[1] + 2 * (x1 - x2) * lam[12] + 2 * (x1 - x3) * lam[13]
    assert sp.expand(equations.generalized_constraint_forces[0] - by_hand) == 0


def test_contacts_that_close_together_are_solved_together() -> None:
    """Two balls of mass m stacked on a floor, at rest in contact: the floor carries both,
    lambda_floor = 2 m g, the lower ball carries the upper, lambda_top = m g."""
    y1, y2, m, g = sp.symbols("y1 y2 m g")
    stack = lg.System(
        coordinates=[y1, y2],
        parameters={m: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("lower", m, (0, y1)), lg.Particle("upper", m, (0, y2))],
        constraints=[lg.Unilateral(y1, name="floor"), lg.Unilateral(y2 - y1, name="top")],
    )
    forces = constrained_equations(stack).constraint_forces
    assert forces is not None
    floor, top = (sp.simplify(v) for v in forces.values())
    assert (floor, top) == (2 * m * g, m * g)


def test_a_contact_implied_by_an_equality_constraint_is_refused() -> None:
    x, y = sp.symbols("x y")
    system = lg.System(
        coordinates=[x, y],
        kinetic=(sp.Symbol("x_dot") ** 2 + sp.Symbol("y_dot") ** 2) / 2,
        constraints=[lg.Holonomic(x - y, name="rod"), lg.Unilateral(2 * y - 2 * x, name="stop")],
    )
    with pytest.raises(ConstraintError, match=r"redundant in contact") as raised:
        constrained_equations(system)
    assert "constraints[1]" in str(raised.value) and "constraints[0]" not in str(raised.value)


def test_a_contact_that_can_never_close_is_refused_by_name() -> None:
    x, y = sp.symbols("x y")
    system = lg.System(
        coordinates=[x, y],
        kinetic=(sp.Symbol("x_dot") ** 2 + sp.Symbol("y_dot") ** 2) / 2,
        constraints=[lg.Unilateral(y, name="floor"), lg.Unilateral(x**2 + 1, name="never")],
    )
    with pytest.raises(ConstraintError, match=r"can never be in contact") as raised:
        constrained_equations(system)
    assert "constraints[1]" in str(raised.value) and "constraints[0]" not in str(raised.value)
