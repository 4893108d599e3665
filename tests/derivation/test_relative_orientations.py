"""Bodies oriented relative to other bodies and frames (a gyroscope in two gimbals, a double
3-D pendulum) against sympy.physics.mechanics' KanesMethod on frames chained by orient_axis:
mass matrix, accelerations and T at random states to 1e-10."""

from __future__ import annotations

import sympy as sp
import sympy.physics.mechanics as me
from test_rigid_body_3d import assert_same_motion, kanes

from lagrangian.model import Frame, RigidBody, System, rotation_sequence


def _column(vector: tuple) -> sp.Matrix:
    return sp.Matrix(list(vector))


def test_a_gyroscope_in_two_gimbals_matches_kanes_method() -> None:
    """Outer gimbal about the world z axis (a), inner about the outer's x (b), the rotor about
    the inner's y (c), its centre at l along the inner's z: a heavy gyroscope."""
    q = me.dynamicsymbols("a b c")
    m1, m2, m, g, l, A1, B1, C1, A2, B2, C2, A, C = sp.symbols("m1 m2 m g l A1 B1 C1 A2 B2 C2 A C")
    world, outer, inner, rotor = (me.ReferenceFrame(n) for n in ("N", "O", "I", "R"))
    outer.orient_axis(world, world.z, q[0])
    inner.orient_axis(outer, outer.x, q[1])
    rotor.orient_axis(inner, inner.y, q[2])
    pivot = me.Point("P")
    pivot.set_vel(world, 0)
    centre = pivot.locatenew("G", l * inner.z)
    centre.v2pt_theory(pivot, world, inner)
    bodies = [
        me.RigidBody("outer", pivot, outer, m1, (me.inertia(outer, A1, B1, C1), pivot)),
        me.RigidBody("inner", pivot, inner, m2, (me.inertia(inner, A2, B2, C2), pivot)),
        me.RigidBody("rotor", centre, rotor, m, (me.inertia(rotor, A, C, A), centre)),
    ]
    reference = kanes(world, q, bodies, [(centre, -m * g * world.z)])

    a, b, c = sp.symbols("a b c")
    inner_axes = rotation_sequence([("z", a), ("x", b)]).matrix
    centre_at = tuple(inner_axes * sp.Matrix([0, 0, l]))
    system = System(
        coordinates=[a, b, c],
        parameters=[m1, m2, m, g, l, A1, B1, C1, A2, B2, C2, A, C],
        gravity=(0, 0, -g),
        frames=[Frame("heading", [("z", a)])],
        rigid_bodies=[
            RigidBody("outer", m1, sp.diag(A1, B1, C1), (0, 0, 0), parent="heading"),
            RigidBody(
                "inner", m2, sp.diag(A2, B2, C2), (0, 0, 0), parent="outer", rotations=[("x", b)]
            ),
            RigidBody(
                "rotor", m, sp.diag(A, C, A), centre_at, parent="inner", rotations=[("y", c)]
            ),
        ],
    )
    assert_same_motion(system, reference)


def test_a_double_3d_pendulum_matches_kanes_method() -> None:
    """Two rods on spherical-like joints: the first turned by (z, a), (x, b) from the world,
    the second by (x, c), (y, d) relative to the first."""
    q = me.dynamicsymbols("a b c d")
    m1, m2, l1, l2, g, I1, J1, K1, I2, J2, K2 = sp.symbols("m1 m2 l1 l2 g I1 J1 K1 I2 J2 K2")
    world, swing, first, tilt, second = (me.ReferenceFrame(n) for n in ("N", "S", "B", "T", "C"))
    swing.orient_axis(world, world.z, q[0])
    first.orient_axis(swing, swing.x, q[1])
    tilt.orient_axis(first, first.x, q[2])
    second.orient_axis(tilt, tilt.y, q[3])
    pivot = me.Point("O")
    pivot.set_vel(world, 0)
    g1 = pivot.locatenew("G1", -l1 / 2 * first.z)
    g1.v2pt_theory(pivot, world, first)
    joint = pivot.locatenew("J", -l1 * first.z)
    joint.v2pt_theory(pivot, world, first)
    g2 = joint.locatenew("G2", -l2 / 2 * second.z)
    g2.v2pt_theory(joint, world, second)
    bodies = [
        me.RigidBody("rod1", g1, first, m1, (me.inertia(first, I1, J1, K1), g1)),
        me.RigidBody("rod2", g2, second, m2, (me.inertia(second, I2, J2, K2), g2)),
    ]
    loads = [(g1, -m1 * g * world.z), (g2, -m2 * g * world.z)]
    reference = kanes(world, q, bodies, loads)

    a, b, c, d = sp.symbols("a b c d")
    R1 = rotation_sequence([("z", a), ("x", b)]).matrix
    R2 = rotation_sequence([("x", c), ("y", d)], parent=R1).matrix
    p1 = R1 * sp.Matrix([0, 0, -l1 / 2])
    p2 = R1 * sp.Matrix([0, 0, -l1]) + R2 * sp.Matrix([0, 0, -l2 / 2])
    system = System(
        coordinates=[a, b, c, d],
        parameters=[m1, m2, l1, l2, g, I1, J1, K1, I2, J2, K2],
        gravity=(0, 0, -g),
        rigid_bodies=[
            RigidBody("rod1", m1, sp.diag(I1, J1, K1), tuple(p1), rotations=[("z", a), ("x", b)]),
            RigidBody(
                "rod2",
                m2,
                sp.diag(I2, J2, K2),
                tuple(p2.applyfunc(sp.expand)),
                parent="rod1",
                rotations=[("x", c), ("y", d)],
            ),
        ],
    )
    assert_same_motion(system, reference)
