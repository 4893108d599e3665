"""Reaction wrenches of the constraints on bodies written in maximal coordinates, against the
textbook: the pin of a compound pendulum (a uniform rod: m l theta_dot^2/2 + m g cos(theta)
along the rod, m g sin(theta)/4 across it), the rod tension of seed 003's dumbbell, and the tip
of a heavy top (F = m (a_c - g) with a_c from the top's own equations in Euler angles)."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.constraints import reaction_wrenches
from lagrangian.errors import ConstraintError
from lagrangian.model.rotation import euler_rotation, evaluate_matrix
from lagrangian.symbolic.symbols import t, time_derivative

m, g, l = sp.symbols("m g l")
PARAMETERS = {"m": 1.3, "g": 9.81, "l": 0.8}


def pinned_rod() -> lg.System:
    """A uniform rod of length l, its centre (x, y) and angle theta free, pinned at one end to
    the origin by two holonomic constraints."""
    x, y, theta = lg.coordinates("x y theta")
    return lg.System(
        coordinates=[x, y, theta],
        parameters={m: PARAMETERS["m"], g: PARAMETERS["g"], l: PARAMETERS["l"]},
        rigid_bodies=[lg.RigidBody("rod", m, m * l**2 / 12, (x, y), theta)],
        constraints=[
            lg.Holonomic(x - l * sp.sin(theta) / 2, "pin x"),
            lg.Holonomic(y + l * sp.cos(theta) / 2, "pin y"),
        ],
        gravity=(0, -g),
        initial=rod_state(1.0, 0.0),
    )


def rod_state(theta: float, theta_dot: float) -> dict[str, float]:
    half = PARAMETERS["l"] / 2
    return {
        "x": half * np.sin(theta),
        "y": -half * np.cos(theta),
        "theta": theta,
        "x_dot": half * np.cos(theta) * theta_dot,
        "y_dot": half * np.sin(theta) * theta_dot,
        "theta_dot": theta_dot,
    }


def textbook_pin(theta: np.ndarray, theta_dot: np.ndarray) -> tuple[np.ndarray, ...]:
    """(along the rod toward the pin, across it toward increasing theta, moment about the
    centre) of the pin force on a uniform rod: I_pin theta_ddot = -m g (l/2) sin(theta),
    theta_ddot = -3 g sin(theta) / (2 l)."""
    mass, gravity, length = PARAMETERS["m"], PARAMETERS["g"], PARAMETERS["l"]
    radial = mass * length * theta_dot**2 / 2 + mass * gravity * np.cos(theta)
    tangential = mass * gravity * np.sin(theta) / 4
    return radial, tangential, -length / 2 * tangential


def components(force: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The force along -e_r (toward the pin) and e_theta."""
    fx, fy = force[..., 0], force[..., 1]
    inward = -(fx * np.sin(theta) - fy * np.cos(theta))
    return inward, fx * np.cos(theta) + fy * np.sin(theta)


def test_the_pin_force_of_a_compound_pendulum_is_the_textbook_one() -> None:
    rng = random.Random(4)
    for _ in range(4):
        theta, theta_dot = rng.uniform(-2.5, 2.5), rng.uniform(-3.0, 3.0)
        pin = reaction_wrenches(pinned_rod(), rod_state(theta, theta_dot))["rod"]
        radial, tangential, moment = textbook_pin(np.array(theta), np.array(theta_dot))
        inward, across = components(pin.force, np.array(theta))
        np.testing.assert_allclose([inward, across, pin.torque], [radial, tangential, moment])
        # the body-frame wrench is the same force in body axes, the same moment
        c, s = np.cos(theta), np.sin(theta)
        np.testing.assert_allclose(
            pin.wrench,
            [c * pin.force[0] + s * pin.force[1], -s * pin.force[0] + c * pin.force[1], moment],
        )
        assert pin.kind == "planar" and pin.body == "rod"


def test_the_pin_force_along_a_simulation_uses_the_recorded_multipliers() -> None:
    trajectory = lg.simulate(
        pinned_rod(),
        t_span=2.0,
        samples=40,
        method="DOP853",
        rtol=1e-11,
        atol=1e-11,
        baumgarte=(10.0, 10.0),
    )
    pin = reaction_wrenches(pinned_rod(), trajectory)["rod"]
    theta, theta_dot = trajectory["theta"], trajectory["theta_dot"]
    radial, tangential, moment = textbook_pin(theta, theta_dot)
    inward, across = components(pin.force, theta)
    assert pin.force.shape == (40, 2) and pin.torque.shape == (40,)
    np.testing.assert_allclose(inward, radial, rtol=1e-6)
    np.testing.assert_allclose(across, tangential, atol=1e-6)
    np.testing.assert_allclose(pin.torque, moment, atol=1e-6)


def test_the_dumbbell_rod_pulls_with_the_seeds_tension() -> None:
    """Seed 003: m1 q1_ddot = f1 + mu (q1 - q2) + m1 g with
    mu = -m1 m2 theta_dot^2 / (m1 + m2)
         + ((m2 f1x - m1 f2x) cos(theta) + (m2 f1y - m1 f2y) sin(theta)) / (h (m1 + m2)),
    q2 - q1 = h (cos(theta), sin(theta)); the rod pushes particle 2 with the opposite force."""
    x1, y1, x2, y2 = lg.coordinates("x1 y1 x2 y2")
    m1, m2, h = sp.symbols("m1 m2 h")
    forces = sp.symbols("f1x f1y f2x f2y")
    values = {
        "m1": 1.2,
        "m2": 0.7,
        "h": 0.9,
        "g": 9.81,
        "f1x": 0.4,
        "f1y": -1.1,
        "f2x": 2.0,
        "f2y": 0.3,
    }
    system = lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={sp.Symbol(k): v for k, v in values.items()},
        particles=[lg.Particle("particle1", m1, (x1, y1)), lg.Particle("particle2", m2, (x2, y2))],
        forces=[lg.Force("particle1", forces[:2]), lg.Force("particle2", forces[2:])],
        constraints=[lg.Holonomic((x2 - x1) ** 2 + (y2 - y1) ** 2 - h**2, "rod")],
        gravity=(0, -g),
    )
    rng = random.Random(8)
    for _ in range(3):
        theta, rate = rng.uniform(-3, 3), rng.uniform(-2, 2)
        start, velocity = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1)]), rng.uniform(-1, 1)
        along = np.array([np.cos(theta), np.sin(theta)])
        other = start + values["h"] * along
        spin = values["h"] * rate * np.array([-np.sin(theta), np.cos(theta)])
        state = {
            "x1": start[0],
            "y1": start[1],
            "x2": other[0],
            "y2": other[1],
            "x1_dot": velocity,
            "y1_dot": 0.0,
            "x2_dot": velocity + spin[0],
            "y2_dot": spin[1],
        }
        reactions = reaction_wrenches(system, state)
        total = values["m1"] + values["m2"]
        mu = -values["m1"] * values["m2"] * rate**2 / total + (
            (values["m2"] * values["f1x"] - values["m1"] * values["f2x"]) * np.cos(theta)
            + (values["m2"] * values["f1y"] - values["m1"] * values["f2y"]) * np.sin(theta)
        ) / (values["h"] * total)
        np.testing.assert_allclose(reactions["particle1"].force, mu * (start - other), atol=1e-12)
        np.testing.assert_allclose(reactions["particle2"].force, -mu * (start - other), atol=1e-12)
        assert reactions["particle1"].torque is None


def test_the_tip_of_a_heavy_top_holds_it_with_m_times_a_minus_g() -> None:
    """The top in maximal coordinates (centre x, y, z and ZXZ angles, the tip pinned by three
    constraints) against the top of the examples in Euler angles alone: the tip force is
    F = m (a_c - g), a_c the centre's acceleration there, and its moment about the centre is
    (tip - centre) x F."""
    top = lg.examples.heavy_symmetric_top()
    x, y, z, phi, theta, psi = lg.coordinates("x y z phi theta psi")
    A, C = sp.symbols("A C")
    R = euler_rotation("ZXZ", (phi, theta, psi))
    axis = R.matrix[:, 2]
    free = lg.System(
        coordinates=[x, y, z, phi, theta, psi],
        parameters=top.parameters,
        rigid_bodies=[lg.RigidBody("top", m, sp.diag(A, A, C), (x, y, z), orientation=R)],
        constraints=[lg.Holonomic(c - l * e) for c, e in zip((x, y, z), axis)],
        gravity=(0, 0, -g),
    )
    reduced = lg.derive(top)
    centre = sp.Matrix(top.rigid_bodies[0].position)
    angles = top.coordinates
    velocity = centre.applyfunc(lambda e: time_derivative(e, angles))
    acceleration = velocity.applyfunc(lambda e: time_derivative(e, angles))
    rng = random.Random(6)
    for _ in range(3):
        values = {s: v for s, v in top.parameters.items()}
        values.update({q: rng.uniform(0.3, 1.2) for q in angles})
        values.update({v: rng.uniform(-3.0, 3.0) for v in top.velocities})
        values[t] = 0.0
        q_ddot = np.linalg.solve(
            evaluate_matrix(reduced.mass_matrix, values), evaluate_matrix(reduced.forcing, values)
        )
        values.update(zip(top.accelerations, q_ddot[:, 0]))
        position = evaluate_matrix(centre, values)[:, 0]
        speed = evaluate_matrix(velocity, values)[:, 0]
        state = {s.name: values[s] for s in (*angles, *top.velocities)}
        state.update({"x": position[0], "y": position[1], "z": position[2]})
        state.update({"x_dot": speed[0], "y_dot": speed[1], "z_dot": speed[2]})
        tip = reaction_wrenches(free, state)["top"]
        weight = np.array([0.0, 0.0, -values[m] * values[g]])
        expected = values[m] * evaluate_matrix(acceleration, values)[:, 0] - weight
        np.testing.assert_allclose(tip.force, expected, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(tip.torque, np.cross(-position, expected), atol=1e-9)


def test_a_body_without_coordinates_of_its_own_is_refused() -> None:
    with pytest.raises(
        ConstraintError,
        match=r"rigid_bodies\[0\]: 3-D body 'cylinder' moves by 2 coordinates \(x, phi\), not 6",
    ):
        reaction_wrenches(lg.examples.cylinder_on_incline(), {"x": 0, "phi": 0})
    with pytest.raises(
        ConstraintError, match=r"particles\[0\]: particle 'particle1' shares x1, y1 with other"
    ):
        reaction_wrenches(lg.examples.dumbbell(), {})


def test_a_state_with_unknown_or_missing_names_is_refused() -> None:
    state = rod_state(0.3, 0.1)
    with pytest.raises(ConstraintError, match=r"The state names omega, which are not"):
        reaction_wrenches(pinned_rod(), {**state, "omega": 1.0})
    del state["theta_dot"]
    with pytest.raises(ConstraintError, match=r"no value for theta_dot"):
        reaction_wrenches(pinned_rod(), state)
