"""Every particle and rigid body of a System as a frame of its own (MLS94 ch. 2 and 4):
its twist in the body and in the spatial frame, the adjoint that relates them, its generalized
inertia and the matrix ad_V of the Newton–Euler equation.

Twists are ordered (v, omega) as in MLS94; the body frame sits at the centre of mass.

    kind      twist V^b               spatial twist V^s                M^b            Ad_g
    particle  r_dot                   r_dot                            m 1            1
    planar    (R^T p_dot, th_dot)     (p_dot - th_dot J p, th_dot)     diag(m, m, I)  (*)
    rigid     (R^T p_dot, omega_b)    (p_dot - omega_s x p, omega_s)   diag(m 1, I)   (**)

    (*) [[R, -J p], [0, 1]],   (**) [[R, hat(p) R], [0, R]],
    V^s = Ad_g V^b,   M^s = Ad_g^-T M^b Ad_g^-1,   T = 1/2 V^b.M^b V^b = 1/2 V^s.M^s V^s,

J = [[0, -1], [1, 0]] the planar quarter turn, and

    ad_V = [[hat(omega), hat(v)], [0, hat(omega)]]  (3-D),  [[omega J, -J v], [0, 0]]  (planar),  0.

>>> import lagrangian as lg, sympy as sp
>>> theta, m, l, I = sp.symbols("theta m l I")
>>> rod = lg.RigidBody("rod", m, I, (l * sp.sin(theta), -l * sp.cos(theta)), theta)
>>> pendulum = lg.System(coordinates=[theta], parameters=[m, l, I], rigid_bodies=[rod])
>>> (frame,) = body_frames(pendulum)
>>> frame.twist.T
Matrix([[l*theta_dot, 0, theta_dot]])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.derivation.trig import combine_trig_matrix, combine_trig_sympy
from lagrangian.model import System
from lagrangian.model.elements import Particle, RigidBody
from lagrangian.model.inertia import generalized_inertia
from lagrangian.model.rotation import hat
from lagrangian.model.twist import adjoint, adjoint_inverse, body_twist, spatial_twist
from lagrangian.symbolic.symbols import t, time_derivative, velocity

#: The planar quarter turn J = R(pi/2): J v = z_hat x v, the planar cross product.
QUARTER_TURN = sp.ImmutableMatrix([[0, -1], [1, 0]])


@dataclass(frozen=True)
class BodyFrame:
    """One body (or particle) as a frame at its centre of mass.

    Attributes
    ----------
    name, kind:
        The element's name; ``"particle"``, ``"planar"`` or ``"rigid"`` (a 3-D body).
    mass, position, rotation:
        m, the centre p(q, t) and R(q, t) (body axes -> world axes; 1 for a particle).
    twist, spatial_twist:
        V^b and V^s in q, q_dot and t (table in the module docstring).
    inertia, spatial_inertia:
        M^b and M^s = Ad^-T M^b Ad^-1.
    adjoint:
        Ad_g, with V^s = Ad_g V^b and F^b = Ad_g^T F^s for wrenches.
    jacobian, spatial_jacobian:
        dV^b/dq_dot and dV^s/dq_dot, the twist Jacobians (one column per coordinate).
    """

    name: str
    kind: str
    mass: sp.Expr
    position: tuple[sp.Expr, ...]
    rotation: sp.ImmutableMatrix
    twist: sp.ImmutableMatrix
    spatial_twist: sp.ImmutableMatrix
    inertia: sp.ImmutableMatrix
    spatial_inertia: sp.ImmutableMatrix
    adjoint: sp.ImmutableMatrix
    jacobian: sp.ImmutableMatrix
    spatial_jacobian: sp.ImmutableMatrix


def ad_twist(kind: str, twist: sp.MatrixBase) -> sp.ImmutableMatrix:
    """ad_V of a twist V = (v, omega) (the Newton-Euler equation, MLS94 ch. 4):
    [[hat(omega), hat(v)], [0, hat(omega)]] in 3-D, [[omega J, -J v], [0, 0]] in the plane,
    and the zero matrix for a particle (no rotation).

    >>> ad_twist("planar", sp.Matrix([1, 0, 2]))
    Matrix([
    [0, -2,  0],
    [2,  0, -1],
    [0,  0,  0]])
    """
    V = sp.Matrix(twist)
    if kind == "particle":
        return sp.ImmutableMatrix(sp.zeros(V.rows, V.rows))
    if kind == "planar":
        v, omega = V[:2, 0], V[2]
        top = (QUARTER_TURN * omega).row_join(-QUARTER_TURN * v)
        return sp.ImmutableMatrix(top.col_join(sp.zeros(1, 3)))
    v, omega = V[:3, 0], V[3:, 0]
    top = hat(omega).row_join(hat(v))
    return sp.ImmutableMatrix(top.col_join(sp.zeros(3).row_join(hat(omega))))


def point_wrench(kind: str, point: Sequence[Any], force: Sequence[Any]) -> sp.ImmutableMatrix:
    """The spatial wrench F^s = (f, r x f) of a force f (world axes) applied at the point r:
    its moment about the world origin (the scalar r_x f_y - r_y f_x in the plane); a
    particle's wrench is the force itself.

    >>> point_wrench("planar", [1, 0], [0, 2]).T
    Matrix([[0, 2, 2]])
    """
    f, r = sp.Matrix(list(force)), sp.Matrix(list(point))
    if kind == "particle":
        return sp.ImmutableMatrix(f)
    if kind == "planar":
        return sp.ImmutableMatrix([f[0], f[1], r[0] * f[1] - r[1] * f[0]])
    return sp.ImmutableMatrix(f.col_join(r.cross(f)))


def body_frames(system: System) -> tuple[BodyFrame, ...]:
    """The frame of every particle, then every rigid body, of ``system`` (in their order)."""
    q = tuple(system.coordinates)
    particles = [_particle_frame(p, q) for p in system.particles]
    return (*particles, *[_body_frame(b, q) for b in system.rigid_bodies])


def fixed_in(frame: BodyFrame, point: Sequence[Any], coordinates: Sequence[sp.Symbol]) -> bool:
    """True when ``point`` moves with the body: R^T (r - p) has no coordinate and no t."""
    offset = frame.rotation.T * (sp.Matrix(list(point)) - sp.Matrix(list(frame.position)))
    moving = {*coordinates, t}

    def constant(entry: sp.Expr) -> bool:
        value = combine_trig_sympy(entry)  # canonical for trigonometric polynomials
        if value.free_symbols & moving and sp.count_ops(value) <= 200:
            value = sp.simplify(value)  # fractions, square roots
        return not value.free_symbols & moving

    return all(constant(e) for e in offset)


def _jacobians(
    twist: sp.MatrixBase, spatial: sp.MatrixBase, q: Sequence[sp.Symbol]
) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix]:
    rates = [velocity(s) for s in q]
    return (
        sp.ImmutableMatrix(sp.Matrix(twist).jacobian(rates)),
        sp.ImmutableMatrix(sp.Matrix(spatial).jacobian(rates)),
    )


def _frame(
    element: Particle | RigidBody,
    kind: str,
    rotation: sp.MatrixBase,
    inertia: sp.MatrixBase,
    twists: tuple[sp.MatrixBase, sp.MatrixBase],
    adjoints: tuple[sp.MatrixBase, sp.MatrixBase],
    q: Sequence[sp.Symbol],
) -> BodyFrame:
    """A frame from its pieces, with M^s = Ad^-T M^b Ad^-1 and the twist Jacobians."""
    twist, spatial = (combine_trig_matrix(v) for v in twists)
    forward, inverse = adjoints
    spatial_inertia = combine_trig_matrix(sp.Matrix(inverse).T * inertia * inverse)
    return BodyFrame(
        element.name,
        kind,
        element.mass,
        tuple(element.position),
        sp.ImmutableMatrix(rotation),
        twist,
        spatial,
        sp.ImmutableMatrix(inertia),
        spatial_inertia,
        sp.ImmutableMatrix(forward),
        *_jacobians(twist, spatial, q),
    )


def _particle_frame(particle: Particle, q: Sequence[sp.Symbol]) -> BodyFrame:
    d = len(particle.position)
    r_dot = sp.Matrix([time_derivative(x, q) for x in particle.position])
    one = sp.eye(d)
    return _frame(particle, "particle", one, particle.mass * one, (r_dot, r_dot), (one, one), q)


def _body_frame(body: RigidBody, q: Sequence[sp.Symbol]) -> BodyFrame:
    if not body.planar:
        R, p = body.orientation.matrix, body.position  # type: ignore[union-attr]
        inertia = generalized_inertia(body.mass, body.inertia_tensor)
        twists = (body_twist(body.orientation, p, q), spatial_twist(body.orientation, p, q))
        adjoints = (adjoint(body.orientation, p), adjoint_inverse(body.orientation, p))
        return _frame(body, "rigid", R, inertia, twists, adjoints, q)
    angle, p = body.angle, sp.Matrix(list(body.position))
    R = sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])
    p_dot, rate = p.applyfunc(lambda e: time_derivative(e, q)), time_derivative(angle, q)
    twist = (R.T * p_dot).col_join(sp.Matrix([rate]))
    spatial = (p_dot - rate * QUARTER_TURN * p).col_join(sp.Matrix([rate]))
    forward = R.row_join(-QUARTER_TURN * p).col_join(sp.Matrix([[0, 0, 1]]))
    inverse = R.T.row_join(R.T * QUARTER_TURN * p).col_join(sp.Matrix([[0, 0, 1]]))
    inertia = sp.diag(body.mass, body.mass, body.inertia)
    return _frame(body, "planar", R, inertia, (twist, spatial), (forward, inverse), q)
