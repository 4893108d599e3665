"""Rolling contact beyond the thin disc: a wheel with a round tyre (a torus) and a ball on the
plane z = 0.  The torus wheel is checked against sympy.physics.mechanics' KanesMethod with its
contact point C = G - R L.z - r_t N.z (its material velocity as the nonholonomic constraints),
the ball against the closed forms of a uniform ball rolling without slipping."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from kane_rolling import numbers, plain_symbols

import lagrangian as lg
from lagrangian.constraints import constrained_equations
from lagrangian.errors import ModelError
from lagrangian.model import Frame, RigidBody, RollingDisc, System, shape
from lagrangian.model.contact import ContactHeight, NoSlip, rolling_sphere
from lagrangian.symbolic.symbols import t

TIME = me.dynamicsymbols._t
x, y, z, psi, theta, phi = sp.symbols("x y z psi theta phi")
m, g, R, rt, A, C = sp.symbols("m g R r_t A C")
FRAMES = [Frame("heading", [("z", psi)]), Frame("lean", [("x", theta)], parent="heading")]
VALUES = {m: 1.3, g: 9.81, R: 0.3, rt: 0.05, A: 0.04, C: 0.07}


def torus_wheel(free_height: bool = False) -> System:
    """Centre (x, y, z or R cos(theta) + r_t), heading psi, lean theta, spin phi about y."""
    height = z if free_height else R * sp.cos(theta) + rt
    wheel = RigidBody(
        "wheel", m, sp.diag(A, C, A), (x, y, height), parent="lean", rotations=[("y", phi)]
    )
    return System(
        coordinates=[x, y, *([z] if free_height else []), psi, theta, phi],
        parameters=VALUES,
        gravity=(0, 0, -g),
        frames=FRAMES,
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", R, "y", tyre_radius=rt)],
    )


def test_the_torus_touches_at_the_lowest_point_of_its_tyre() -> None:
    system = torus_wheel(free_height=True)
    height, slip_x, slip_y = system.constraints
    assert isinstance(height, ContactHeight)
    assert isinstance(slip_x, NoSlip) and isinstance(slip_y, NoSlip)
    assert sp.expand(height.expression - (z - R * sp.cos(theta) - rt)) == 0
    # written at the contact height, the holonomic constraint holds identically
    assert [type(c) for c in torus_wheel().constraints] == [NoSlip, NoSlip]


def _kane_torus() -> tuple[me.KanesMethod, list, dict]:
    """mechanics' torus wheel in the same coordinates; x' and y' dependent."""
    q = me.dynamicsymbols("x y psi theta phi")
    u = me.dynamicsymbols("u_x u_y u_psi u_theta u_phi")
    world, heading, lean, disc = (me.ReferenceFrame(n) for n in ("N", "Y", "L", "D"))
    heading.orient_axis(world, world.z, q[2])
    lean.orient_axis(heading, heading.x, q[3])
    disc.orient_axis(lean, lean.y, q[4])
    speeds = {qi.diff(TIME): ui for qi, ui in zip(q, u)}
    origin = me.Point("O")
    origin.set_vel(world, 0)
    height = R * sp.cos(q[3]) + rt
    centre = origin.locatenew("G", q[0] * world.x + q[1] * world.y + height * world.z)
    centre.set_vel(world, centre.pos_from(origin).dt(world).xreplace(speeds))
    disc.set_ang_vel(world, disc.ang_vel_in(world).xreplace(speeds))
    contact = centre.locatenew("P", -R * lean.z - rt * world.z)
    contact.v2pt_theory(centre, world, disc)
    slip = [contact.vel(world).dot(world.x), contact.vel(world).dot(world.y)]
    kane = me.KanesMethod(
        world,
        q,
        u[2:],
        kd_eqs=[qi.diff(TIME) - ui for qi, ui in zip(q, u)],
        u_dependent=u[:2],
        velocity_constraints=slip,
    )
    body = me.RigidBody("wheel", centre, disc, m, (me.inertia(disc, A, C, A), centre))
    kane.kanes_equations([body], [(centre, -m * g * world.z)])
    plain = plain_symbols(q, u)
    return kane, [s.xreplace(plain) for s in slip], plain


def test_the_torus_wheel_matches_kanes_method_at_random_rolling_states() -> None:
    system = torus_wheel()
    kane, slip, plain = _kane_torus()
    equations = constrained_equations(system)
    x_dot, y_dot = system.velocities[:2]
    rng = random.Random(11)
    for _ in range(3):
        values: dict = dict(VALUES)
        values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
        values.update({s: rng.uniform(-2.0, 2.0) for s in system.velocities})
        values[t] = 0.0
        values[x_dot] = values[x_dot] - float(slip[0].xreplace(values))
        values[y_dot] = values[y_dot] - float(slip[1].xreplace(values))
        solution = np.linalg.solve(
            numbers(equations.augmented_matrix, values),
            numbers(equations.augmented_rhs, values)[:, 0],
        )
        mass = numbers(kane.mass_matrix_full.xreplace(plain), values)
        forcing = numbers(kane.forcing_full.xreplace(plain), values)[:, 0]
        theirs = np.linalg.solve(mass, forcing)[5:]
        order = [2, 3, 4, 0, 1]  # mechanics: independent speeds first
        np.testing.assert_allclose(solution[:5][order], theirs, rtol=1e-9, atol=1e-9)


# -- a ball ---------------------------------------------------------------------------------


a, b, c, F, r = sp.symbols("a b c F r")


def ball(forces: tuple = (), torques: tuple = ()) -> System:
    """A uniform solid ball of radius r, centre (x, y, r), oriented by z-y-x angles a, b, c."""
    body = RigidBody(
        "ball",
        m,
        shape("solid_sphere", radius=r),
        (x, y, r),
        rotations=[("z", a), ("y", b), ("x", c)],
    )
    return System(
        coordinates=[x, y, a, b, c],
        parameters={m: 2.0, g: 9.81, r: 0.1, F: 1.5},
        gravity=(0, 0, -g),
        rigid_bodies=[body],
        rolling=[rolling_sphere("ball", r)],
        forces=list(forces),
        torques=list(torques),
    )


def _accelerations(system: System, values: dict) -> np.ndarray:
    """q_ddot from the multiplier form at a state that satisfies the constraints."""
    equations = constrained_equations(system)
    n = len(system.coordinates)
    solution = np.linalg.solve(
        numbers(equations.augmented_matrix, values),
        numbers(equations.augmented_rhs, values)[:, 0],
    )
    return solution[:n]


def _state_at_rest(system: System, rng: random.Random) -> dict:
    values: dict = {p: v for p, v in system.parameters.items()}
    values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
    values.update({s: 0.0 for s in system.velocities})
    values[t] = 0.0
    return values


def test_the_ball_makes_the_no_slip_constraints_of_its_lowest_point() -> None:
    system = ball()
    assert [type(con) for con in system.constraints] == [NoSlip, NoSlip]
    # v_C = v_G + omega x (-r e_z): x_dot - r omega_y = 0, y_dot + r omega_x = 0
    omega = lg.model.spatial_angular_velocity(system.rigid_bodies[0].orientation, [x, y, a, b, c])
    x_dot, y_dot = system.velocities[:2]
    slip_x, slip_y = (con.expression for con in system.constraints)
    assert sp.simplify(slip_x - (x_dot - r * omega[1])) == 0
    assert sp.simplify(slip_y - (y_dot + r * omega[0])) == 0


@pytest.mark.parametrize(
    ("height", "expected"),
    [(1, sp.Rational(5, 7)), (2, sp.Rational(10, 7)), (0, 0)],
)
def test_a_pushed_ball_accelerates_as_the_closed_form_says(height: int, expected) -> None:
    """A horizontal force F on a uniform ball rolling without slipping, applied at height h
    above the ground (on the vertical through the centre): m a = F + f, I alpha = ... give
    a = F (1 + (h - r) r m / I) / (m (1 + m r^2 / I)) = (5/7) (h / r) F / m for I = 2/5 m r^2
    (at the centre 5F/7m, at the top 10F/7m, at the contact point 0: it does no work)."""
    at = "ball_contact" if height == 0 else "ball"
    push = (lg.Force(at, (F, 0, 0), name="push"),)
    # at the top: the force at the centre and its moment r e_z x F
    moment = (lg.Torque("ball", (0, r * F, 0), name="push moment"),) if height == 2 else ()
    system = ball(push, moment)
    values = _state_at_rest(system, random.Random(5 + height))
    found = _accelerations(system, values)
    assert found[0] == pytest.approx(float(expected * 1.5 / 2.0), abs=1e-12)
    assert found[1] == pytest.approx(0.0, abs=1e-12)


def test_a_ball_given_no_contact_radius_is_refused() -> None:
    with pytest.raises(ModelError, match=r"rolling\[0\].tyre_radius.*unknown name 'rho'"):
        ball().replace(rolling=[rolling_sphere("ball", sp.Symbol("rho"))])
