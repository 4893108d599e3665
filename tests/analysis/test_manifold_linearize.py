"""Linearization on the constraint manifold against independent references.

- a pendulum in Cartesian coordinates (x, y on x^2 + y^2 = l^2) against the angle form:
  omega = sqrt(g/l) about the bottom, growth rate sqrt(g/l) at the top;
- the same pendulum against sympy.physics.mechanics' Linearizer (LagrangesMethod with the
  holonomic constraint, to_linearizer with the same independent coordinate), at a generic
  state that is not an equilibrium;
- the rolling disc (examples/rolling_disc) against sympy.physics.mechanics.KanesMethod with
  the two rolling constraints as velocity constraints (dependent speeds x_dot, y_dot), and the
  classical result that upright steady rolling of a thin disc is stable exactly above the
  spin rate sqrt(g/(3 r)) (Neimark and Fufaev, Dynamics of Nonholonomic Systems, ch. 3).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.analysis import linearize
from lagrangian.errors import AnalysisError, ConstraintError

sys.path.insert(0, str(Path(__file__).parents[1] / "constraints"))
import constraint_systems as cs

G, L_ROD, MASS = 9.81, 0.7, 1.3
g, l, m = sp.symbols("g l m")


def test_cartesian_pendulum_at_the_bottom_is_the_angle_form() -> None:
    lin = linearize(cs.pendulum(), {"x": 0, "y": "-l"})
    assert lin.state_vector == (sp.Symbol("x"), sp.Symbol("x_dot"))
    assert [s.name for s in lin.dependent] == ["y", "y_dot"]
    assert sp.simplify(lin.A - sp.Matrix([[0, 1], [-g / l, 0]])) == sp.zeros(2)
    assert [float(w) for w in lin.frequencies] == pytest.approx([math.sqrt(G / L_ROD)])
    assert lin.is_solution and "equilibrium on the constraint manifold" in lin.note
    # the rod pulls up with m g: lambda dh/dy = 2 lambda y = m g at y = -l
    (lam,) = lin.multipliers.values()
    assert sp.simplify(2 * lam * (-l) - m * g) == 0


def test_cartesian_pendulum_at_the_top_grows_at_sqrt_g_over_l() -> None:
    lin = linearize(cs.pendulum(), {"x": 0, "y": L_ROD})
    assert [float(s) for s in lin.growth_rates] == pytest.approx([math.sqrt(G / L_ROD)])


def test_the_dependent_deviations_follow_the_independent_ones() -> None:
    state = cs.pendulum_state(0.5, 0.0)
    lin = linearize(cs.pendulum(), state, independent=["x", "x_dot"])
    assert [s.name for s in lin.state_vector] == ["x", "x_dot"]
    # on the circle dy = -x/y dx (tangent at the state)
    full = lin.full_deviation([1, 0])
    assert float(full[1]) == pytest.approx(-state["x"] / state["y"])
    # x_ddot = -g x sqrt(l^2 - x^2)/l^2 on the circle at rest, so at x = l sin(theta)
    # d x_ddot/dx = -(g/l) cos(2 theta)/cos(theta): the instantaneous frequency in x
    frequencies = [float(w) for w in lin.frequencies]
    expected = math.sqrt(G / L_ROD * math.cos(1.0) / math.cos(0.5))
    assert frequencies == pytest.approx([expected], rel=1e-9)
    assert not lin.is_solution


def _sympy_pendulum_linearization(state: dict[str, float]) -> sp.Matrix:
    """A of the Cartesian pendulum by LagrangesMethod.to_linearizer (x independent), about
    ``state`` with its accelerations and multiplier found by LagrangesMethod."""
    x, y = me.dynamicsymbols("x y")
    xd, yd = me.dynamicsymbols("x y", 1)
    lagrangian = m * (xd**2 + yd**2) / 2 - m * g * y
    method = me.LagrangesMethod(lagrangian, [x, y], hol_coneqs=[x**2 + y**2 - l**2])
    method.form_lagranges_equations()
    linearizer = method.to_linearizer(q_ind=[x], qd_ind=[xd], q_dep=[y], qd_dep=[yd])
    values = {m: MASS, g: G, l: L_ROD}
    point = {x: state["x"], y: state["y"], xd: state["x_dot"], yd: state["y_dot"]}
    rates = method.rhs().subs({**point, **values})  # [x_dot, y_dot, x_ddot, y_ddot, ...]
    point.update({xd.diff(): rates[2], yd.diff(): rates[3]})
    # the multiplier of LagrangesMethod.eom (rhs() has it with the other sign, sympy #30215)
    point.update(method.solve_multipliers({**point, **values}, sol_type="dict"))
    a, _ = linearizer.linearize(op_point=[point, values], A_and_B=True)
    return sp.Matrix(a).subs(values)


def _entries(matrix: sp.MatrixBase) -> list[float]:
    return [float(e) for e in matrix]


def test_cartesian_pendulum_agrees_with_sympy_linearizer_at_a_generic_state() -> None:
    state = cs.pendulum_state(0.8, 1.7)
    expected = _sympy_pendulum_linearization(state)
    lin = linearize(cs.pendulum(), state, independent=["x", "x_dot"])
    ours = lin.A.subs({m: MASS, g: G, l: L_ROD})
    assert _entries(ours) == pytest.approx(_entries(expected), rel=1e-9, abs=1e-9)
    assert not lin.is_solution and "not a solution" in lin.note


def _kane_rolling_disc() -> tuple[me.KanesMethod, list, list]:
    """The thin disc of examples/rolling_disc by Kane's method: q = (x, y, psi, theta, phi)
    with ZXY angles, u = q_dot, x_dot and y_dot dependent through the rolling constraints."""
    x, y, psi, theta, phi = q = list(me.dynamicsymbols("x y psi theta phi"))
    u = list(me.dynamicsymbols("u1:6"))
    r = sp.Symbol("r")
    frame = me.ReferenceFrame("N")
    disc_frame = frame.orientnew("D", "Body", (psi, theta, phi), "ZXY")
    origin = me.Point("O")
    origin.set_vel(frame, 0)
    lift = r * (sp.sin(psi) * sp.sin(theta) * frame.x - sp.cos(psi) * sp.sin(theta) * frame.y)
    centre = origin.locatenew("G", x * frame.x + y * frame.y + lift + r * sp.cos(theta) * frame.z)
    speeds = {qi.diff(): ui for qi, ui in zip(q, u)}
    disc_frame.set_ang_vel(frame, disc_frame.ang_vel_in(frame).subs(speeds))
    centre.set_vel(frame, centre.pos_from(origin).dt(frame).subs(speeds))
    inertia = me.inertia(disc_frame, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    disc = me.RigidBody("disc", centre, disc_frame, m, (inertia, centre))
    method = me.KanesMethod(
        frame,
        q_ind=q,
        u_ind=u[2:],
        u_dependent=u[:2],
        kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)],
        velocity_constraints=[u[0] - r * u[4] * sp.cos(psi), u[1] - r * u[4] * sp.sin(psi)],
    )
    method.kanes_equations([disc], [(centre, -m * g * frame.z)])
    return method, q, u


@pytest.mark.slow
def test_rolling_disc_agrees_with_sympy_kanes_method() -> None:
    method, q, u = _kane_rolling_disc()
    values = {m: 1.0, g: 9.81, sp.Symbol("r"): 0.3}
    spin = 4.0
    point = {**dict.fromkeys(q, 0), **dict.fromkeys(u, 0), **{ui.diff(): 0 for ui in u}}
    point.update({u[0]: 0.3 * spin, u[4]: spin})
    expected, _, _ = method.linearize(op_point=[point, values], A_and_B=True)
    lin = linearize(lg.examples.rolling_disc(), {"phi_dot": spin, "x_dot": 0.3 * spin})
    assert [s.name for s in lin.state_vector] == [
        "x",
        "y",
        "psi",
        "theta",
        "phi",
        "psi_dot",
        "theta_dot",
        "phi_dot",
    ]
    assert _entries(lin.A.subs(values)) == pytest.approx(_entries(expected), abs=1e-12)


@pytest.mark.parametrize("factor", [0.9, 0.99, 1.01, 1.5])
def test_upright_rolling_is_stable_above_the_critical_spin(factor: float) -> None:
    critical = math.sqrt(9.81 / (3 * 0.3))  # sqrt(g / (3 r)) for a thin disc
    spin = factor * critical
    lin = linearize(lg.examples.rolling_disc(), {"phi_dot": spin, "x_dot": 0.3 * spin})
    assert lin.is_solution and "steady motion" in lin.note
    assert [s.name for s in lin.dependent] == ["x_dot", "y_dot"]
    assert bool(lin.growth_rates) is (factor < 1)


def test_a_state_off_the_constraints_is_refused_with_its_residual() -> None:
    with pytest.raises(ConstraintError, match=r"'rod' \(constraints\[0\]\).*-0\.48"):
        linearize(cs.pendulum(), {"x": 0.1, "y": 0.0})
    with pytest.raises(ConstraintError, match="velocity level"):
        linearize(lg.examples.rolling_disc(), {"phi_dot": 5.0})


def test_independent_coordinates_the_constraints_cannot_fix_are_refused() -> None:
    # at the bottom x^2 + y^2 = l^2 fixes y, not x
    with pytest.raises(AnalysisError, match="leave x to be eliminated"):
        linearize(cs.pendulum(), {"x": 0, "y": -L_ROD}, independent=["y"])
