"""The electrical and electromechanical examples of seed 001 (and its robot arm) against the
equations the notes derive by hand.

Every equation is a residual d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q (= 0), so the notes'
"lhs = rhs" is compared as lhs - rhs.
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg

S = sp.Symbol


def assert_same(ours: sp.Expr, expected: sp.Expr) -> None:
    assert sp.simplify(ours - expected) == 0, f"{ours} != {expected}"


def assert_same_vector(ours: sp.MatrixBase, expected: list[sp.Expr]) -> None:
    assert len(ours) == len(expected)
    for a, b in zip(ours, expected, strict=True):
        assert_same(a, b)


@pytest.fixture(scope="module")
def servo() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.servo_system())


# -- catalog ----------------------------------------------------------------------------------

EXAMPLES = [
    "series_rlc",
    "two_mesh_circuit",
    "rc_rl_circuit",
    "capacitor_microphone",
    "robot_arm",
    "servo_system",
]


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_is_registered_and_described(name: str) -> None:
    system = lg.examples.get(name)()
    assert name in lg.examples.names()
    assert system.name == name
    assert system.description == lg.examples.describe(name)
    state = {*system.coordinates, *system.velocities}
    assert set(system.initial) == state
    assert all(value is not None for value in system.parameters.values())


# -- series RLC -------------------------------------------------------------------------------


def test_series_rlc_is_kvl() -> None:
    q, q_dot, q_ddot = S("q"), S("q_dot"), S("q_ddot")
    L, C, R, u = sp.symbols("L C R u")
    eom = lg.derive(lg.examples.series_rlc())
    # Seed 001: L q_ddot + R q_dot + q/C = u.
    assert_same(eom.equations[0], L * q_ddot + R * q_dot + q / C - u)
    step = eom.steps[0]
    assert_same(step.dL_dvelocity, L * q_dot)
    assert_same(step.dL_dcoordinate, -q / C)
    assert_same(step.dF_dvelocity, R * q_dot)


# -- two-mesh circuit -------------------------------------------------------------------------


def test_two_mesh_equations() -> None:
    q1, q2 = sp.symbols("q1 q2")
    q1d, q2d, q1dd, q2dd = sp.symbols("q1_dot q2_dot q1_ddot q2_ddot")
    L1, L2, L12, C1, C2, R1, R2, U_a = sp.symbols("L1 L2 L12 C1 C2 R1 R2 U_a")
    eom = lg.derive(lg.examples.two_mesh_circuit())
    expected = [
        (L1 + L12) * q1dd - L12 * q2dd + R1 * q1d + q1 / C1 - U_a,
        -L12 * q1dd + (L2 + L12) * q2dd + R2 * q2d + q2 / C2,
    ]
    assert_same_vector(eom.equations, expected)


def test_two_mesh_partial_derivatives() -> None:
    q1, q2 = sp.symbols("q1 q2")
    q1d, q2d = sp.symbols("q1_dot q2_dot")
    L1, L2, L12, C1, C2, R1, R2, U_a = sp.symbols("L1 L2 L12 C1 C2 R1 R2 U_a")
    first, second = lg.derive(lg.examples.two_mesh_circuit()).steps
    # dKe/dq_dot (= dL/dq_dot, V has no velocities).
    assert_same(first.dL_dvelocity, (L1 + L12) * q1d - L12 * q2d)
    assert_same(second.dL_dvelocity, (L2 + L12) * q2d - L12 * q1d)
    # dKe/dq = 0, so dL/dq = -dV/dq.
    assert_same(first.dL_dcoordinate, -q1 / C1)
    assert_same(second.dL_dcoordinate, -q2 / C2)
    assert_same(first.dF_dvelocity, R1 * q1d)
    assert_same(second.dF_dvelocity, R2 * q2d)
    assert_same(first.generalized_force, U_a)
    assert_same(second.generalized_force, 0)


def test_two_mesh_accelerations_satisfy_the_notes_solved_form() -> None:
    q1, q2 = sp.symbols("q1 q2")
    q1d, q2d = sp.symbols("q1_dot q2_dot")
    L1, L2, L12, C1, C2, R1, R2, U_a = sp.symbols("L1 L2 L12 C1 C2 R1 R2 U_a")
    q1dd, q2dd = lg.derive(lg.examples.two_mesh_circuit()).explicit_accelerations
    # The notes solve each equation for its own acceleration, the other one kept.
    assert_same(q1dd, (-q1 / C1 - R1 * q1d + L12 * q2dd + U_a) / (L1 + L12))
    assert_same(q2dd, (L12 * q1dd - q2 / C2 - R2 * q2d) / (L2 + L12))


# -- RC + RL circuit: a coordinate without inertia --------------------------------------------


def test_rc_rl_equations() -> None:
    q1, q2 = sp.symbols("q1 q2")
    q1d, q2d, q2dd = sp.symbols("q1_dot q2_dot q2_ddot")
    L, C, R, R_L, u_a = sp.symbols("L C R R_L u_a")
    eom = lg.derive(lg.examples.rc_rl_circuit())
    expected = [
        R * q1d + (q1 - q2) / C - u_a,
        L * q2dd + R_L * q2d + (-q1 + q2) / C,
    ]
    assert_same_vector(eom.equations, expected)
    first, second = eom.steps
    assert_same(first.dL_dvelocity, 0)
    assert_same(second.dL_dvelocity, L * q2d)
    assert_same(first.dL_dcoordinate, -(q1 - q2) / C)
    assert_same(second.dL_dcoordinate, -(-q1 + q2) / C)


def test_rc_rl_mass_matrix_is_singular_and_q1_is_first_order() -> None:
    q1, q2 = sp.symbols("q1 q2")
    L = S("L")
    eom = lg.derive(lg.examples.rc_rl_circuit())
    assert eom.mass_matrix == sp.Matrix([[0, 0], [0, L]])
    assert dict(eom.coordinate_orders) == {q1: 1, q2: 2}
    assert not eom.mass_matrix_is_regular
    assert eom.algebraic_equations == ()


def test_rc_rl_explicit_form_is_the_notes() -> None:
    q1, q2 = sp.symbols("q1 q2")
    q1d, q2d, q2dd = sp.symbols("q1_dot q2_dot q2_ddot")
    L, C, R, R_L, u_a = sp.symbols("L C R R_L u_a")
    explicit = lg.derive(lg.examples.rc_rl_circuit()).explicit
    assert set(explicit) == {q1d, q2dd}
    assert_same(explicit[q1d], ((-q1 + q2) / C + u_a) / R)
    assert_same(explicit[q2dd], (-R_L * q2d + (q1 - q2) / C) / L)
    # The notes' state form with u_C = (q1 - q2)/C and i_L = q2_dot.
    u_c, i_L = (q1 - q2) / C, q2d
    assert_same((explicit[q1d] - q2d) / C, (-u_c / R - i_L + u_a / R) / C)
    assert_same(explicit[q2dd], (u_c - R_L * i_L) / L)


def test_rc_rl_has_no_explicit_accelerations() -> None:
    eom = lg.derive(lg.examples.rc_rl_circuit())
    with pytest.raises(lg.DerivationError, match=r"mass matrix is singular.*q1.: 1"):
        _ = eom.explicit_accelerations


# -- capacitor microphone ---------------------------------------------------------------------


def test_capacitor_microphone_equations() -> None:
    x, q = sp.symbols("x q")
    xd, qd, xdd, qdd = sp.symbols("x_dot q_dot x_ddot q_ddot")
    m, K, B, f, L, R, v, eps, A, x0 = sp.symbols("m K B f L R v eps A x0")
    eom = lg.derive(lg.examples.capacitor_microphone())
    expected = [
        m * xdd + B * xd + K * x - q**2 / (2 * eps * A) - f,
        L * qdd + R * qd + (x0 - x) * q / (eps * A) - v,
    ]
    assert_same_vector(eom.equations, expected)


def test_capacitor_microphone_energies() -> None:
    x, q = sp.symbols("x q")
    xd, qd = sp.symbols("x_dot q_dot")
    m, K, L, eps, A, x0 = sp.symbols("m K L eps A x0")
    eom = lg.derive(lg.examples.capacitor_microphone())
    assert_same(eom.kinetic_energy, m * xd**2 / 2 + L * qd**2 / 2)
    assert_same(eom.potential_energy, K * x**2 / 2 + q**2 * (x0 - x) / (2 * eps * A))
    assert eom.mass_matrix == sp.diag(m, L)


# -- robot arm --------------------------------------------------------------------------------

THETA, R_ = sp.symbols("theta r")
THETA_D, R_D, THETA_DD, R_DD = sp.symbols("theta_dot r_dot theta_ddot r_ddot")


def test_robot_arm_equations() -> None:
    m, g, B1, B2, tau, f = sp.symbols("m g B1 B2 tau f")
    eom = lg.derive(lg.examples.robot_arm())
    expected = [
        m * R_**2 * THETA_DD
        + 2 * m * R_ * R_D * THETA_D
        + m * g * R_ * sp.cos(THETA)
        + B1 * THETA_D
        - tau,
        m * R_DD - m * R_ * THETA_D**2 + m * g * sp.sin(THETA) + B2 * R_D - f,
    ]
    assert_same_vector(eom.equations, expected)


def test_robot_arm_partial_derivatives() -> None:
    m, g, B1, B2 = sp.symbols("m g B1 B2")
    steps = lg.derive(lg.examples.robot_arm()).steps
    assert_same_vector([s.dL_dvelocity for s in steps], [m * R_**2 * THETA_D, m * R_D])
    assert_same_vector(
        [s.dL_dcoordinate for s in steps],
        [-m * g * R_ * sp.cos(THETA), m * R_ * THETA_D**2 - m * g * sp.sin(THETA)],
    )
    assert_same_vector([s.dF_dvelocity for s in steps], [B1 * THETA_D, B2 * R_D])


def test_robot_arm_matrix_form() -> None:
    m, g, B1, B2, tau, f = sp.symbols("m g B1 B2 tau f")
    eom = lg.derive(lg.examples.robot_arm())
    assert_same_vector(eom.mass_matrix, [m * R_**2, 0, 0, m])
    assert_same_vector(eom.gravity, [m * g * R_ * sp.cos(THETA), m * g * sp.sin(THETA)])
    # The notes' matrix [[B1, 2 m r theta_dot], [-m r theta_dot, B2]] mixes damping into C;
    # ours keeps C q_dot and the damping forces -dF/dq_dot apart.
    assert_same_vector(eom.coriolis, [2 * m * R_ * R_D * THETA_D, -m * R_ * THETA_D**2])
    assert_same_vector(eom.dissipation_forces, [-B1 * THETA_D, -B2 * R_D])
    assert_same_vector(eom.generalized_forces, [tau, f])
    notes_matrix = sp.Matrix([[B1, 2 * m * R_ * THETA_D], [-m * R_ * THETA_D, B2]])
    velocities = sp.Matrix([THETA_D, R_D])
    assert_same_vector(eom.coriolis - eom.dissipation_forces, list(notes_matrix * velocities))


def test_robot_arm_full_matrix_equation() -> None:
    m, g, B1, B2, tau, f = sp.symbols("m g B1 B2 tau f")
    eom = lg.derive(lg.examples.robot_arm())
    accelerations = sp.Matrix([THETA_DD, R_DD])
    # M q_ddot + V(q, q_dot) + G = Q, the notes' final matrix equation, as residuals.
    notes = (
        sp.Matrix([[m * R_**2, 0], [0, m]]) * accelerations
        + sp.Matrix([[B1, 2 * m * R_ * THETA_D], [-m * R_ * THETA_D, B2]])
        * sp.Matrix([THETA_D, R_D])
        + sp.Matrix([m * g * R_ * sp.cos(THETA), m * g * sp.sin(THETA)])
        - sp.Matrix([tau, f])
    )
    ours = eom.mass_matrix * accelerations - eom.forcing
    assert_same_vector(ours, list(notes))
    assert_same_vector(eom.equations, list(notes))


# -- servo system -----------------------------------------------------------------------------

Q1, Q2, Q3 = sp.symbols("q1 q2 q3")
I_S, I_R, OMEGA = sp.symbols("q1_dot q2_dot q3_dot")
DI_S, DI_R, DOMEGA = sp.symbols("q1_ddot q2_ddot q3_ddot")
Ls, Lr, LM, J, ks = sp.symbols("Ls Lr LM J ks")
Rs, Rr, Bm, us, ur, T_L = sp.symbols("Rs Rr Bm us ur T_L")


def servo_notes_equations() -> list[sp.Expr]:
    """The notes' three differential equations, i_s = q1_dot, i_r = q2_dot, theta_r = q3."""
    s, c = sp.sin(Q3), sp.cos(Q3)
    return [
        Ls * DI_S + LM * c * DI_R - LM * I_R * s * OMEGA + Rs * I_S - us,
        Lr * DI_R + LM * c * DI_S - LM * I_S * s * OMEGA + Rr * I_R - ur,
        J * DOMEGA + LM * I_S * I_R * s + Bm * OMEGA + ks * Q3 + T_L,
    ]


def test_servo_equations(servo: lg.EquationsOfMotion) -> None:
    assert_same_vector(servo.equations, servo_notes_equations())


def test_servo_partial_derivatives(servo: lg.EquationsOfMotion) -> None:
    first, second, third = servo.steps
    # dKe/dq_dot = dL/dq_dot (V has no velocities).
    assert_same(first.dL_dvelocity, Ls * I_S + LM * I_R * sp.cos(Q3))
    assert_same(second.dL_dvelocity, LM * I_S * sp.cos(Q3) + Lr * I_R)
    assert_same(third.dL_dvelocity, J * OMEGA)
    # dL/dq = dKe/dq - dV/dq.
    assert_same(first.dL_dcoordinate, 0)
    assert_same(second.dL_dcoordinate, 0)
    assert_same(third.dL_dcoordinate, -LM * I_S * I_R * sp.sin(Q3) - ks * Q3)
    assert_same_vector([s.dF_dvelocity for s in servo.steps], [Rs * I_S, Rr * I_R, Bm * OMEGA])
    assert_same_vector([s.generalized_force for s in servo.steps], [us, ur, -T_L])


def test_servo_kinetic_energy(servo: lg.EquationsOfMotion) -> None:
    expected = Ls * I_S**2 / 2 + LM * I_S * I_R * sp.cos(Q3) + Lr * I_R**2 / 2 + J * OMEGA**2 / 2
    assert_same(servo.kinetic_energy, expected)
    assert servo.mass_matrix == sp.Matrix(
        [[Ls, LM * sp.cos(Q3), 0], [LM * sp.cos(Q3), Lr, 0], [0, 0, J]]
    )


def test_servo_accelerations_match_a_numeric_solve(servo: lg.EquationsOfMotion) -> None:
    rng = random.Random(2024)
    symbols = [Q1, Q2, Q3, I_S, I_R, OMEGA, Ls, Lr, J, ks, Rs, Rr, Bm, us, ur, T_L]
    values = {s: rng.uniform(0.5, 2.0) for s in symbols}
    values[LM] = 0.5 * min(values[Ls], values[Lr])  # keeps the inductances positive definite
    # The notes' equations are linear in the accelerations: A a = b with b = -residual(a = 0).
    equations = [e.subs(values) for e in servo_notes_equations()]
    unknowns = [DI_S, DI_R, DOMEGA]
    a = np.array([[float(e.diff(u)) for u in unknowns] for e in equations])
    b = np.array([-float(e.subs(dict.fromkeys(unknowns, 0))) for e in equations])
    reference = np.linalg.solve(a, b)
    ours = np.array([float(e.subs(values)) for e in servo.explicit_accelerations])
    np.testing.assert_allclose(ours, reference, rtol=1e-12)


def test_servo_state_space_as_corrected_in_the_module(servo: lg.EquationsOfMotion) -> None:
    """The state-space formulas of the servo_system model file's comment (the notes' with typos
    fixed) are what the derivation gives."""
    s, c = sp.sin(Q3), sp.cos(Q3)
    det = Ls * Lr - LM**2 * c**2
    di_s = (
        -Rs * Lr * I_S
        - LM**2 * I_S * OMEGA * sp.sin(2 * Q3) / 2
        + Rr * LM * I_R * c
        + Lr * LM * I_R * OMEGA * s
        + Lr * us
        - LM * c * ur
    ) / det
    di_r = (
        Rs * LM * I_S * c
        + Ls * LM * I_S * OMEGA * s
        - Rr * Ls * I_R
        - LM**2 * I_R * OMEGA * sp.sin(2 * Q3) / 2
        - LM * c * us
        + Ls * ur
    ) / det
    domega = (-LM * I_S * I_R * s - Bm * OMEGA - ks * Q3 - T_L) / J
    assert_same_vector(servo.explicit_accelerations, [di_s, di_r, domega])
