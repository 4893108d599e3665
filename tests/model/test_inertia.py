"""Inertia tensors: shapes against the defining integral I = int rho (|r|^2 1 - r r^T) dV,
rotation and the parallel-axis theorem against sympy.physics.mechanics, combination against
a body cut in two, and the generalized inertia matrix against the kinetic energy (seed 003)."""

from __future__ import annotations

import random
import re
from functools import cache

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.model import inertia as inertia_module
from lagrangian.model.inertia import (
    SHAPES,
    MassProperties,
    box,
    check_inertia,
    combine,
    cylinder,
    disc,
    generalized_inertia,
    hollow_sphere,
    parallel_axis,
    ring,
    rod,
    rotated,
    shape,
    solid_sphere,
    spatial_inertia,
)
from lagrangian.model.rotation import euler_rotation, hat
from lagrangian.model.twist import body_twist, spatial_twist
from lagrangian.symbolic.symbols import t, velocity

m, r, h, A, B, C = sp.symbols("m r h A B C", positive=True)
x, y, z = sp.symbols("x y z", real=True)
rho, u, v = sp.symbols("rho u v", real=True)


def _integrand(point: sp.Matrix) -> sp.Matrix:
    return point.dot(point) * sp.eye(3) - point * point.T


def _integrate(density, point, *limits) -> sp.Matrix:
    return (density * _integrand(point)).applyfunc(lambda e: sp.integrate(e, *limits))


def _cylindrical(s, phi, zz) -> sp.Matrix:
    return sp.Matrix([s * sp.cos(phi), s * sp.sin(phi), zz])


phi, theta = sp.symbols("phi theta", real=True)


@cache
def _reference_tensors() -> dict[str, tuple[sp.Matrix, sp.Matrix]]:
    """Ours and the integral, each shape along z (mass m spread uniformly)."""
    L = h
    volume_cylinder = sp.pi * r**2 * L
    return {
        "rod": (rod(m, L), _integrate(m / L, sp.Matrix([0, 0, z]), (z, -L / 2, L / 2))),
        "disc": (
            disc(m, r),
            _integrate(
                m / (sp.pi * r**2) * rho,
                _cylindrical(rho, phi, 0),
                (rho, 0, r),
                (phi, 0, 2 * sp.pi),
            ),
        ),
        "ring": (
            ring(m, r),
            _integrate(m / (2 * sp.pi), _cylindrical(r, phi, 0), (phi, 0, 2 * sp.pi)),
        ),
        "cylinder": (
            cylinder(m, r, L),
            _integrate(
                m / volume_cylinder * rho,
                _cylindrical(rho, phi, z),
                (rho, 0, r),
                (phi, 0, 2 * sp.pi),
                (z, -L / 2, L / 2),
            ),
        ),
        "solid_sphere": (
            solid_sphere(m, r),
            _integrate(
                m / (sp.Rational(4, 3) * sp.pi * r**3) * rho**2 * sp.sin(theta),
                rho
                * sp.Matrix(
                    [sp.sin(theta) * sp.cos(phi), sp.sin(theta) * sp.sin(phi), sp.cos(theta)]
                ),
                (rho, 0, r),
                (theta, 0, sp.pi),
                (phi, 0, 2 * sp.pi),
            ),
        ),
        "hollow_sphere": (
            hollow_sphere(m, r),
            _integrate(
                m / (4 * sp.pi) * sp.sin(theta),
                r
                * sp.Matrix(
                    [sp.sin(theta) * sp.cos(phi), sp.sin(theta) * sp.sin(phi), sp.cos(theta)]
                ),
                (theta, 0, sp.pi),
                (phi, 0, 2 * sp.pi),
            ),
        ),
        "box": (
            box(m, A, B, C),
            _integrate(
                m / (A * B * C),
                sp.Matrix([x, y, z]),
                (x, -A / 2, A / 2),
                (y, -B / 2, B / 2),
                (z, -C / 2, C / 2),
            ),
        ),
    }


@pytest.mark.parametrize("kind", list(SHAPES))
def test_shapes_are_the_integral_of_their_mass_distribution(kind: str) -> None:
    ours, integral = _reference_tensors()[kind]
    assert (ours - integral).applyfunc(sp.simplify) == sp.zeros(3, 3)


def test_shapes_are_the_textbook_values() -> None:
    assert solid_sphere(m, r)[0, 0] == sp.Rational(2, 5) * m * r**2
    assert hollow_sphere(m, r)[1, 1] == sp.Rational(2, 3) * m * r**2
    assert disc(m, r)[2, 2] == m * r**2 / 2 and disc(m, r)[0, 0] == m * r**2 / 4
    assert ring(m, r)[2, 2] == m * r**2 and ring(m, r)[1, 1] == m * r**2 / 2
    assert rod(m, h)[0, 0] == m * h**2 / 12 and rod(m, h)[2, 2] == 0
    assert sp.simplify(cylinder(m, r, h)[0, 0] - m * (3 * r**2 + h**2) / 12) == 0
    assert sp.expand(box(m, A, B, C)[0, 0] - m * (B**2 + C**2) / 12) == 0


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_the_axis_of_an_axisymmetric_shape_is_where_its_moment_is(axis: str) -> None:
    tensor = cylinder(m, r, h, axis=axis)
    index = "xyz".index(axis)
    assert tensor[index, index] == m * r**2 / 2
    assert shape("cylinder", radius=r, length=h, axis=axis).tensor(m) == tensor


def test_rotated_is_sympy_mechanics_inertia_expressed_in_another_frame() -> None:
    a, b, c = sp.symbols("a b c")
    Ixx, Iyy, Izz, Ixy, Iyz, Izx = sp.symbols("Ixx Iyy Izz Ixy Iyz Izx")
    N = me.ReferenceFrame("N")
    body = N.orientnew("B", "Body", (a, b, c), "ZXY")
    dyadic = me.inertia(body, Ixx, Iyy, Izz, Ixy, Iyz, Izx)
    tensor = sp.Matrix([[Ixx, Ixy, Izx], [Ixy, Iyy, Iyz], [Izx, Iyz, Izz]])
    ours = rotated(tensor, euler_rotation("ZXY", (a, b, c)))
    reference = dyadic.to_matrix(N)
    assert (ours - reference).applyfunc(sp.simplify) == sp.zeros(3, 3)


def test_parallel_axis_is_sympy_mechanics_inertia_of_a_point_mass() -> None:
    N = me.ReferenceFrame("N")
    d = sp.symbols("d1 d2 d3")
    point = me.inertia_of_point_mass(m, d[0] * N.x + d[1] * N.y + d[2] * N.z, N)
    centre = box(m, A, B, C)
    expected = centre + point.to_matrix(N)
    assert (parallel_axis(centre, m, d) - expected).applyfunc(sp.expand) == sp.zeros(3, 3)


def test_combining_two_halves_of_a_box_gives_the_whole_box() -> None:
    half = box(m / 2, A / 2, B, C)
    parts = [
        MassProperties(m / 2, (-A / 4, 0, 0), half),
        MassProperties(m / 2, (A / 4, 0, 0), half),
    ]
    whole = combine(parts)
    assert whole.mass == m and whole.centre == (0, 0, 0)
    assert (whole.inertia - box(m, A, B, C)).applyfunc(sp.simplify) == sp.zeros(3, 3)


def test_combining_point_masses_gives_their_centre_and_inertia() -> None:
    m1, m2, l = sp.symbols("m1 m2 l", positive=True)
    dumbbell = combine(
        [MassProperties(m1, (0, 0, 0), sp.zeros(3)), MassProperties(m2, (l, 0, 0), sp.zeros(3))]
    )
    assert sp.simplify(dumbbell.centre[0] - m2 * l / (m1 + m2)) == 0
    # seed 003: the reduced mass m1 m2 / (m1 + m2) times l^2 about the centre
    assert sp.simplify(dumbbell.inertia[1, 1] - m1 * m2 * l**2 / (m1 + m2)) == 0
    assert dumbbell.inertia[0, 0] == 0


def test_generalized_inertia_gives_the_same_energy_in_body_and_spatial_frames() -> None:
    """1/2 V_s^T M^s V_s = 1/2 V_b^T M^b V_b = 1/2 m |p_dot|^2 + 1/2 w_b^T I w_b."""
    angles = sp.symbols("a b c")
    p = sp.symbols("p1 p2 p3")
    coordinates = [*angles, *p]
    orientation = euler_rotation("ZYX", angles)
    tensor = sp.Matrix([[3, 0.2, -0.1], [0.2, 2, 0.3], [-0.1, 0.3, 2.5]])
    mass = 1.7
    M_b = generalized_inertia(mass, tensor)
    M_s = spatial_inertia(mass, tensor, orientation, p)
    V_b = body_twist(orientation, p, coordinates)
    V_s = spatial_twist(orientation, p, coordinates)
    omega_b = V_b[3:, :]
    p_dot = sp.Matrix([velocity(s) for s in p])
    rng = random.Random(7)
    for _ in range(3):
        state = {s: rng.uniform(-2, 2) for s in coordinates}
        state.update({velocity(s): rng.uniform(-2, 2) for s in coordinates})
        state[t] = 0.0
        definition = (mass * p_dot.dot(p_dot) + (omega_b.T * tensor * omega_b)[0]) / 2
        expected = float(definition.xreplace(state))
        body = float(((V_b.T * M_b * V_b)[0] / 2).xreplace(state))
        spatial = float(((V_s.T * M_s * V_s)[0] / 2).xreplace(state))
        assert body == pytest.approx(expected, rel=1e-12)
        assert spatial == pytest.approx(expected, rel=1e-12)


def test_spatial_inertia_is_the_seeds_block_form() -> None:
    """M^s = [[m 1, -m hat(c)], [m hat(c), R I R^T - m hat(c)^2]] (seed 003, c = p)."""
    angles = sp.symbols("a b c")
    p = sp.Matrix(sp.symbols("p1 p2 p3"))
    orientation = euler_rotation("ZXZ", angles)
    tensor = sp.diag(A, B, C)
    c_hat = hat(p)
    world = orientation.matrix * tensor * orientation.matrix.T
    expected = sp.Matrix(
        sp.BlockMatrix(
            [[m * sp.eye(3), -m * c_hat], [m * c_hat, world - m * c_hat**2]]
        ).as_explicit()
    )
    ours = spatial_inertia(m, tensor, orientation, p)
    rng = random.Random(3)
    for _ in range(3):
        point = {s: rng.uniform(-2, 2) for s in (*angles, *p, m, A, B, C)}
        difference = (ours - expected).xreplace(point).evalf()
        assert np.max(np.abs(np.array(difference, dtype=float))) < 1e-12
    assert generalized_inertia(m, tensor) == sp.diag(m, m, m, A, B, C)


@pytest.mark.parametrize(
    ("tensor", "values", "message"),
    [
        (sp.Matrix([[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]), {}, r"is not symmetric"),
        (sp.diag(1, -1, 1), {}, r"not positive semidefinite \(a principal moment is -1\)"),
        (sp.diag(1, 1, 2.5), {}, r"\(1, 1, 2.5\) violate the triangle inequality"),
        (sp.diag(A, A, C), {A: 1.0, C: 3.0}, r"\(1, 1, 3\) violate the triangle inequality"),
        (sp.diag(-A, B, C), {}, r"has a negative moment on its diagonal"),
        (sp.diag(A, A, 3 * A), {}, r"violate the triangle inequality"),
    ],
)
def test_impossible_inertia_tensors_are_found(tensor, values, message: str) -> None:
    (problem,) = check_inertia(tensor, "I", values)
    assert problem.field == "I"
    assert re.search(message, problem.message), problem.message


@pytest.mark.parametrize(
    ("tensor", "values"),
    [
        (rod(1, 2), {}),  # a thin rod: one zero moment, still a body
        (sp.diag(A, B, C), {}),  # unknown values: nothing to decide
        (sp.diag(sp.Symbol("I1"), sp.Symbol("I1"), sp.Symbol("I3")), {}),
        (rotated(box(1, 1, 2, 3), euler_rotation("ZXZ", (0.3, 0.2, 0.1))), {}),
        (sp.diag(A, A, C), {A: 1.0, C: 2.0}),  # on the boundary: a flat disc
    ],
)
def test_possible_inertia_tensors_pass(tensor, values) -> None:
    assert check_inertia(tensor, "I", values) == []


def test_shape_refuses_what_it_cannot_build() -> None:
    with pytest.raises(lg.ModelError, match=r"unknown shape 'cylindre'.*did you mean 'cylinder'"):
        shape("cylindre", radius=r, length=h)
    with pytest.raises(lg.ModelError, match=r"a cylinder needs its length"):
        shape("cylinder", radius=r)
    with pytest.raises(lg.ModelError, match=r"a solid_sphere has no dimension 'length'"):
        shape("solid_sphere", radius=r, length=h)
    with pytest.raises(lg.ModelError, match=r"axis 'x' is not allowed .* no axis of symmetry"):
        shape("box", length_x=1, length_y=2, length_z=3, axis="x")


def test_every_shape_has_a_tensor_function_with_its_dimensions() -> None:
    for kind, (function, names, axial) in SHAPES.items():
        assert getattr(inertia_module, kind) is function
        sizes = dict.fromkeys(names, sp.Integer(2))
        assert shape(kind, **sizes).tensor(m) == function(m, *sizes.values())
        assert axial == ("axis" in function.__code__.co_varnames)


# -- bodies in a System -------------------------------------------------------------------------


def _top(inertia, parameters) -> lg.System:
    a, b, c = sp.symbols("a b c")
    return lg.System(
        coordinates=[a, b, c],
        parameters=parameters,
        rigid_bodies=[
            lg.RigidBody(
                "top",
                sp.Symbol("m"),
                inertia,
                (0, 0, 0),
                orientation=euler_rotation("ZXZ", (a, b, c)),
            )
        ],
    )


def test_a_system_refuses_an_impossible_inertia_naming_body_and_field() -> None:
    with pytest.raises(
        lg.ModelError,
        match=r"rigid_bodies\[0\]\.inertia: the principal moments of the inertia of body 'top' "
        r"\(0.5, 0.5, 2\) violate the triangle inequality",
    ):
        _top(sp.diag(sp.Symbol("A"), sp.Symbol("A"), sp.Symbol("C")), {"m": 1, "A": 0.5, "C": 2})
    with pytest.raises(lg.ModelError, match=r"inertia of body 'top' is not symmetric"):
        _top([[1, 0, 0], [0.5, 1, 0], [0, 0, 1]], {"m": 1})
    with pytest.raises(lg.ModelError, match=r"a 3-D rigid body needs a 3x3 inertia"):
        _top(sp.Symbol("A"), {"m": 1, "A": 1})
    with pytest.raises(lg.ModelError, match=r"inertia: unknown name 'R'"):
        _top(shape("disc", radius=sp.Symbol("R")), {"m": 1})
    with pytest.raises(lg.ModelError, match=r"'R' is not an expression"):
        shape("disc", radius="R")  # text is not evaluated
    # without defaults nothing numeric is decided; a negative mass makes a shape's tensor negative
    assert _top(
        sp.diag(sp.Symbol("A"), sp.Symbol("A"), sp.Symbol("C")), {"m": 1, "A": None, "C": None}
    )
    with pytest.raises(lg.ModelError, match=r"not positive semidefinite"):
        _top(shape("solid_sphere", radius=1), {"m": -1})


def test_a_body_with_a_shape_has_its_tensor_from_its_mass() -> None:
    dimensions = {"radius": sp.Symbol("r"), "length": sp.Symbol("h")}
    system = _top(shape("cylinder", axis="x", **dimensions), {"m": 2, "r": 1, "h": 3})
    body = system.rigid_bodies[0]
    mass, radius, length = (sp.Symbol(s) for s in "mrh")
    assert body.inertia_tensor == cylinder(mass, radius, length, axis="x")
    assert not body.planar
    with pytest.raises(ValueError, match=r"planar body 'rod' has a scalar moment of inertia"):
        _ = lg.RigidBody("rod", 1, 1, (0, 0), angle=sp.Symbol("q")).inertia_tensor


def test_numbers_in_a_tensor_are_exact() -> None:
    body = lg.RigidBody(
        "b", 1, [[1, 0, 0], [0, 2.5, 0], [0, 0, 2]], (0, 0, 0), orientation=np.eye(3).tolist()
    )
    assert body.inertia[1, 1] == sp.Rational(5, 2)
    assert body.orientation.form == "matrix"
