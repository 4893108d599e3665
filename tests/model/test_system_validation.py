"""Bad input gets one ModelError naming every problem, its field and the fix."""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import LagrangianError, ModelError

x, y, theta = sp.symbols("x y theta")
x_dot, theta_dot, theta_ddot = sp.symbols("x_dot theta_dot theta_ddot")
m, k, g, l = sp.symbols("m k g l")


def test_unknown_name_is_named_with_a_suggestion() -> None:
    kk = sp.Symbol("kk")
    with pytest.raises(ModelError, match=r"potential: unknown name 'kk' — did you mean 'k'\?"):
        lg.System(coordinates=[x], parameters=[m, k], potential=kk * x**2 / 2)


def test_coordinate_that_is_also_a_parameter() -> None:
    with pytest.raises(ModelError, match=r"parameters\.x: is also a coordinate"):
        lg.System(coordinates=[x], parameters=[x, m], kinetic=m * x_dot**2 / 2)


def test_velocity_in_a_potential() -> None:
    with pytest.raises(ModelError, match=r"potential: the velocity x_dot may not appear here"):
        lg.System(coordinates=[x], parameters=[m], potential=m * x_dot)


def test_acceleration_in_an_energy() -> None:
    x_ddot = sp.Symbol("x_ddot")
    with pytest.raises(ModelError, match=r"kinetic: the acceleration x_ddot may not appear"):
        lg.System(coordinates=[x], parameters=[m], kinetic=m * x_ddot)


def test_non_scalar_energy() -> None:
    with pytest.raises(ModelError, match=r"kinetic: must be a scalar expression"):
        lg.System(coordinates=[x], parameters=[m], kinetic=sp.Matrix([m * x_dot**2, 0]))


def test_positions_of_inconsistent_dimension() -> None:
    with pytest.raises(ModelError, match=r"inconsistent dimensions"):
        lg.System(
            coordinates=[x, y],
            parameters=[m, g],
            particles=[lg.Particle("a", m, (x, y)), lg.Particle("b", m, (x, y, 0))],
            gravity=(0, -g),
        )


def test_force_on_an_unknown_point() -> None:
    with pytest.raises(
        ModelError,
        match=r"forces\[0\]\.at: unknown point 'bobb' — did you mean "
        r"'bob'\?",
    ):
        lg.System(
            coordinates=[x],
            parameters=[m, k],
            particles=[lg.Particle("bob", m, (x,))],
            forces=[lg.Force("bobb", (k,))],
        )


def test_circuit_element_on_an_unknown_coordinate() -> None:
    q1, q1_dot = sp.symbols("q1 q1_dot")
    big_l, u = sp.symbols("L u")
    with pytest.raises(ModelError, match=r"circuit\[1\]\.coordinate: unknown coordinate q2"):
        lg.System(
            coordinates=[q1],
            parameters=[big_l, u],
            circuit=[lg.Inductor(big_l, q1_dot), lg.VoltageSource(u, "q2")],
        )


def test_every_problem_is_reported_at_once() -> None:
    kk = sp.Symbol("kk")
    with pytest.raises(ModelError, match=r"\(3 problems\)") as caught:
        lg.System(
            coordinates=[x],
            parameters=[m],
            kinetic=m * x_dot**2 / 2 + kk,
            potential=x_dot,
            generalized_forces={"z": 1},
        )
    fields = [p.field for p in caught.value.problems]
    assert fields == ["kinetic", "potential", "generalized_forces.z"]
    assert all(p.fix for p in caught.value.problems)


def test_parameter_value_must_be_a_number() -> None:
    with pytest.raises(ModelError, match=r"parameters\.m: value 'heavy' is not a real number"):
        lg.System(coordinates=[x], parameters={"m": "heavy"}, kinetic=m * x_dot**2 / 2)


def test_model_error_is_a_value_error_and_a_lagrangian_error() -> None:
    with pytest.raises(ValueError, match="unknown name"):
        lg.System(coordinates=[x], kinetic=m * x_dot**2)
    assert issubclass(ModelError, LagrangianError)


def test_time_functions_become_plain_symbols() -> None:
    t = sp.Symbol("t")
    xf = sp.Function("x")(t)
    system = lg.System(
        coordinates=[xf],
        parameters=[m, k],
        kinetic=m * xf.diff(t) ** 2 / 2,
        potential=k * xf**2 / 2,
    )
    assert system.coordinates == (x,)
    assert system.kinetic == m * x_dot**2 / 2
    assert system.potential == k * x**2 / 2


def test_symbols_with_assumptions_are_unified_by_name() -> None:
    m_pos = sp.Symbol("m", positive=True)
    system = lg.System(coordinates=["x"], parameters={m_pos: 2.0}, kinetic=m * x_dot**2 / 2)
    assert system.kinetic.free_symbols == {m_pos, x_dot}


def test_system_is_immutable() -> None:
    system = lg.examples.simple_pendulum()
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign"):
        system.name = "other"  # type: ignore[misc]
    changed = system.with_parameters({"m": 2.0})
    assert changed.parameters[m] == 2.0 and system.parameters[m] == 1.0


def test_a_part_fine_in_one_field_is_checked_again_where_less_is_allowed() -> None:
    # the checks remember the parts they found fine, for each kind of field: a velocity term
    # fine in the kinetic energy is still refused in a position
    term = m * x_dot * sp.sin(x)
    with pytest.raises(ModelError) as raised:
        lg.System(
            coordinates=[x],
            parameters=[m, g],
            kinetic=term + m * x_dot**2 / 2,
            particles=[lg.Particle("bob", m, (x + term, sp.sin(x)))],
            gravity=(0, -g),
        )
    fields = [(problem.field, problem.message) for problem in raised.value.problems]
    assert fields == [("particles[0].position[0]", "the velocity x_dot may not appear here")]


def test_a_bad_part_beside_parts_found_fine_is_reported() -> None:
    fine = sp.sin(x) + sp.cos(x)
    with pytest.raises(ModelError, match=r"position\[1\]: unknown name 'kk' — did you mean 'k'"):
        lg.System(
            coordinates=[x],
            parameters=[m, k],
            particles=[lg.Particle("bob", m, (fine, fine + sp.Symbol("kk")))],
        )
    with pytest.raises(ModelError, match=r"position\[1\]: .* holds an undefined or infinite"):
        lg.System(
            coordinates=[x], parameters=[m], particles=[lg.Particle("a", m, (fine, fine + sp.oo))]
        )


_PHI, _X_DOT, _Y_DOT = sp.symbols("phi x_dot y_dot")
_TURN = sp.Matrix([[sp.cos(_PHI), -sp.sin(_PHI)], [sp.sin(_PHI), sp.cos(_PHI)]])
#: Velocity constraints written as products of rotations, their parts repeated (not sums of
#: one velocity times a factor: the linearity check differentiates them).
_PRODUCTS = [
    (_TURN * _TURN * sp.Matrix([_X_DOT, _Y_DOT]))[0] * (_TURN * _TURN)[0, 1],
    (_TURN * _TURN * sp.Matrix([_X_DOT, _Y_DOT]))[1] * (_TURN * sp.Matrix([_X_DOT, 1]))[0],
    ((_TURN * _TURN)[0, 0] + _X_DOT * _TURN[1, 0]) ** 2 + _Y_DOT,
]


@pytest.mark.parametrize("expression", _PRODUCTS)
def test_a_velocity_constraint_is_linear_as_its_hessian_says(expression: sp.Expr) -> None:
    """Accepted exactly when SymPy's Hessian in the velocities expands to zero."""
    x, y = sp.symbols("x y")
    linear = all(sp.expand(e) == 0 for e in sp.hessian(expression, (_X_DOT, _Y_DOT)))
    constraint = lg.VelocityConstraint(expression)
    if linear:
        lg.System(coordinates=[x, y, _PHI], constraints=[constraint])
        return
    with pytest.raises(ModelError, match="is not linear in the velocities"):
        lg.System(coordinates=[x, y, _PHI], constraints=[constraint])
