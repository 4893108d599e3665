"""Rotation matrices given whole: recognised as products of rotations about constant axes,
their angular velocities composed from the factors, checked against the angular velocity
differentiated from the matrix (vee(R^T R_dot), evaluated in numbers) and against the same
rotations given as a sequence."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp

from lagrangian.model.rotation import (
    as_orientation,
    body_angular_velocity,
    quaternion_rotation,
    rotation_sequence,
    spatial_angular_velocity,
)
from lagrangian.model.rotation_factors import factor_rotation
from lagrangian.symbolic.symbols import t, time_derivative, velocity

yaw, lean, pitch, steer, spin, lam, h = sp.symbols("yaw lean pitch steer spin lam h")
Q = (yaw, lean, pitch, steer, spin)


def rx(a: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(a), sp.sin(a)
    return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(a), sp.sin(a)
    return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(a), sp.sin(a)
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _differentiated(R: sp.Matrix, at: dict) -> tuple[np.ndarray, np.ndarray]:
    """vee(R^T R_dot) and vee(R_dot R^T) in numbers, R_dot by the chain rule: the
    definition, with no simplification needed."""
    R_dot = R.applyfunc(lambda e: time_derivative(e, Q))
    body, spatial = (R.T * R_dot).xreplace(at), (R_dot * R.T).xreplace(at)
    vee = [(2, 1), (0, 2), (1, 0)]
    return (
        np.array([float(body[i, j].evalf()) for i, j in vee]),
        np.array([float(spatial[i, j].evalf()) for i, j in vee]),
    )


def _state(rng: random.Random) -> dict:
    values = {s: rng.uniform(-2, 2) for s in Q}
    values.update({velocity(s): rng.uniform(-2, 2) for s in Q})
    values.update({lam: rng.uniform(0.1, 1.0), h: rng.uniform(0.1, 1.0), t: 0.3})
    return values


FORK = rz(yaw) * rx(lean) * ry(pitch) * ry(-lam) * rz(-steer) * ry(lam) * ry(spin)
CASES = {
    "elementary product": rz(yaw) * rx(lean) * ry(pitch),
    "bicycle fork and wheel (steer axis tilted by a constant)": FORK,
    "constant rotation on the right": rz(yaw) * rx(lean) * ry(lam),
    "constant rotation in between": rz(yaw) * rx(lam) * ry(pitch),
    "angles with offsets and a time-dependent turn": rz(yaw + lam) * rx(h * t) * ry(2 * pitch),
    "a quaternion of half angles": sp.Matrix(
        quaternion_rotation(sp.cos(yaw / 2), 0, 0, sp.sin(yaw / 2)).matrix
    )
    * rx(lean),
}


def test_a_quaternion_of_half_angles_turns_by_the_whole_angle() -> None:
    R = sp.Matrix(quaternion_rotation(sp.cos(yaw / 2), sp.sin(yaw / 2), 0, 0).matrix)
    found = factor_rotation(R, Q)
    assert found is not None
    assert [(tuple(n), a) for n, a in found.factors] == [((1, 0, 0), yaw)]


@pytest.mark.parametrize("name", list(CASES))
def test_a_product_given_whole_is_factored_and_its_angular_velocity_is_the_definitions(
    name: str,
) -> None:
    R = CASES[name]
    assert factor_rotation(R, Q) is not None
    body = body_angular_velocity(as_orientation(R), Q)
    spatial = spatial_angular_velocity(as_orientation(R), Q)
    rng = random.Random(3)
    for _ in range(3):
        at = _state(rng)
        expected_body, expected_spatial = _differentiated(R, at)
        np.testing.assert_allclose(
            np.array(body.xreplace(at).evalf(), dtype=float).ravel(), expected_body, atol=1e-12
        )
        np.testing.assert_allclose(
            np.array(spatial.xreplace(at).evalf(), dtype=float).ravel(),
            expected_spatial,
            atol=1e-12,
        )


def test_the_factors_are_the_elementary_rotations_written() -> None:
    found = factor_rotation(FORK, Q)
    assert found is not None and found.tail is None
    axes = [tuple(axis) for axis, _ in found.factors]
    # yaw about z, lean about x, pitch about y, steer about the tilted steer axis, spin about y
    assert [angle for _, angle in found.factors] == [yaw, lean, pitch, steer, spin]
    assert axes == [(0, 0, 1), (1, 0, 0), (0, 1, 0), (sp.sin(lam), 0, -sp.cos(lam)), (0, 1, 0)]


def test_a_constant_tail_is_kept_apart() -> None:
    found = factor_rotation(rz(yaw) * rx(lean) * ry(lam), Q)
    assert found is not None
    assert found.tail == sp.ImmutableMatrix(ry(lam))


def test_the_composed_angular_velocity_is_the_sequence_s() -> None:
    sequence = [("z", yaw), ("x", lean), ("y", pitch), ("y", -lam), ("z", -steer), ("y", lam)]
    expected = body_angular_velocity(rotation_sequence(sequence), Q)
    given = body_angular_velocity(as_orientation(rz(yaw) * rx(lean) * ry(pitch) * FORK_TILT), Q)
    difference = (expected - given).applyfunc(sp.expand).applyfunc(sp.trigsimp)
    assert difference == sp.zeros(3, 1)


FORK_TILT = ry(-lam) * rz(-steer) * ry(lam)


@pytest.mark.parametrize(
    "R",
    [
        rz(yaw) * rx(lean) * rz(yaw),  # one angle in two factors
        quaternion_rotation(sp.cos(yaw / 2), 0, sp.sin(yaw / 2), 0).matrix.xreplace({}) * rx(lean),
        sp.Matrix([[1, 0, 0], [0, 1, yaw], [0, 0, 1]]),  # not a rotation
    ],
    ids=["repeated angle", "half angles", "shear"],
)
def test_what_is_not_a_product_of_distinct_turns_is_left_to_the_definition(R: sp.Matrix) -> None:
    found = factor_rotation(R, Q)
    if found is None:
        return
    # a factoring that is found must be right: the product equals R
    product = sp.eye(3)
    for axis, angle in found.factors:
        product = product * rotation_sequence([(tuple(axis), angle)]).matrix
    tail = found.tail if found.tail is not None else sp.eye(3)
    at = _state(random.Random(5))
    difference = np.array((product * tail - R).xreplace(at).evalf(), dtype=float)
    np.testing.assert_allclose(difference, 0, atol=1e-12)


def test_a_repeated_angle_still_gets_the_definitions_angular_velocity() -> None:
    R = rz(yaw) * rx(lean) * rz(yaw)
    assert factor_rotation(R, Q) is None
    body = body_angular_velocity(as_orientation(R), Q)
    at = _state(random.Random(11))
    expected, _ = _differentiated(R, at)
    np.testing.assert_allclose(
        np.array(body.xreplace(at).evalf(), dtype=float).ravel(), expected, atol=1e-12
    )
