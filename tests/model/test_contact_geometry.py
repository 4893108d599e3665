"""The rolling-contact constraints as built: the Whipple bicycle's wheels against an
independent numerical reference (the lowest rim point found by minimising its height over the
rim angle, the material velocity there from finite differences of the position and of the
rotation matrix, omega = R_dot R^T), the horizontal length s of the axle found from its form
(cos(lean) for a leaning wheel, sin(tilt) for a tilted one, the square root kept whole for a
steered one), and the cheap checks of a System (linear velocity constraints at sight, the
numerical rotation check only for a matrix given as such)."""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.examples import BENCHMARKS
from lagrangian.model import Frame, RigidBody, RollingDisc, System, shape
from lagrangian.model.constraints import _linear
from lagrangian.model.contact import (
    ContactHeight,
    NoSlip,
    _HorizontalLength,
    _over_s,
    _plainly_not_zero,
    _wheel_geometry,
    contact_point,
)
from lagrangian.model.rotation import angular_velocity_terms, euler_rotation
from lagrangian.symbolic.native import to_symengine
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.symbols import velocity

x, y, z, psi, theta, phi, m, r = sp.symbols("x y z psi theta phi m r")


@pytest.fixture(scope="module")
def bicycle() -> System:
    return BENCHMARKS["whipple_bicycle"]()


def _reference_slip(system: System, body_name: str, radius: str, state: dict) -> np.ndarray:
    """(C_z, v_C . e_x, v_C . e_y) of a wheel with axle y, by numbers alone."""
    body = next(b for b in system.rigid_bodies if b.name == body_name)
    q = list(system.coordinates)
    known = {p: v for p, v in system.parameters.items() if v is not None}
    p_of = sp.lambdify(q, sp.Matrix(body.position).xreplace(known), "numpy")
    R_of = sp.lambdify(q, sp.Matrix(body.orientation.matrix).xreplace(known), "numpy")
    r_value = known[sp.Symbol(radius)]
    at = np.array([state[s] for s in q])
    rates = np.array([state[velocity(s)] for s in q])

    def lowest(R: np.ndarray) -> np.ndarray:
        # rim points p + r (cos u e1 + sin u e3): lowest where tan u = e3_z / e1_z
        u = np.arctan2(-R[2, 2], -R[2, 0])
        return r_value * (np.cos(u) * R[:, 0] + np.sin(u) * R[:, 2])

    h = 1e-6
    p = np.array(p_of(*at), dtype=float).ravel()
    R = np.array(R_of(*at), dtype=float)
    p_dot = (
        np.array(p_of(*(at + h * rates)), dtype=float).ravel()
        - np.array(p_of(*(at - h * rates)), dtype=float).ravel()
    ) / (2 * h)
    R_dot = (np.array(R_of(*(at + h * rates))) - np.array(R_of(*(at - h * rates)))) / (2 * h)
    arm = lowest(R)
    v = p_dot + R_dot @ R.T @ arm
    return np.array([p[2] + arm[2], v[0], v[1]])


def _ours(system: System, contact: str, state: dict) -> np.ndarray:
    known = {p: v for p, v in system.parameters.items() if v is not None}
    found = {
        c.name.split()[-1]: c.expression for c in system.constraints if c.name.startswith(contact)
    }
    values = []
    for key in ("height", "x", "y"):
        expr = found.get(key, sp.Integer(0))
        values.append(float(expr.xreplace(known).xreplace(state)))
    return np.array(values)


@pytest.mark.parametrize(("body", "radius"), [("rear_wheel", "rR"), ("front_wheel", "rF")])
def test_the_bicycle_wheels_roll_as_their_lowest_rim_points_say(
    bicycle: System, body: str, radius: str
) -> None:
    rng = random.Random(11)
    for _ in range(4):
        state = {s: rng.uniform(-0.6, 0.6) for s in bicycle.coordinates}
        state.update({velocity(s): rng.uniform(-2.0, 2.0) for s in bicycle.coordinates})
        expected = _reference_slip(bicycle, body, radius, state)
        np.testing.assert_allclose(_ours(bicycle, f"{body}_contact", state), expected, atol=1e-7)


def test_the_bicycle_has_the_front_contact_height_and_four_no_slip_constraints(
    bicycle: System,
) -> None:
    kinds = [(type(c), c.name) for c in bicycle.constraints]
    assert kinds == [
        (NoSlip, "rear_wheel_contact slip x"),
        (NoSlip, "rear_wheel_contact slip y"),
        (ContactHeight, "front_wheel_contact height"),
        (NoSlip, "front_wheel_contact slip x"),
        (NoSlip, "front_wheel_contact slip y"),
    ]


def _roots(expr: sp.Expr) -> set[sp.Expr]:
    return {p.base for p in expr.atoms(sp.Pow) if p.exp in (sp.S.Half, -sp.S.Half)}


def test_a_leaning_wheel_has_s_cos_lean_and_a_steered_one_keeps_one_whole_root(
    bicycle: System,
) -> None:
    rear = [c.expression for c in bicycle.constraints if c.name.startswith("rear")]
    assert all(not _roots(e) for e in rear)
    lean, steer = sp.symbols("lean steer")
    front = [c.expression for c in bicycle.constraints if c.name.startswith("front")]
    (base,) = set().union(*(_roots(e) for e in front))
    # 1 - a_z^2 with a_z the front axle's vertical component, not multiplied out
    a_z = sp.sympify(base - 1).args
    assert base.is_Add and len(base.args) == 2 and any(p.is_Pow for p in a_z)
    assert sp.expand(base.subs({lean: 0, steer: 0})) == 1


def _wheel(orientation: lg.model.Orientation, axis: str) -> System:
    body = RigidBody(
        "wheel", m, shape("disc", radius=r, axis=axis), (x, y, z), orientation=orientation
    )
    return System(
        coordinates=[x, y, z, psi, theta, phi],
        parameters={m: 1.0, r: 0.3},
        rigid_bodies=[body],
        rolling=[RollingDisc("wheel", r)],
    )


@pytest.mark.parametrize(
    ("sequence", "axis", "height"),
    [
        ("ZXY", "y", r * sp.cos(theta)),  # heading, lean, spin: s = cos(lean)
        ("ZXZ", "z", r * sp.sin(theta)),  # precession, tilt, spin: s = sin(tilt)
        ("ZYX", "x", r * sp.cos(theta)),  # heading, lean about y, spin about x
    ],
)
def test_s_is_found_from_the_form_of_the_axle(sequence: str, axis: str, height: sp.Expr) -> None:
    system = _wheel(euler_rotation(sequence, (psi, theta, phi)), axis)
    height_constraint, *_ = system.constraints
    assert sp.expand(height_constraint.expression - (z - height)) == 0
    assert all(not _roots(c.expression) for c in system.constraints)
    point = contact_point(system.rolling[0], system.rigid_bodies[0])
    assert sp.expand(point[2] - (z - height)) == 0


def test_a_velocity_constraint_linear_only_once_expanded_is_accepted() -> None:
    x_dot, y_dot = velocity(x), velocity(y)
    square = (x_dot + y_dot) * (x_dot - y_dot) - x_dot**2 + y_dot**2 + x_dot * sp.cos(y)
    system = System(
        coordinates=[x, y],
        parameters={m: 1.0},
        kinetic=m * (x_dot**2 + y_dot**2) / 2,
        constraints=[lg.VelocityConstraint(square)],
    )
    assert system.constraints[0].expression == square


def test_the_no_slip_constraints_pass_the_linearity_check_the_system_skips_for_them(
    bicycle: System,
) -> None:
    # linear by construction (NoSlip.linear_by_construction): the check a user's velocity
    # constraint gets, and SymPy's Hessian in the velocities, find them linear
    rates = {velocity(q) for q in bicycle.coordinates}
    slips = [c.expression for c in bicycle.constraints if isinstance(c, NoSlip)]
    assert len(slips) == 4
    for expr in slips:
        used = sorted(expr.free_symbols & rates, key=str)
        assert used and _linear(expr, used)
        hessian = sp.hessian(expr, used)
        assert all(sp.expand(e) == 0 for e in hessian)


def test_rotations_relative_to_a_given_matrix_are_still_checked() -> None:
    skewed = sp.Matrix([[1, 0, 0], [0, 1, sp.Rational(1, 2)], [0, 0, 1]])
    body = RigidBody("top", m, sp.eye(3), (0, 0, 0), parent="stand", rotations=[("z", psi)])
    with pytest.raises(lg.ModelError, match=r"orientation of body 'top' is not orthonormal"):
        System(
            coordinates=[psi],
            parameters={m: 1.0},
            frames=[Frame("stand", orientation=skewed)],
            rigid_bodies=[body],
        )


def test_a_rolling_body_whose_position_symengine_cannot_hold_is_refused_by_field() -> None:
    body = RigidBody(
        "wheel",
        m,
        shape("disc", radius=r, axis="y"),
        (x, y, r * sp.cos(theta) + sp.Integral(x, (psi, 0, 1))),
        orientation=euler_rotation("ZXY", (psi, theta, phi)),
    )
    with pytest.raises(lg.ModelError, match=r"rolling\[0\]: the body 'wheel': .*Integral"):
        System(
            coordinates=[x, y, psi, theta, phi],
            parameters={m: 1.0, r: 0.3},
            rigid_bodies=[body],
            rolling=[RollingDisc("wheel", r)],
        )


@pytest.mark.parametrize("seed", range(8))
def test_a_coefficient_over_s_is_the_expansion_with_s_squared_replaced(seed: int) -> None:
    # _over_s writes s plain as A + B s + C (1 - a_z^2) from plain = A / s + B + C s: the
    # same expression as s plain expanded with s^2 replaced by 1 - a_z^2 and expanded again,
    # on expanded sums of the kind a steered wheel makes (s only as 1 / s and s)
    rng = random.Random(seed)
    s = _HorizontalLength.SYMBOL
    lean, steer, lam, rF = se.symbols("lean steer lam rF")
    a_z = se.sin(lean) * se.cos(steer) * se.sin(lam) + se.cos(lean) * se.sin(steer) - rF
    length = _HorizontalLength(s, se.sqrt(1 - a_z**2), a_z)
    factors = [se.sin(lean), se.cos(steer), se.sin(lam) ** 2, rF, a_z, se.sqrt(1 + lean**2)]
    terms = [
        rng.randint(-3, 3) * rng.choice([1, s, 1 / s]) * se.Mul(*rng.choices(factors, k=3))
        for _ in range(10)
    ]
    plain = se.expand(se.Add(*terms))
    expected = se.expand(se.expand(plain * s).xreplace({s**2: 1 - a_z**2}))
    assert _over_s(plain, length) == expected
    assert str(_over_s(plain, length)) == str(expected)


def test_the_bicycle_front_wheel_coefficients_over_s_are_the_full_expansion(
    bicycle: System,
) -> None:
    # every coefficient the front wheel's no-slip sums are tidied from, written over s both
    # ways (the rear wheel leans: its s is cos(lean), no placeholder)
    body = next(b for b in bicycle.rigid_bodies if b.name == "front_wheel")
    geometry = _wheel_geometry(RollingDisc("front_wheel", sp.Symbol("rF"), "y"), body)
    s = _HorizontalLength.SYMBOL
    assert not geometry.length.closed
    q = tuple(bicycle.coordinates)
    omega = angular_velocity_terms(body.orientation, q, body=False)
    offset = geometry.offset
    over = 0
    for v in q:
        w = [se.diff(e, to_symengine(velocity(v))) for e in omega]
        for k in (0, 1):
            i, j = (k + 1) % 3, (k + 2) % 3
            centre = se.diff(to_symengine(body.position[k]), to_symengine(v))
            plain = se.expand(centre + w[i] * offset[j] - w[j] * offset[i])
            if not plain.has(s):
                continue
            over += 1
            expected = se.expand(se.expand(plain * s).xreplace({s**2: 1 - geometry.length.a_z**2}))
            assert _over_s(plain, geometry.length) == expected
    assert over >= 8


def test_what_is_plainly_not_zero_the_probe_finds_not_zero() -> None:
    # the wheel's geometry asks the probe only where its radius and closed s are not plainly
    # non-zero; what is plainly so, the probe finds so too, and the rest is left to it
    lean, rR, lam = se.symbols("lean rR lam")
    plain = [rR, se.Integer(2), se.Rational(-1, 3), se.cos(lean), se.sin(lean), se.cos(lam)]
    for expr in plain:
        assert _plainly_not_zero(expr)
        assert not is_zero(expr)
    left = [se.Integer(0), se.sqrt(se.Rational(3, 4)), rR - rR, se.sin(-lam), se.sin(lean) ** 2]
    assert not any(_plainly_not_zero(expr) for expr in left)
