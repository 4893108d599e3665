"""Equivalent Lagrangians and point transformations (seed 000, seed 002).

References:
- L and L + dF(q, t)/dt have the same Euler–Lagrange equations;
- gauge change A -> A + grad psi, phi -> phi - dpsi/dt of a charge: same equations;
- Kepler in Cartesian coordinates, transformed to polar: m (r'' - r th'^2) + m mu / r^2 = 0
  and d/dt (m r^2 th') = 0 (textbook polar equations);
- a point transformation q = q(s, t) multiplies the equations by J^T (the notes' invariance
  proof), checked as a Hypothesis property with random affine maps on a 2-DOF system with
  dissipation, an applied force and a gyroscopic term.
"""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.analysis import equivalent_under_total_derivative, point_transformation

t = lg.t
x, y, z = sp.symbols("x y z")
x_dot, y_dot, z_dot = sp.symbols("x_dot y_dot z_dot")
x_ddot, y_ddot = sp.symbols("x_ddot y_ddot")
m, mu, q_e, e0, b0 = sp.symbols("m mu q_e E0 B0")
r, theta, s1, s2 = sp.symbols("r theta s1 s2")
r_dot, theta_dot, r_ddot, theta_ddot = sp.symbols("r_dot theta_dot r_ddot theta_ddot")


def test_adding_a_total_derivative_changes_nothing() -> None:
    theta_, phi_ = sp.symbols("theta phi")
    gauge = theta_**2 * sp.sin(phi_) * t + sp.cos(theta_ - phi_)
    system = lg.examples.double_pendulum()
    through_derive = equivalent_under_total_derivative(system, gauge)
    assert through_derive.equivalent and through_derive.difference == sp.zeros(2, 1)
    on_equations = equivalent_under_total_derivative(lg.derive(system), gauge)
    assert on_equations.equivalent
    assert sp.expand(on_equations.added_term - through_derive.added_term) == 0


def test_gauge_function_with_velocities_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match="depends on velocities"):
        equivalent_under_total_derivative(lg.examples.mass_on_spring(), x * x_dot)


def _charge(scalar: sp.Expr, vector: tuple[sp.Expr, ...]) -> lg.System:
    speed = (x_dot, y_dot, z_dot)
    return lg.System(
        coordinates=[x, y, z],
        parameters={m: 1.0, q_e: 1.0, e0: 0.1, b0: 1.0},
        particles=[lg.Particle("charge", m, (x, y, z))],
        velocity_potential=q_e * scalar - q_e * sum(a * v for a, v in zip(vector, speed)),
    )


def test_gauge_change_leaves_the_charge_equations_unchanged() -> None:
    scalar, vector = -e0 * x, (-b0 * y / 2, b0 * x / 2, sp.Integer(0))
    psi = x**2 * y * t + sp.sin(z) * x + b0 * x * y / 2
    new_scalar = scalar - psi.diff(t)
    new_vector = tuple(a + psi.diff(c) for a, c in zip(vector, (x, y, z)))
    before = lg.derive(_charge(scalar, vector)).equations
    after = lg.derive(_charge(new_scalar, new_vector)).equations
    assert (after - before).applyfunc(sp.expand) == sp.zeros(3, 1)
    # the same change is L -> L + q dpsi/dt
    assert equivalent_under_total_derivative(_charge(scalar, vector), q_e * psi).equivalent


def test_kepler_from_cartesian_to_polar() -> None:
    kepler = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, mu: 1.0},
        particles=[lg.Particle("planet", m, (x, y))],
        potential=-m * mu / sp.sqrt(x**2 + y**2),
    )
    radius = sp.Symbol("r", positive=True)
    polar = point_transformation(
        kepler, {"x": radius * sp.cos(theta), "y": radius * sp.sin(theta)}, [radius, theta]
    )
    assert polar.coordinates == (r, theta)
    radial, angular = lg.derive(polar).equations
    assert sp.simplify(radial - (m * (r_ddot - r * theta_dot**2) + m * mu / r**2)) == 0
    momentum = m * r**2 * theta_dot
    rate = momentum.diff(r) * r_dot + momentum.diff(theta_dot) * theta_ddot
    assert sp.simplify(angular - rate) == 0


def test_non_invertible_map_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match=r"not invertible.*Jacobian determinant"):
        point_transformation(
            lg.examples.two_masses_three_springs(), {"x1": s1 + s2, "x2": 2 * s1 + 2 * s2}, [s1, s2]
        )


def test_invalid_maps_list_every_problem() -> None:
    with pytest.raises(
        lg.AnalysisError, match=r"3 problems[\s\S]*x3[\s\S]*unknown names w[\s\S]*x2: is missing"
    ):
        point_transformation(
            lg.examples.two_masses_three_springs(), {"x1": s1, "x3": s2 * sp.Symbol("w")}, [s1, s2]
        )


a, b, c, beta, gamma, eps = sp.symbols("a b c beta gamma epsilon")
PLANE = lg.System(
    coordinates=[x, y],
    parameters={m: 1.0, a: 1.0, b: 0.5, c: 2.0, beta: 0.1, gamma: 0.3, eps: 0.2},
    kinetic=m * (x_dot**2 + y_dot**2) / 2 + eps * x * y_dot,
    potential=a * x**4 + b * x * y + c * y**2,
    dissipation=beta * x_dot**2 / 2,
    generalized_forces={y: gamma * x},
)
PLANE_EQUATIONS = lg.derive(PLANE).equations

entries = st.integers(min_value=-3, max_value=3)


@settings(max_examples=15, deadline=None)
@given(st.lists(entries, min_size=4, max_size=4), entries, entries, entries)
def test_point_transformation_multiplies_the_equations_by_j_transpose(
    matrix: list[int], offset_x: int, offset_y: int, drift: int
) -> None:
    jacobian = sp.Matrix(2, 2, matrix)
    assume(jacobian.det() != 0)
    old = jacobian * sp.Matrix([s1, s2]) + sp.Matrix([offset_x + drift * t, offset_y])
    transformed = point_transformation(PLANE, {"x": old[0], "y": old[1]}, [s1, s2])
    new_equations = lg.derive(transformed).equations
    rates = sp.Matrix(sp.symbols("s1_dot s2_dot"))
    accelerations = sp.Matrix(sp.symbols("s1_ddot s2_ddot"))
    velocity = jacobian * rates + old.diff(t)
    acceleration = jacobian * accelerations  # q is affine in s and t
    substitution = {
        x: old[0],
        y: old[1],
        x_dot: velocity[0],
        y_dot: velocity[1],
        x_ddot: acceleration[0],
        y_ddot: acceleration[1],
    }
    expected = jacobian.T * PLANE_EQUATIONS.xreplace(substitution)
    assert (new_equations - expected).applyfunc(sp.expand) == sp.zeros(2, 1)
