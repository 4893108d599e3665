"""The rolling-contact element: a thin disc rolling without slipping on z = 0 (Greenwood,
Advanced Dynamics §3.4; Neimark & Fufaev ch. 1), built from a heading frame, a lean frame and
the spinning wheel.  Checked: the constraints it makes and their classification, the
accelerations against sympy.physics.mechanics' KanesMethod with the contact point's velocity as
its nonholonomic constraints, the stability of upright rolling (a thin uniform disc rolls
upright stably when Omega^2 > g/(3 r)), and energy conservation in simulation."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from kane_rolling import numbers, plain_symbols

import lagrangian as lg
from lagrangian.constraints import classify, constrained_equations
from lagrangian.derivation import check_newton_euler
from lagrangian.errors import ModelError
from lagrangian.io.dump import dumps
from lagrangian.model import Frame, RigidBody, RollingDisc, System, shape
from lagrangian.model.contact import ContactHeight, NoSlip, contact_point
from lagrangian.symbolic.symbols import t

TIME = me.dynamicsymbols._t
x, y, z, psi, theta, phi = sp.symbols("x y z psi theta phi")
m, g, r = sp.symbols("m g r")
FRAMES = [Frame("heading", [("z", psi)]), Frame("lean", [("x", theta)], parent="heading")]


def rolling_disc(free_height: bool = False) -> System:
    """Centre (x, y, z or r cos(theta)), heading psi, lean theta, spin phi about the axle y."""
    height = z if free_height else r * sp.cos(theta)
    wheel = RigidBody(
        "wheel",
        m,
        shape("disc", radius=r, axis="y"),
        (x, y, height),
        parent="lean",
        rotations=[("y", phi)],
    )
    return System(
        coordinates=[x, y, *([z] if free_height else []), psi, theta, phi],
        parameters={m: 1.0, g: 9.81, r: 0.3},
        gravity=(0, 0, -g),
        frames=FRAMES,
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", r)],
    )


def test_the_disc_makes_two_no_slip_constraints_when_its_height_is_written_out() -> None:
    system = rolling_disc()
    assert [type(c) for c in system.constraints] == [NoSlip, NoSlip]
    x_dot, y_dot, psi_dot, theta_dot, phi_dot = system.velocities[:5]
    (slip_x, slip_y) = (c.expression for c in system.constraints)
    # v_C = v_G + omega x (-r L.z), in world axes (by hand)
    assert (
        sp.expand(
            slip_x
            - (
                x_dot
                - r * phi_dot * sp.cos(psi)
                - r * psi_dot * sp.sin(theta) * sp.cos(psi)
                - r * theta_dot * sp.sin(psi) * sp.cos(theta)
            )
        )
        == 0
    )
    assert (
        sp.expand(
            slip_y
            - (
                y_dot
                - r * phi_dot * sp.sin(psi)
                - r * psi_dot * sp.sin(psi) * sp.sin(theta)
                + r * theta_dot * sp.cos(psi) * sp.cos(theta)
            )
        )
        == 0
    )
    point = contact_point(system.rolling[0], system.rigid_bodies[0])
    assert sp.expand(point[2]) == 0
    assert sp.expand(point[0] - (x - r * sp.sin(psi) * sp.sin(theta))) == 0


def test_the_constraints_hold_the_systems_own_symbols_with_their_assumptions() -> None:
    """A radius declared positive and a steered wheel (the root of its tilt in every term):
    the constraints are made of the System's symbols (a plain symbol of the same name is
    another symbol), and agree with the contact point's height and velocity written
    out by hand."""
    radius, mass = sp.Symbol("R", positive=True), sp.Symbol("M", positive=True)
    steer = sp.Symbol("delta", real=True)
    frames = [*FRAMES, Frame("fork", [("z", steer)], parent="lean")]
    wheel = RigidBody(
        "wheel", mass, shape("disc", radius=radius, axis="y"), (x, y, z), parent="fork"
    )
    system = System(
        coordinates=[x, y, z, psi, theta, steer],
        parameters={mass: 1.0, g: 9.81, radius: 0.3},
        gravity=(0, 0, -g),
        frames=frames,
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", radius)],
    )
    own = {*system.coordinates, *system.parameters, *system.velocities}
    for constraint in system.constraints:
        # a symbol equals another only with the same assumptions: no plain R in place of R
        assert constraint.expression.free_symbols <= own, constraint.expression.free_symbols
    # by hand: v_C = v_p + omega x (C - p), C - p = R (a a_z - e_z) / |a x e_z|
    rotation = sp.rot_axis3(-psi) * sp.rot_axis1(-theta) * sp.rot_axis3(-steer)
    axle = rotation[:, 1]
    down = (axle * axle[2] - sp.Matrix([0, 0, 1])) / sp.sqrt(1 - axle[2] ** 2)
    rates = dict(zip(system.coordinates, system.velocities))
    omega = (
        rates[psi] * sp.Matrix([0, 0, 1])
        + rates[theta] * sp.rot_axis3(-psi)[:, 0]
        + rates[steer] * rotation[:, 2]
    )
    slip = sp.Matrix([rates[x], rates[y], rates[z]]) + omega.cross(radius * down)
    by_name = {c.name: c.expression for c in system.constraints}
    height = by_name["wheel_contact height"]
    assert sp.simplify(height - (z + radius * down[2])) == 0
    rng = random.Random(7)
    values = {s: rng.uniform(0.2, 1.2) for s in sorted(own, key=str)}
    for name, expected in (("x", slip[0]), ("y", slip[1])):
        made = by_name[f"wheel_contact slip {name}"]
        assert abs(float((made - expected).subs(values))) < 1e-12


def test_the_rolling_disc_is_nonholonomic_with_three_independent_velocities() -> None:
    report = classify(rolling_disc())
    assert [c.holonomic for c in report.constraints] == [False, False]
    assert report.integrable_set is False
    assert (report.generic_rank, report.independent_velocities, report.dof) == (2, 3, 5)


def test_a_free_centre_height_adds_the_holonomic_contact() -> None:
    system = rolling_disc(free_height=True)
    assert [type(c) for c in system.constraints] == [ContactHeight, NoSlip, NoSlip]
    assert sp.expand(system.constraints[0].expression - (z - r * sp.cos(theta))) == 0
    report = classify(system)
    assert [c.holonomic for c in report.constraints] == [True, False, False]
    assert (report.holonomic_rank, report.independent_velocities, report.dof) == (1, 3, 5)


def test_the_constraints_are_made_once_through_replace_and_a_model_file() -> None:
    system = rolling_disc()
    assert system.replace(name="again").constraints == system.constraints
    again = lg.loads(dumps(system))
    assert again.constraints == system.constraints


# -- against KanesMethod --------------------------------------------------------------------


def _kane() -> tuple[me.KanesMethod, list, list]:
    """sympy.physics.mechanics' rolling disc in the same coordinates, the contact point's
    material velocity (C.v2pt_theory) as the two nonholonomic constraints, x' and y' dependent."""
    q = me.dynamicsymbols("x y psi theta phi")
    u = me.dynamicsymbols("u_x u_y u_psi u_theta u_phi")
    world, heading, lean, disc = (me.ReferenceFrame(n) for n in ("N", "Y", "L", "D"))
    heading.orient_axis(world, world.z, q[2])
    lean.orient_axis(heading, heading.x, q[3])
    disc.orient_axis(lean, lean.y, q[4])
    speeds = {qi.diff(TIME): ui for qi, ui in zip(q, u)}
    origin = me.Point("O")
    origin.set_vel(world, 0)
    centre = origin.locatenew("G", q[0] * world.x + q[1] * world.y + r * sp.cos(q[3]) * world.z)
    centre.set_vel(world, centre.pos_from(origin).dt(world).xreplace(speeds))
    disc.set_ang_vel(world, disc.ang_vel_in(world).xreplace(speeds))
    contact = centre.locatenew("C", -r * lean.z)
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
    inertia = me.inertia(disc, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    body = me.RigidBody("disc", centre, disc, m, (inertia, centre))
    kane.kanes_equations([body], [(centre, -m * g * world.z)])
    plain = plain_symbols(q, u)
    return kane, [s.xreplace(plain) for s in slip], plain


def test_the_accelerations_match_kanes_method_at_random_rolling_states() -> None:
    system = rolling_disc()
    kane, slip, plain = _kane()
    equations = constrained_equations(system)
    x_dot, y_dot = system.velocities[:2]
    rng = random.Random(7)
    for _ in range(3):
        values: dict = {p: rng.uniform(0.5, 1.5) for p in system.parameters}
        values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
        values.update({s: rng.uniform(-2.0, 2.0) for s in system.velocities})
        values[t] = 0.0
        # the dependent speeds from mechanics' own constraints (each has x_dot or y_dot alone)
        values[x_dot] = values[x_dot] - float(slip[0].xreplace(values))
        values[y_dot] = values[y_dot] - float(slip[1].xreplace(values))
        solution = np.linalg.solve(
            numbers(equations.augmented_matrix, values),
            numbers(equations.augmented_rhs, values)[:, 0],
        )
        mass = numbers(kane.mass_matrix_full.xreplace(plain), values)
        forcing = numbers(kane.forcing_full.xreplace(plain), values)[:, 0]
        theirs = np.linalg.solve(mass, forcing)[5:]  # (q_dot, then u_dot in mechanics' order)
        order = [2, 3, 4, 0, 1]  # mechanics: independent speeds first
        np.testing.assert_allclose(solution[:5][order], theirs, rtol=1e-9, atol=1e-9)


# -- upright rolling: stability and energy ------------------------------------------------------


def _state_derivative(system: System):
    """f(q, q_dot) = (q_dot, q_ddot) with the constraints enforced (multiplier form)."""
    equations = constrained_equations(system)
    values = {**dict(system.parameters), t: 0}
    state = [*system.coordinates, *system.velocities]
    matrix = sp.lambdify([state], equations.augmented_matrix.xreplace(values), "numpy")
    rhs = sp.lambdify([state], equations.augmented_rhs.xreplace(values), "numpy")
    n = len(system.coordinates)

    def derivative(point: np.ndarray) -> np.ndarray:
        solved = np.linalg.solve(np.array(matrix(point), float), np.array(rhs(point), float))
        return np.concatenate([point[n:], solved[:n, 0]])

    return derivative


@pytest.mark.parametrize("ratio", [0.8, 1.2, 2.0])
def test_upright_rolling_is_stable_above_the_critical_spin_rate(ratio: float) -> None:
    """Linearized about straight upright rolling at spin rate Omega, the lean-heading mode
    has lambda^2 = (4/5) (g/r - 3 Omega^2) for a thin uniform disc (I = m r^2/2 about the
    axle, m r^2/4 about a diameter): stable exactly when Omega^2 > g/(3 r), v^2 > g r/3."""
    system = rolling_disc()
    derivative = _state_derivative(system)
    spin = np.sqrt(ratio * 9.81 / (3 * 0.3))
    rolling = np.zeros(10)
    rolling[5], rolling[9] = 0.3 * spin, spin  # x_dot = r Omega, phi_dot = Omega
    np.testing.assert_allclose(derivative(rolling)[5:], 0.0, atol=1e-12)
    step, jacobian = 1e-6, np.zeros((10, 10))
    for k in range(10):
        e = np.zeros(10)
        e[k] = step
        jacobian[:, k] = (derivative(rolling + e) - derivative(rolling - e)) / (2 * step)
    eigenvalues = np.linalg.eigvals(jacobian)
    (mode,) = {round(abs(ev), 6) for ev in eigenvalues if abs(ev) > 1e-4}
    expected = 4 / 5 * (9.81 / 0.3 - 3 * spin**2)
    assert mode**2 == pytest.approx(abs(expected), rel=1e-6)
    growth = max(ev.real for ev in eigenvalues)
    if ratio < 1:
        assert growth == pytest.approx(np.sqrt(expected), rel=1e-6)
    else:
        assert abs(growth) < 1e-6


def test_a_wobbling_roll_conserves_energy_and_the_constraints() -> None:
    system = rolling_disc()
    start = {str(s): 0.0 for s in (*system.coordinates, *system.velocities)}
    start.update({"x_dot": 3.0, "y_dot": -0.03, "theta_dot": 0.1, "phi_dot": 10.0})
    run = lg.simulate(system, start, 2.0, rtol=1e-10, atol=1e-12, samples=201)
    assert run.status == "success"
    drift = np.max(np.abs(run.energy - run.energy[0]))
    assert drift < 1e-7 * abs(run.energy[0])
    assert np.max(run.constraint_residual) < 1e-7
    lean = run.q[:, system.coordinates.index(theta)]
    assert np.max(np.abs(lean)) < 0.05  # above the critical spin: a small wobble


# -- bad input ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("disc", "match"),
    [
        (
            RollingDisc("wheal", r),
            r"rolling\[0\].body.*unknown rigid body 'wheal'.*did you mean 'wheel'",
        ),
        (RollingDisc("wheel", sp.Symbol("R")), r"rolling\[0\].radius.*unknown name 'R'"),
        (RollingDisc("wheel", r, "w"), r"rolling\[0\].axis.*unknown axis 'w'"),
        (RollingDisc("rotor", r), r"rolling\[0\].body.*'rotor' is not a 3-D rigid body"),
    ],
)
def test_a_bad_rolling_disc_is_refused_with_the_fix(disc: RollingDisc, match: str) -> None:
    rotor = RigidBody("rotor", m, 1, (x, y), angle=phi)
    system = rolling_disc()
    with pytest.raises(ModelError, match=match):
        system.replace(rolling=[disc], rigid_bodies=[*system.rigid_bodies, rotor])


def test_a_disc_whose_axle_is_vertical_is_refused() -> None:
    coin = RigidBody("coin", m, shape("disc", radius=r), (x, y, 0), rotations=[("z", phi)])
    with pytest.raises(ModelError, match=r"the disc of body 'coin' lies flat.*not vertical"):
        System(
            coordinates=[x, y, phi],
            parameters=[m, r],
            rigid_bodies=[coin],
            rolling=[RollingDisc("coin", r)],
        )


def test_a_body_without_a_wheel_shape_needs_an_axle() -> None:
    wheel = rolling_disc().rigid_bodies[0]
    plain = RigidBody(**{**wheel.__dict__, "inertia": sp.diag(1, 2, 1), "orientation": None})
    with pytest.raises(ModelError, match=r"rolling\[0\].axis.*no wheel axle.*axis: x, y or z"):
        rolling_disc().replace(rigid_bodies=[plain])
    fixed = rolling_disc().replace(rigid_bodies=[plain], rolling=[RollingDisc("wheel", r, "y")])
    assert fixed.constraints == rolling_disc().constraints


def test_the_rolling_coin_example_agrees_with_its_newton_euler_equations() -> None:
    system = lg.examples.rolling_coin()
    assert [type(c) for c in system.constraints] == [NoSlip, NoSlip]
    check = check_newton_euler(system)
    assert check.agree, check.summary()


def test_a_force_at_the_contact_point_works_through_the_material_point() -> None:
    """Q_j = F . d(v_C)/d(q_dot_j), v_C the disc's material point at the contact (mechanics'
    v2pt_theory: its x and y components are _kane's constraints), for a horizontal push
    F = (F_x, F_y, 0) at the contact point."""
    push_x, push_y = sp.symbols("F_x F_y")
    system = rolling_disc().replace(
        parameters={m: 1.0, g: 9.81, r: 0.3, push_x: 1.0, push_y: 2.0},
        forces=[lg.Force("wheel_contact", (push_x, push_y, 0), name="push")],
    )
    assert [f.at for f in system.forces] == ["wheel"]
    assert [tq.name for tq in system.torques] == ["push"]
    ours = lg.derive(system).generalized_forces
    _, (along_x, along_y), _ = _kane()
    rng = random.Random(3)
    values: dict = {p: rng.uniform(0.5, 1.5) for p in system.parameters}
    values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
    for j, rate in enumerate(system.velocities):
        theirs = push_x * along_x.diff(rate) + push_y * along_y.diff(rate)
        assert float((ours[j] - theirs).xreplace(values)) == pytest.approx(0, abs=1e-12)
