"""The 3-D rigid-body examples against textbook results (Goldstein ch. 5, Landau-Lifshitz
sections 35-36): the heavy top's cyclic momenta and steady precession, Euler's equations and
the instability of rotation about the middle axis, the physical pendulum's small oscillations,
the rolling disc's steady circle, and the cylinder rolling down an incline."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.interpolate import CubicSpline

import lagrangian as lg
from lagrangian.analysis import cyclic_coordinates
from lagrangian.constraints import classify, constrained_equations
from lagrangian.model.inertia import ring

TIGHT = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12}

# -- heavy symmetric top ------------------------------------------------------------------------

TOP = {"m": 1.0, "g": 9.81, "l": 0.1, "A": 0.005, "C": 0.008}


def test_the_top_file_holds_its_textbook_parameters() -> None:
    assert {p.name: v for p, v in lg.examples.heavy_symmetric_top().parameters.items()} == TOP


def test_the_top_has_the_textbook_momenta_and_nutation_equation() -> None:
    """p_phi = I1 phi_dot sin^2 + C omega3 cos, p_psi = C omega3 (cyclic), and
    I1 theta_ddot = I1 phi_dot^2 sin cos - C omega3 phi_dot sin + m g l sin, I1 = A + m l^2."""
    system = lg.examples.heavy_symmetric_top()
    phi, theta, psi = system.coordinates
    phi_dot, _, psi_dot = system.velocities
    m, g, l, A, C = sp.symbols("m g l A C")
    I1, omega3 = A + m * l**2, psi_dot + phi_dot * sp.cos(theta)
    cyclic = {c.coordinate: c.momentum for c in cyclic_coordinates(system)}
    assert set(cyclic) == {phi, psi}
    p_phi = I1 * phi_dot * sp.sin(theta) ** 2 + C * omega3 * sp.cos(theta)
    assert sp.simplify(cyclic[phi] - p_phi) == 0
    assert sp.expand(cyclic[psi] - C * omega3) == 0
    nutation = (
        I1 * lg.acceleration(theta)
        - I1 * phi_dot**2 * sp.sin(theta) * sp.cos(theta)
        + C * omega3 * phi_dot * sp.sin(theta)
        - m * g * l * sp.sin(theta)
    )
    assert sp.simplify(lg.derive(system).equations[1] - nutation) == 0
    report = lg.analyze(system)
    assert {"p_phi", "p_psi"} <= {c.name for c in report.conserved}


def test_the_released_top_keeps_its_momenta_and_energy() -> None:
    trajectory = lg.simulate(lg.examples.heavy_symmetric_top(), t_span=1.0, samples=200, **TIGHT)
    drift = trajectory.drift()
    assert trajectory.success
    assert drift["energy_relative"] < 1e-9
    assert drift["conserved_p_phi_absolute"] < 1e-11
    assert drift["conserved_p_psi_relative"] < 1e-11
    assert np.ptp(trajectory["theta"]) > 1e-4  # it nutates: the test above is not trivial


def slow_precession(theta0: float, omega3: float) -> float:
    """The slow root of m g l = Omega (C omega3 - I1 Omega cos(theta0))."""
    I1, C = TOP["A"] + TOP["m"] * TOP["l"] ** 2, TOP["C"]
    weight = TOP["m"] * TOP["g"] * TOP["l"]
    a = I1 * np.cos(theta0)
    return (C * omega3 - np.sqrt((C * omega3) ** 2 - 4 * a * weight)) / (2 * a)


@pytest.mark.parametrize(("factor", "steady"), [(1.0, True), (1.1, False)])
def test_a_top_started_at_steady_precession_keeps_its_angle(factor: float, steady: bool) -> None:
    theta0, omega3 = 0.5, 50.0
    rate = factor * slow_precession(theta0, omega3)
    start = {
        "phi": 0.0,
        "theta": theta0,
        "psi": 0.0,
        "phi_dot": rate,
        "theta_dot": 0.0,
        "psi_dot": omega3 - rate * np.cos(theta0),
    }
    trajectory = lg.simulate(lg.examples.heavy_symmetric_top(), start, 1.0, samples=200, **TIGHT)
    wobble = np.max(np.abs(trajectory["theta"] - theta0))
    if steady:
        assert wobble < 1e-8
        np.testing.assert_allclose(trajectory["phi_dot"], rate, rtol=1e-8)
    else:  # 10 % off the root: the axis nods
        assert wobble > 1e-4


# -- torque-free asymmetric body ----------------------------------------------------------------

INERTIA = np.array([1.0, 2.0, 2.5])


def body_rates(trajectory: lg.Trajectory) -> np.ndarray:
    """omega in body axes from ZXZ angles and rates (the header's formulas), shape (N, 3)."""
    theta, psi = trajectory["theta"], trajectory["psi"]
    phi_dot, theta_dot, psi_dot = (trajectory[n] for n in ("phi_dot", "theta_dot", "psi_dot"))
    return np.column_stack(
        [
            phi_dot * np.sin(theta) * np.sin(psi) + theta_dot * np.cos(psi),
            phi_dot * np.sin(theta) * np.cos(psi) - theta_dot * np.sin(psi),
            phi_dot * np.cos(theta) + psi_dot,
        ]
    )


def spin(axis: int, omega: float, nudge: float) -> dict[str, float]:
    """Spin omega about body axis 1, 2 or 3 (theta = pi/2 keeps the angles far from gimbal
    lock), nudged by theta_dot."""
    psi = {1: np.pi / 2, 2: 0.0, 3: 0.0}[axis]
    phi_dot, psi_dot = (0.0, omega) if axis == 3 else (omega, 0.0)
    return {
        "phi": 0.0,
        "theta": np.pi / 2,
        "psi": psi,
        "phi_dot": phi_dot,
        "theta_dot": nudge,
        "psi_dot": psi_dot,
    }


def test_eulers_equations_hold_along_the_tumbling_motion() -> None:
    trajectory = lg.simulate(lg.examples.asymmetric_body(), t_span=20.0, samples=4001, **TIGHT)
    assert trajectory.success
    omega = body_rates(trajectory)
    omega_dot = CubicSpline(trajectory.t, omega)(trajectory.t, 1)
    I1, I2, I3 = INERTIA
    w1, w2, w3 = omega.T
    euler = np.column_stack(
        [
            I1 * omega_dot[:, 0] - (I2 - I3) * w2 * w3,
            I2 * omega_dot[:, 1] - (I3 - I1) * w3 * w1,
            I3 * omega_dot[:, 2] - (I1 - I2) * w1 * w2,
        ]
    )
    assert np.max(np.abs(euler[5:-5])) < 1e-6
    kinetic = 0.5 * np.sum(INERTIA * omega**2, axis=1)
    momentum = np.linalg.norm(INERTIA * omega, axis=1)
    np.testing.assert_allclose(kinetic, kinetic[0], rtol=1e-9)
    np.testing.assert_allclose(momentum, momentum[0], rtol=1e-9)
    assert w2.min() < -1.5  # the tennis racket flip: axis 2 turns over


def test_a_spin_about_the_middle_axis_grows_at_the_textbook_rate() -> None:
    """omega1 = eps cosh(lambda t), lambda = omega sqrt((I2 - I1)(I3 - I2)/(I1 I3))."""
    omega, eps = 2.0, 1e-7
    I1, I2, I3 = INERTIA
    rate = omega * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    times = np.linspace(0.0, 12.0, 121)
    trajectory = lg.simulate(
        lg.examples.asymmetric_body(), spin(2, omega, eps), 12.0, t_eval=times, **TIGHT
    )
    w1 = body_rates(trajectory)[:, 0]
    np.testing.assert_allclose(w1, eps * np.cosh(rate * times), rtol=1e-3)
    assert w1[-1] > 1e3 * eps


@pytest.mark.parametrize("axis", [1, 3])
def test_a_spin_about_the_smallest_or_largest_axis_stays_put(axis: int) -> None:
    eps = 1e-4
    trajectory = lg.simulate(
        lg.examples.asymmetric_body(), spin(axis, 2.0, eps), 20.0, samples=401, **TIGHT
    )
    omega = body_rates(trajectory)
    others = np.delete(omega, axis - 1, axis=1)
    assert np.max(np.abs(others)) < 5 * eps
    np.testing.assert_allclose(omega[:, axis - 1], 2.0, atol=1e-6)


# -- 3-D physical pendulum -----------------------------------------------------------------------


def test_the_physical_pendulum_swings_about_both_horizontal_axes_at_the_textbook_rates() -> None:
    """omega^2 = m g d / I_pivot about each horizontal axis (d = h/2), and a free turn about
    the vertical (zero frequency)."""
    system = lg.examples.physical_pendulum_3d()
    values = {p.name: v for p, v in system.parameters.items()}
    g, h, wx, wy = values["g"], values["h"], values["w_x"], values["w_y"]
    d, mass = h / 2, values["m"]
    about_x = mass * (wy**2 + h**2) / 12 + mass * d**2
    about_y = mass * (wx**2 + h**2) / 12 + mass * d**2
    expected = sorted([0.0, np.sqrt(mass * g * d / about_x), np.sqrt(mass * g * d / about_y)])
    modes = lg.analyze(system).normal_modes
    assert modes is not None
    np.testing.assert_allclose(sorted(float(f) for f in modes.frequencies), expected, atol=1e-9)
    # a small swing about x alone has that period in a simulation too
    period = 2 * np.pi / np.sqrt(mass * g * d / about_x)
    start = {"a": 1e-3, "b": 0.0, "c": 0.0, "a_dot": 0.0, "b_dot": 0.0, "c_dot": 0.0}
    trajectory = lg.simulate(system, start, period, samples=3, **TIGHT)
    np.testing.assert_allclose(trajectory["a"], [1e-3, -1e-3, 1e-3], rtol=1e-5)


# -- rolling disc --------------------------------------------------------------------------------


def test_the_rolling_disc_is_non_holonomic_with_three_free_velocities() -> None:
    report = classify(lg.examples.rolling_disc())
    assert [c.holonomic for c in report.constraints] == [False, False]
    assert "non-holonomic" in report.constraints[0].reason
    assert report.dof == 5 and report.independent_velocities == 3


def circle_start(lean: float, radius: float, factor: float = 1.0) -> dict[str, float]:
    """Steady rolling on a circle of ``radius`` (the contact point's), leaning by ``lean``
    toward the centre: g tan(lean) = Omega^2 (3/2 R - 5/4 r sin(lean))."""
    g, r = 9.81, 0.3
    turn = factor * np.sqrt(g * np.tan(lean) / (1.5 * radius - 1.25 * r * np.sin(lean)))
    roll = radius * turn / r
    return {
        "x": 0.0,
        "y": 0.0,
        "psi": 0.0,
        "theta": -lean,
        "phi": 0.0,
        "x_dot": r * roll,
        "y_dot": 0.0,
        "psi_dot": turn,
        "theta_dot": 0.0,
        "phi_dot": roll,
    }


@pytest.mark.parametrize(("factor", "steady"), [(1.0, True), (1.1, False)])
def test_the_disc_rolls_steadily_on_the_textbook_circle(factor: float, steady: bool) -> None:
    lean, radius = 0.2, 1.0
    start = circle_start(lean, radius, factor)
    loop = 2 * np.pi / start["psi_dot"]
    trajectory = lg.simulate(
        lg.examples.rolling_disc(), start, loop, samples=100, baumgarte=(5.0, 5.0), **TIGHT
    )
    drift = trajectory.drift()
    assert drift["energy_relative"] < 1e-9 and drift["constraint_residual_max"] < 1e-9
    wobble = np.max(np.abs(trajectory["theta"] + lean))
    if not steady:
        assert wobble > 1e-3
        return
    assert wobble < 1e-8
    path = np.column_stack([trajectory["x"], trajectory["y"] - radius])
    np.testing.assert_allclose(np.linalg.norm(path, axis=1), radius, rtol=1e-8)


def test_the_rolling_disc_example_conserves_energy_and_keeps_rolling() -> None:
    trajectory = lg.simulate(lg.examples.rolling_disc(), samples=200, baumgarte=(5.0, 5.0), **TIGHT)
    drift = trajectory.drift()
    assert trajectory.success and trajectory.multiplier_names == ("lambda_1", "lambda_2")
    assert drift["energy_relative"] < 1e-9 and drift["constraint_residual_max"] < 1e-9


# -- cylinder on an incline ----------------------------------------------------------------------

m, g, r, alpha, I = sp.symbols("m g r alpha I")


def rolled(inertia: sp.MatrixBase) -> tuple[sp.Expr, sp.Expr]:
    """(x_ddot, friction lambda) of the cylinder example with another inertia tensor."""
    system = lg.examples.cylinder_on_incline()
    body = system.rigid_bodies[0]
    other = lg.RigidBody(body.name, body.mass, inertia, body.position, orientation=body.orientation)
    parameters = {**system.parameters, I: 1.0, sp.Symbol("J"): 1.0}
    equations = constrained_equations(system.replace(rigid_bodies=[other], parameters=parameters))
    assert equations.explicit is not None
    x_ddot = equations.explicit[lg.acceleration(system.coordinates[0])]
    return sp.simplify(x_ddot), sp.simplify(equations.explicit[sp.Symbol("lambda_1")])


def test_rolling_down_an_incline_accelerates_at_g_sin_alpha_over_one_plus_i_over_mr2() -> None:
    across = sp.Symbol("J")
    x_ddot, friction = rolled(sp.diag(across, I, across))
    assert sp.simplify(x_ddot - g * sp.sin(alpha) / (1 + I / (m * r**2))) == 0
    assert sp.simplify(friction + m * g * sp.sin(alpha) * I / (I + m * r**2)) == 0
    x_ddot, friction = rolled(ring(m, r, "y"))
    assert sp.simplify(x_ddot - g * sp.sin(alpha) / 2) == 0
    assert sp.simplify(friction + m * g * sp.sin(alpha) / 2) == 0


def test_the_solid_cylinder_rolls_at_two_thirds_g_sin_alpha() -> None:
    system = lg.examples.cylinder_on_incline()
    equations = constrained_equations(system)
    x, _ = system.coordinates
    assert sp.simplify(equations.explicit[lg.acceleration(x)] - 2 * g * sp.sin(alpha) / 3) == 0
    assert sp.simplify(equations.explicit[sp.Symbol("lambda_1")] + m * g * sp.sin(alpha) / 3) == 0
    trajectory = lg.simulate(system, samples=21, baumgarte=(5.0, 5.0), **TIGHT)
    values = {p.name: v for p, v in system.parameters.items()}
    a = 2 * values["g"] * np.sin(values["alpha"]) / 3
    np.testing.assert_allclose(trajectory["x"], a * trajectory.t**2 / 2, atol=1e-10)
    np.testing.assert_allclose(trajectory["lambda_1"], -values["m"] * a / 2, rtol=1e-9)
