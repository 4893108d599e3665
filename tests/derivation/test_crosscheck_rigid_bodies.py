"""The 3-D rigid-body examples (model files) against sympy.physics.mechanics built
independently on the same system: RigidBody, frames oriented by mechanics' own methods, and
KanesMethod.  Compared: the mass matrix and the accelerations at random states and parameters
(constrained examples: the accelerations with the constraints enforced, at states that satisfy
them), and for every example the Newton–Euler equations of its body projected on the
coordinates against its Euler–Lagrange equations."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from test_rigid_body_3d import TIME, assert_same_motion, kanes

import lagrangian as lg
from lagrangian.constraints import constrained_equations
from lagrangian.derivation import check_newton_euler
from lagrangian.model.rotation import evaluate_matrix
from lagrangian.symbolic.symbols import t


def _fixed_point() -> tuple[me.ReferenceFrame, me.Point]:
    frame = me.ReferenceFrame("N")
    origin = me.Point("O")
    origin.set_vel(frame, 0)
    return frame, origin


def test_heavy_symmetric_top_matches_kanes_method() -> None:
    q = me.dynamicsymbols("phi theta psi")
    m, g, l, A, C = sp.symbols("m g l A C")
    frame, tip = _fixed_point()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, q, "ZXZ")
    centre = tip.locatenew("G", l * body.z)
    centre.v2pt_theory(tip, frame, body)
    top = me.RigidBody("top", centre, body, m, (me.inertia(body, A, A, C), centre))
    reference = kanes(frame, q, [top], [(centre, -m * g * frame.z)])
    assert_same_motion(lg.examples.heavy_symmetric_top(), reference)


def test_asymmetric_body_matches_kanes_method() -> None:
    q = me.dynamicsymbols("phi theta psi")
    m, I1, I2, I3 = sp.symbols("m I1 I2 I3")
    frame, centre = _fixed_point()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, q, "ZXZ")
    rigid = me.RigidBody("body", centre, body, m, (me.inertia(body, I1, I2, I3), centre))
    assert_same_motion(lg.examples.asymmetric_body(), kanes(frame, q, [rigid], []))


def test_physical_pendulum_3d_matches_kanes_method() -> None:
    q = me.dynamicsymbols("a b c")
    m, g, wx, wy, h = sp.symbols("m g w_x w_y h")
    frame, joint = _fixed_point()
    body = me.ReferenceFrame("B")
    body.orient_body_fixed(frame, q, "XYZ")
    centre = joint.locatenew("G", -h / 2 * body.z)
    centre.v2pt_theory(joint, frame, body)
    moments = (m * (wy**2 + h**2) / 12, m * (wx**2 + h**2) / 12, m * (wx**2 + wy**2) / 12)
    inertia = me.inertia(body, *moments)
    box = me.RigidBody("box", centre, body, m, (inertia, centre))
    reference = kanes(frame, q, [box], [(centre, -m * g * frame.z)])
    assert_same_motion(lg.examples.physical_pendulum_3d(), reference)


# -- the constrained examples ------------------------------------------------------------------


def _numbers(expr: sp.Basic, values: dict) -> np.ndarray:
    result = evaluate_matrix(sp.Matrix(expr), values)
    assert result is not None
    return result


def _constrained_accelerations(system: lg.System, values: dict) -> np.ndarray:
    """q_ddot from [[M, -A^T], [A, 0]] [q_ddot; lambda] = [forcing; gamma] at ``values``."""
    equations = constrained_equations(system)
    matrix = _numbers(equations.augmented_matrix, values)
    rhs = _numbers(equations.augmented_rhs, values)[:, 0]
    return np.linalg.solve(matrix, rhs)[: len(system.coordinates)]


def _kane_accelerations(kane: me.KanesMethod, swap: dict, values: dict) -> np.ndarray:
    mass = _numbers(kane.mass_matrix.xreplace(swap), values)
    forcing = _numbers(kane.forcing.xreplace(swap), values)[:, 0]
    return np.linalg.solve(mass, forcing)


def _speeds_to_plain(q, u) -> dict:
    """mechanics' q(t), u(t) -> lagrangian's plain q, q_dot symbols."""
    swap: dict = {TIME: t}
    for qi, ui in zip(q, u):
        name = qi.func.__name__
        swap[ui] = sp.Symbol(name + "_dot")
        swap[qi] = sp.Symbol(name)
    return swap


def test_rolling_disc_matches_kanes_method_with_dependent_speeds() -> None:
    """Kane: the heading, lean and spin rates independent, the contact velocity dependent
    (x' = r phi' cos(psi), y' = r phi' sin(psi)); all five accelerations compared."""
    q = me.dynamicsymbols("x y psi theta phi")
    x, y, psi, theta, phi = q
    u = me.dynamicsymbols("u_x u_y u_psi u_theta u_phi")
    m, g, r = sp.symbols("m g r")
    frame, origin = _fixed_point()
    lean = me.ReferenceFrame("L")
    lean.orient_body_fixed(frame, (psi, theta, 0), "ZXY")
    disc = me.ReferenceFrame("D")
    disc.orient_axis(lean, lean.y, phi)
    to_speeds = {qi.diff(TIME): ui for qi, ui in zip(q, u)}
    centre = origin.locatenew("G", x * frame.x + y * frame.y + r * lean.z)
    centre.set_vel(frame, centre.pos_from(origin).dt(frame).xreplace(to_speeds))
    disc.set_ang_vel(frame, disc.ang_vel_in(frame).xreplace(to_speeds))
    inertia = me.inertia(disc, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    body = me.RigidBody("disc", centre, disc, m, (inertia, centre))
    kane = me.KanesMethod(
        frame,
        q,
        u[2:],
        kd_eqs=[qi.diff(TIME) - ui for qi, ui in zip(q, u)],
        u_dependent=u[:2],
        velocity_constraints=[u[0] - r * u[4] * sp.cos(psi), u[1] - r * u[4] * sp.sin(psi)],
    )
    kane.kanes_equations([body], [(centre, -m * g * frame.z)])
    # mechanics orders the speeds independent first: (psi, theta, phi, x, y)
    order = [2, 3, 4, 0, 1]
    system = lg.examples.rolling_disc()
    rng = random.Random(5)
    for _ in range(3):
        values = _rolling_state(system, rng)
        ours = _constrained_accelerations(system, values)
        theirs = _kane_accelerations(kane, _speeds_to_plain(q, u), values)
        np.testing.assert_allclose(ours[order], theirs, rtol=1e-9, atol=1e-9)


def _rolling_state(system: lg.System, rng: random.Random) -> dict:
    """A random state on the rolling constraints (x_dot, y_dot from phi_dot and psi)."""
    values = {p: rng.uniform(0.5, 1.5) for p in system.parameters}
    values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
    values.update({s: rng.uniform(-2.0, 2.0) for s in system.velocities})
    named = {s.name: s for s in (*system.coordinates, *system.velocities, *system.parameters)}
    spin, heading, r = named["phi_dot"], named["psi"], named["r"]
    values[named["x_dot"]] = values[r] * values[spin] * np.cos(values[heading])
    values[named["y_dot"]] = values[r] * values[spin] * np.sin(values[heading])
    values[t] = 0.0
    return values


def test_cylinder_on_incline_matches_kanes_method_in_the_rolling_coordinate() -> None:
    """Kane in phi alone (x = r phi substituted); ours with the constraint x - r phi = 0."""
    phi, u = me.dynamicsymbols("phi u_phi")
    q = [phi]
    m, g, r, length, alpha = sp.symbols("m g r length alpha")
    frame, origin = _fixed_point()
    down = sp.cos(alpha) * frame.x - sp.sin(alpha) * frame.z
    normal = sp.sin(alpha) * frame.x + sp.cos(alpha) * frame.z
    body = me.ReferenceFrame("B")
    body.orient_axis(frame, frame.y, phi)
    centre = origin.locatenew("G", r * phi * down + r * normal)
    centre.set_vel(frame, centre.pos_from(origin).dt(frame).xreplace({phi.diff(TIME): u}))
    body.set_ang_vel(frame, body.ang_vel_in(frame).xreplace({phi.diff(TIME): u}))
    across = m * r**2 / 4 + m * length**2 / 12
    inertia = me.inertia(body, across, m * r**2 / 2, across)
    cylinder = me.RigidBody("cylinder", centre, body, m, (inertia, centre))
    kane = me.KanesMethod(frame, q, [u], kd_eqs=[phi.diff(TIME) - u])
    kane.kanes_equations([cylinder], [(centre, -m * g * frame.z)])
    system = lg.examples.cylinder_on_incline()
    x, phi_symbol = system.coordinates
    rng = random.Random(2)
    for _ in range(3):
        values = {p: rng.uniform(0.3, 1.2) for p in system.parameters}
        values[phi_symbol] = rng.uniform(-2.0, 2.0)
        values[lg.velocity(phi_symbol)] = rng.uniform(-2.0, 2.0)
        radius = values[sp.Symbol("r")]
        values[x] = radius * values[phi_symbol]
        values[lg.velocity(x)] = radius * values[lg.velocity(phi_symbol)]
        values[t] = 0.0
        ours = _constrained_accelerations(system, values)
        (theirs,) = _kane_accelerations(kane, _speeds_to_plain(q, [u]), values)
        np.testing.assert_allclose(ours, [radius * theirs, theirs], rtol=1e-10)


@pytest.mark.parametrize(
    "name",
    [
        "heavy_symmetric_top",
        "asymmetric_body",
        "physical_pendulum_3d",
        "rolling_disc",
        "cylinder_on_incline",
    ],
)
def test_the_newton_euler_equations_of_each_example_agree_with_euler_lagrange(name: str) -> None:
    check = check_newton_euler(lg.examples.get(name)())
    assert check.agree, check.summary()
