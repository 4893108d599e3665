"""Rotations and angular velocities, checked against sympy.physics.vector (ReferenceFrame
orientations and ang_vel_in), textbook formulas, finite differences of R(q) and the
definitions V_s = g_dot g^-1, V_b = g^-1 g_dot of seed 003."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
import sympy.physics.vector as pv
from hypothesis import given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.model.rotation import (
    EULER_SEQUENCES,
    as_orientation,
    axis_angle,
    body_angular_velocity,
    check_rotation,
    euler_rotation,
    hat,
    quaternion_rotation,
    spatial_angular_velocity,
    vee,
)
from lagrangian.model.twist import adjoint, adjoint_inverse, body_twist, spatial_twist
from lagrangian.symbolic.symbols import t, time_derivative, velocity

TIME = pv.dynamicsymbols._t
a, b, c = sp.symbols("a b c")
ANGLES = (a, b, c)


def _plain(expr: sp.Basic, names: list[str]) -> sp.Basic:
    """q(t)' -> q_dot, q(t) -> q for the named dynamicsymbols."""
    swap: dict[sp.Basic, sp.Basic] = {}
    for name in names:
        f = pv.dynamicsymbols(name)
        swap[f.diff(TIME)] = sp.Symbol(name + "_dot")
        swap[f] = sp.Symbol(name)
    return expr.xreplace(swap)


def _random_state(symbols, seed: int = 0) -> dict[sp.Symbol, float]:
    rng = random.Random(seed)
    values = {s: rng.uniform(-1.5, 1.5) for s in symbols}
    values.update({velocity(s): rng.uniform(-2, 2) for s in symbols})
    values[t] = rng.uniform(0, 1)
    return values


def _numbers(matrix: sp.MatrixBase, values) -> np.ndarray:
    return np.array(sp.Matrix(matrix).xreplace(values).evalf(), dtype=float)


def _frames(sequence: str, intrinsic: bool):
    dyn = pv.dynamicsymbols("a b c")
    N, B = pv.ReferenceFrame("N"), pv.ReferenceFrame("B")
    if intrinsic:
        B.orient_body_fixed(N, dyn, sequence)
    else:
        B.orient_space_fixed(N, dyn, sequence)
    return N, B


@pytest.mark.parametrize("intrinsic", [True, False])
@pytest.mark.parametrize("sequence", EULER_SEQUENCES)
def test_euler_rotations_match_sympy_physics_vector(sequence: str, intrinsic: bool) -> None:
    N, B = _frames(sequence, intrinsic)
    names = ["a", "b", "c"]
    orientation = euler_rotation(sequence, ANGLES, intrinsic=intrinsic)
    reference_R = _plain(N.dcm(B), names)
    omega = B.ang_vel_in(N)
    reference_body = _plain(omega.to_matrix(B), names)
    reference_spatial = _plain(omega.to_matrix(N), names)
    body = body_angular_velocity(orientation, ANGLES)
    spatial = spatial_angular_velocity(orientation, ANGLES)
    for seed in range(3):
        state = _random_state(ANGLES, seed)
        np.testing.assert_allclose(
            _numbers(orientation.matrix, state), _numbers(reference_R, state), atol=1e-12
        )
        np.testing.assert_allclose(
            _numbers(body, state), _numbers(reference_body, state), atol=1e-12
        )
        np.testing.assert_allclose(
            _numbers(spatial, state), _numbers(reference_spatial, state), atol=1e-12
        )


def test_zxz_body_angular_velocity_is_the_textbook_one() -> None:
    phi, theta, psi = sp.symbols("phi theta psi")
    dphi, dtheta, dpsi = (velocity(s) for s in (phi, theta, psi))
    textbook = sp.Matrix(
        [
            dphi * sp.sin(theta) * sp.sin(psi) + dtheta * sp.cos(psi),
            dphi * sp.sin(theta) * sp.cos(psi) - dtheta * sp.sin(psi),
            dphi * sp.cos(theta) + dpsi,
        ]
    )
    omega = body_angular_velocity(euler_rotation("ZXZ", (phi, theta, psi)), [phi, theta, psi])
    assert (omega - textbook).applyfunc(sp.expand) == sp.zeros(3, 1)


@pytest.mark.parametrize(
    ("sequence", "lock"),
    [("ZXZ", sp.sin(b)), ("ZYZ", sp.sin(b)), ("ZYX", sp.cos(b)), ("XYZ", sp.cos(b))],
)
@pytest.mark.parametrize("intrinsic", [True, False])
def test_gimbal_lock_is_where_the_angle_rates_are_lost(
    sequence: str, lock: sp.Expr, intrinsic: bool
) -> None:
    orientation = euler_rotation(sequence, ANGLES, intrinsic=intrinsic)
    assert orientation.gimbal_lock == lock
    # omega_b = J(angles) angle_rates: det J = +-(the gimbal-lock expression)
    rates = [velocity(s) for s in ANGLES]
    jacobian = body_angular_velocity(orientation, ANGLES).jacobian(rates)
    determinant = sp.trigsimp(jacobian.det())
    assert sp.simplify(determinant**2 - lock**2) == 0


@pytest.mark.parametrize("intrinsic", [True, False])
def test_euler_forms_follow_the_general_formula_vee_of_RT_Rdot(intrinsic: bool) -> None:
    orientation = euler_rotation("YXZ", ANGLES, intrinsic=intrinsic)
    general = as_orientation(orientation.matrix)  # a plain matrix: vee(R^T R_dot) itself
    assert general.form == "matrix"
    for closed, plain in [
        (body_angular_velocity(orientation, ANGLES), body_angular_velocity(general, ANGLES)),
        (spatial_angular_velocity(orientation, ANGLES), spatial_angular_velocity(general, ANGLES)),
    ]:
        assert (closed - plain).applyfunc(sp.simplify) == sp.zeros(3, 1)


def _finite_difference_omega(orientation, coordinates, state, body: bool) -> np.ndarray:
    """vee(R^T dR/dt) by central differences along q_dot (an independent d/dt)."""
    h = 1e-6

    def at(step: float) -> np.ndarray:
        moved = dict(state)
        for q in coordinates:
            moved[q] = state[q] + step * state[velocity(q)]
        moved[t] = state[t] + step
        return _numbers(orientation.matrix, moved)

    R, R_dot = at(0.0), (at(h) - at(-h)) / (2 * h)
    skew = R.T @ R_dot if body else R_dot @ R.T
    return np.array([skew[2, 1], skew[0, 2], skew[1, 0]])


def _unit_quaternion():
    """(cos(a/2), sin(a/2) n(b, c)): a unit quaternion of angle a about the axis n(b, c)."""
    n = (sp.sin(b) * sp.cos(c), sp.sin(b) * sp.sin(c), sp.cos(b))
    return (sp.cos(a / 2), *(sp.sin(a / 2) * x for x in n))


@pytest.mark.parametrize(
    "orientation",
    [
        pytest.param(axis_angle([1, 2, 2], a + t), id="constant axis, rheonomic angle"),
        pytest.param(axis_angle([sp.cos(b), sp.sin(b), c], a), id="moving axis"),
        pytest.param(quaternion_rotation(*_unit_quaternion()), id="unit quaternion"),
        pytest.param(quaternion_rotation(a, b, c, 1 + t), id="quaternion of any length"),
        pytest.param(euler_rotation("ZYZ", (a, b, 2 * t)), id="Euler, a prescribed spin"),
    ],
)
def test_angular_velocity_is_vee_of_RT_Rdot_by_finite_differences(orientation) -> None:
    R = orientation.matrix
    for seed in range(2):
        state = _random_state(ANGLES, seed)
        identity = _numbers(R.T * R, state)
        np.testing.assert_allclose(identity, np.eye(3), atol=1e-12)
        for body, omega in [
            (True, body_angular_velocity(orientation, ANGLES)),
            (False, spatial_angular_velocity(orientation, ANGLES)),
        ]:
            expected = _finite_difference_omega(orientation, ANGLES, state, body)
            np.testing.assert_allclose(_numbers(omega, state).ravel(), expected, atol=1e-7)


def test_quaternion_rotation_is_sympys_for_a_unit_quaternion() -> None:
    w, x, y, z = sp.symbols("w x y z")
    N, B = pv.ReferenceFrame("N"), pv.ReferenceFrame("B")
    B.orient_quaternion(N, (w, x, y, z))
    norm = w**2 + x**2 + y**2 + z**2
    ours = quaternion_rotation(w, x, y, z).matrix
    assert (ours * norm - N.dcm(B)).applyfunc(sp.simplify) == sp.zeros(3, 3)
    # and its angular velocity is sympy's where the quaternion is a unit one identically
    dyn = pv.dynamicsymbols("a b c")
    unit = [e.subs({a: dyn[0], b: dyn[1], c: dyn[2]}) for e in _unit_quaternion()]
    N2, B2 = pv.ReferenceFrame("N"), pv.ReferenceFrame("B")
    B2.orient_quaternion(N2, unit)
    reference = _plain(B2.ang_vel_in(N2).to_matrix(B2), ["a", "b", "c"])
    omega = body_angular_velocity(quaternion_rotation(*_unit_quaternion()), ANGLES)
    state = _random_state(ANGLES, 3)
    np.testing.assert_allclose(_numbers(omega, state), _numbers(reference, state), atol=1e-12)


def test_a_unit_quaternion_is_not_divided_by_its_norm() -> None:
    unit = quaternion_rotation(*_unit_quaternion()).matrix  # |q|^2 = cos^2 + sin^2 = 1
    assert all(sp.fraction(sp.together(e))[1] == 1 for e in unit)
    general = quaternion_rotation(*sp.symbols("w x y z")).matrix
    assert all(sp.fraction(sp.together(e))[1] != 1 for e in general)
    assert quaternion_rotation(1, 0, 0, 0).matrix == sp.eye(3)
    assert quaternion_rotation(2, 0, 0, 0).matrix == sp.eye(3)  # q / |q|


def test_axis_angle_matches_sympy_orient_axis() -> None:
    theta = pv.dynamicsymbols("a")
    N, B = pv.ReferenceFrame("N"), pv.ReferenceFrame("B")
    B.orient_axis(N, N.x + 2 * N.y + 2 * N.z, theta)
    ours = axis_angle([1, 2, 2], a)
    assert (ours.matrix - _plain(N.dcm(B), ["a"])).applyfunc(sp.simplify) == sp.zeros(3, 3)
    omega = _plain(B.ang_vel_in(N).to_matrix(B), ["a"])
    assert (body_angular_velocity(ours, [a]) - omega).applyfunc(sp.simplify) == sp.zeros(3, 1)


def test_elementary_rotations_are_the_textbook_matrices() -> None:
    x = sp.Symbol("x")
    cx, sx = sp.cos(x), sp.sin(x)
    assert axis_angle([0, 0, 1], x).matrix == sp.Matrix([[cx, -sx, 0], [sx, cx, 0], [0, 0, 1]])
    assert axis_angle([1, 0, 0], x).matrix == sp.Matrix([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    assert axis_angle([0, 1, 0], x).matrix == sp.Matrix([[cx, 0, sx], [0, 1, 0], [-sx, 0, cx]])


vectors = st.lists(st.integers(-5, 5), min_size=3, max_size=3)


@settings(max_examples=30, deadline=None)
@given(vectors, vectors)
def test_hat_is_the_cross_product_and_vee_its_inverse(u: list[int], v: list[int]) -> None:
    assert hat(u) * sp.Matrix(v) == sp.Matrix(u).cross(sp.Matrix(v))
    assert vee(hat(u)) == sp.Matrix(u)
    assert hat(u) + hat(u).T == sp.zeros(3, 3)  # skew-symmetric


def _pose_twists(orientation, position, coordinates, state):
    """V_s = vee4(g_dot g^-1), V_b = vee4(g^-1 g_dot) from the 4x4 pose g (seed 003),
    evaluated at ``state``."""
    top = sp.Matrix.hstack(sp.Matrix(orientation.matrix), sp.Matrix(position))
    g = sp.Matrix.vstack(top, sp.Matrix([[0, 0, 0, 1]]))
    g_dot = g.applyfunc(lambda e: time_derivative(e, coordinates))
    g_value, g_rate = _numbers(g, state), _numbers(g_dot, state)
    g_inverse = np.linalg.inv(g_value)

    def twist(hat4: np.ndarray) -> np.ndarray:
        return np.array([*hat4[:3, 3], hat4[2, 1], hat4[0, 2], hat4[1, 0]])

    return twist(g_rate @ g_inverse), twist(g_inverse @ g_rate)


def test_twists_are_the_seeds_and_related_by_the_adjoint() -> None:
    orientation = euler_rotation("ZXZ", ANGLES)
    x, y = sp.symbols("x y")
    coordinates = [*ANGLES, x, y]
    position = [x, y * sp.sin(a), x * y + t]
    ours_s = spatial_twist(orientation, position, coordinates)
    ours_b = body_twist(orientation, position, coordinates)
    Ad = adjoint(orientation, position)
    for seed in range(3):
        state = _random_state(coordinates, seed)
        spatial, body = _pose_twists(orientation, position, coordinates, state)
        np.testing.assert_allclose(_numbers(ours_s, state).ravel(), spatial, atol=1e-12)
        np.testing.assert_allclose(_numbers(ours_b, state).ravel(), body, atol=1e-12)
        np.testing.assert_allclose(_numbers(Ad, state) @ body, spatial, atol=1e-12)
        np.testing.assert_allclose(
            _numbers(adjoint_inverse(orientation, position) * Ad, state), np.eye(6), atol=1e-12
        )


def test_a_matrix_that_is_not_a_rotation_is_found() -> None:
    x = sp.Symbol("x")
    shear = sp.Matrix([[1, x, 0], [0, 1, 0], [0, 0, 1]])
    (problem,) = check_rotation(shear, "R", [{x: 0.5}])
    assert "not orthonormal" in problem.message and "x = 0.5" in problem.message
    mirror = sp.diag(1, 1, -1)
    (problem,) = check_rotation(mirror, "R", [{}])
    assert "reflection" in problem.message
    assert check_rotation(euler_rotation("ZXZ", ANGLES).matrix, "R", [{a: 1, b: 2, c: 3}]) == []
    # orthonormal only at x = 0: a single sample elsewhere finds it
    assert check_rotation(axis_angle([0, 0, 1], x).matrix + sp.eye(3) * x, "R", [{x: 0.7}])


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: euler_rotation("ZXX", ANGLES), r"unknown Euler sequence 'ZXX'.*did you mean"),
        (lambda: euler_rotation("ZXZ", (a, b)), r"2 Euler angles given"),
        (lambda: axis_angle([0, 0, 0], a), r"the axis is the zero vector"),
        (lambda: axis_angle([0, 1], a), r"an axis of 2 components"),
    ],
)
def test_bad_rotations_are_refused(build, match: str) -> None:
    with pytest.raises(lg.ModelError, match=match):
        build()


def _body(orientation, inertia=None, **changes) -> lg.RigidBody:
    m = sp.Symbol("m")
    fields = {
        "name": "top",
        "mass": m,
        "inertia": sp.diag(1, 1, 1) if inertia is None else inertia,
        "position": (0, 0, 0),
        "orientation": orientation,
    }
    fields.update(changes)
    return lg.RigidBody(**fields)


def _system(*bodies: lg.RigidBody, parameters=None) -> lg.System:
    return lg.System(
        coordinates=list(ANGLES), parameters=parameters or {"m": 1.0}, rigid_bodies=bodies
    )


def test_a_system_refuses_an_orientation_that_is_not_a_rotation_naming_body_and_field() -> None:
    shear = [[1, a, 0], [0, 1, 0], [0, 0, 1]]
    with pytest.raises(
        lg.ModelError,
        match=r"rigid_bodies\[0\]\.orientation: the orientation of body 'top' is not orthonormal",
    ):
        _system(_body(shear))
    with pytest.raises(lg.ModelError, match=r"orientation of body 'top' is a reflection"):
        _system(_body(sp.diag(1, 1, -1)))
    with pytest.raises(lg.ModelError, match=r"rigid_bodies\[0\]\.orientation: unknown name 'k'"):
        _system(_body(axis_angle([0, 0, 1], sp.Symbol("k"))))
    with pytest.raises(lg.ModelError, match=r"orientation: .* is not a rotation"):
        _system(_body("up"))


def test_a_system_refuses_a_body_with_both_or_neither_an_angle_and_an_orientation() -> None:
    with pytest.raises(lg.ModelError, match=r"body 'top' has both an angle and an orientation"):
        _system(_body(axis_angle([0, 0, 1], a), angle=a))
    with pytest.raises(lg.ModelError, match=r"body 'top' has neither an angle nor an orientation"):
        _system(_body(None))
    with pytest.raises(lg.ModelError, match=r"a 3-D rigid body needs 3 components"):
        _system(_body(axis_angle([0, 0, 1], a), position=(0, 0)))


def test_a_rotation_built_from_parameters_is_checked_at_their_defaults() -> None:
    k = sp.Symbol("k")
    scaled = sp.Matrix(axis_angle([0, 0, 1], a).matrix) * k  # a rotation only for k = 1
    assert _system(_body(scaled), parameters={"m": 1.0, "k": 1.0}).rigid_bodies
    with pytest.raises(lg.ModelError, match=r"not orthonormal"):
        _system(_body(scaled), parameters={"m": 1.0, "k": 2.0})


def test_dynamicsymbols_in_an_orientation_become_the_coordinates() -> None:
    spin = pv.dynamicsymbols("a")
    system = lg.System(
        coordinates=[spin],
        parameters={"m": 1.0},
        rigid_bodies=[_body(axis_angle([0, 0, 1], spin))],
    )
    orientation = system.rigid_bodies[0].orientation
    assert orientation.angles == (a,) and orientation.matrix[0, 0] == sp.cos(a)
