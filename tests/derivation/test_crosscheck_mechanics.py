"""Cross-check lagrangian's equations of motion against sympy.physics.mechanics.

Every system is built twice, independently: once with the lagrangian Python API and once with
``sympy.physics.mechanics`` (LagrangesMethod or KanesMethod, bodies, loads and frames of its
own).  The two must give the same motion:

    lagrangian:  M q_ddot = forcing           (plain symbols theta, theta_dot, theta_ddot)
    mechanics:   M_ref q'' = forcing_ref      (dynamicsymbols, converted to the plain symbols)

compared as accelerations M^-1 forcing numerically at random states and parameters, and
symbolically where that is cheap.  For LagrangesMethod models the residuals are compared too:
both libraries write d/dt dL/dq_dot - dL/dq - Q (+ dF/dq_dot, which LagrangesMethod receives
as the force -dF/dq_dot in its force list).

The second half checks properties of the matrix form on the same systems (DESIGN.md, seed 001):
equations = M q_ddot - forcing, C(q, q_dot) q_dot = coriolis, dM/dt - 2C skew-symmetric, and
forcing = Q + dissipation + velocity-potential forces - coriolis - time terms - G.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg

TIME = me.dynamicsymbols._t
N_STATES = 3
RTOL = 1e-9


# -- the reference side: sympy.physics.mechanics in plain symbols ------------------------------


@dataclass(frozen=True)
class Reference:
    """What sympy.physics.mechanics says, in lagrangian's plain symbols."""

    method: str
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    residuals: sp.Matrix | None = None  # LagrangesMethod's form_lagranges_equations()


@dataclass(frozen=True)
class Case:
    """One system described both ways."""

    system: lg.System
    reference: Reference


def _plain(
    expr: sp.Basic, coordinates: Sequence[sp.Function], speeds: Sequence[sp.Function] = ()
) -> sp.Basic:
    """q(t)'' -> q_ddot, q(t)' -> q_dot, q(t) -> q; a speed u_j = q_j' -> q_dot, u_j' -> q_ddot."""
    swap: dict[sp.Basic, sp.Basic] = {}
    for j, q in enumerate(coordinates):
        name = q.func.__name__
        q_dot, q_ddot = sp.Symbol(name + "_dot"), sp.Symbol(name + "_ddot")
        swap[q.diff(TIME, 2)] = q_ddot
        swap[q.diff(TIME)] = q_dot
        swap[q] = sp.Symbol(name)
        if speeds:
            swap[speeds[j].diff(TIME)] = q_ddot
            swap[speeds[j]] = q_dot
    # xreplace works from the top of the tree, so q(t)'' is replaced before q(t) inside it.
    return expr.xreplace(swap)


def lagranges_reference(
    lagrangian: sp.Expr,
    coordinates: Sequence[sp.Function],
    forcelist: Sequence[tuple] = (),
    frame: me.ReferenceFrame | None = None,
) -> Reference:
    """LagrangesMethod: residuals d/dt dL/dqd - dL/dq - Q, mass matrix and forcing."""
    method = me.LagrangesMethod(
        lagrangian, list(coordinates), forcelist=list(forcelist) or None, frame=frame
    )
    residuals = method.form_lagranges_equations()
    return Reference(
        method="LagrangesMethod",
        mass_matrix=_plain(method.mass_matrix, coordinates),
        forcing=_plain(method.forcing, coordinates),
        residuals=_plain(residuals, coordinates),
    )


def kanes_reference(
    frame: me.ReferenceFrame,
    coordinates: Sequence[sp.Function],
    bodies: Sequence,
    loads: Sequence[tuple],
) -> Reference:
    """KanesMethod with generalized speeds u_j = q_j' (so its equations are Lagrange's)."""
    speeds = [me.dynamicsymbols(q.func.__name__ + "_u") for q in coordinates]
    kinematics = [q.diff(TIME) - u for q, u in zip(coordinates, speeds, strict=True)]
    method = me.KanesMethod(frame, q_ind=list(coordinates), u_ind=speeds, kd_eqs=kinematics)
    method.kanes_equations(list(bodies), list(loads))
    return Reference(
        method="KanesMethod",
        mass_matrix=_plain(method.mass_matrix, coordinates, speeds),
        forcing=_plain(method.forcing, coordinates, speeds),
    )


def _point(
    base: me.Point, frame: me.ReferenceFrame, name: str, offset: Sequence[sp.Expr]
) -> me.Point:
    """The point base + offset (components along frame.x, .y, .z), with its velocity in frame
    (base's velocity plus the rate of the offset, frame being the inertial frame)."""
    axes = (frame.x, frame.y, frame.z)
    relative = sum((c * axis for c, axis in zip(offset, axes, strict=False)), me.Vector(0))
    point = base.locatenew(name, relative)
    point.set_vel(frame, base.vel(frame) + relative.dt(frame))
    return point


def _inertial_frame() -> tuple[me.ReferenceFrame, me.Point]:
    frame, origin = me.ReferenceFrame("N"), me.Point("O")
    origin.set_vel(frame, 0)
    return frame, origin


# -- the systems ---------------------------------------------------------------------------------


def double_pendulum() -> Case:
    """Two bobs on massless rods, absolute angles from the downward vertical."""
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    th1, th2 = lg.coordinates("theta1 theta2")
    r1 = (l1 * sp.sin(th1), -l1 * sp.cos(th1))
    r2 = (r1[0] + l2 * sp.sin(th2), r1[1] - l2 * sp.cos(th2))
    system = lg.System(
        coordinates=[th1, th2],
        parameters=[m1, m2, l1, l2, g],
        particles=[lg.Particle("bob1", m1, r1), lg.Particle("bob2", m2, r2)],
        gravity=(0, -g),
    )

    q1, q2 = me.dynamicsymbols("theta1 theta2")
    frame, origin = _inertial_frame()
    p1 = _point(origin, frame, "P1", (l1 * sp.sin(q1), -l1 * sp.cos(q1)))
    p2 = _point(p1, frame, "P2", (l2 * sp.sin(q2), -l2 * sp.cos(q2)))
    bob1, bob2 = me.Particle("bob1", p1, m1), me.Particle("bob2", p2, m2)
    bob1.potential_energy = m1 * g * p1.pos_from(origin).dot(frame.y)
    bob2.potential_energy = m2 * g * p2.pos_from(origin).dot(frame.y)
    return Case(system, lagranges_reference(me.Lagrangian(frame, bob1, bob2), [q1, q2]))


def spherical_pendulum() -> Case:
    """A bob on a rod of length l from a fixed pivot: polar angle theta from -z, azimuth phi."""
    m, length, g = sp.symbols("m l g")
    th, ph = lg.coordinates("theta phi")
    r = (length * sp.sin(th) * sp.cos(ph), length * sp.sin(th) * sp.sin(ph), -length * sp.cos(th))
    system = lg.System(
        coordinates=[th, ph],
        parameters=[m, length, g],
        particles=[lg.Particle("bob", m, r)],
        gravity=(0, 0, -g),
    )

    qt, qp = me.dynamicsymbols("theta phi")
    frame, origin = _inertial_frame()
    # Built by rotations rather than by components: A about z by phi, B about -A.y by theta,
    # so the bob at -l B.z is at l (sin theta cos phi, sin theta sin phi, -cos theta).
    a_frame, b_frame = me.ReferenceFrame("A"), me.ReferenceFrame("B")
    a_frame.orient_axis(frame, frame.z, qp)
    b_frame.orient_axis(a_frame, -a_frame.y, qt)
    bob_point = origin.locatenew("P", -length * b_frame.z)
    bob_point.set_vel(frame, bob_point.pos_from(origin).dt(frame))
    bob = me.Particle("bob", bob_point, m)
    bob.potential_energy = m * g * bob_point.pos_from(origin).dot(frame.z)
    return Case(system, lagranges_reference(me.Lagrangian(frame, bob), [qt, qp]))


def dumbbell() -> Case:
    """Seed 003: m1 at (x1, y1), m2 at (x1 + h cos theta, y1 + h sin theta), forces f1, f2."""
    m1, m2, h, g = sp.symbols("m1 m2 h g")
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")
    x1, y1, th = lg.coordinates("x1 y1 theta")
    system = lg.System(
        coordinates=[x1, y1, th],
        parameters=[m1, m2, h, g, f1x, f1y, f2x, f2y],
        particles=[
            lg.Particle("p1", m1, (x1, y1)),
            lg.Particle("p2", m2, (x1 + h * sp.cos(th), y1 + h * sp.sin(th))),
        ],
        gravity=(0, -g),
        forces=[lg.Force(at="p1", force=(f1x, f1y)), lg.Force(at="p2", force=(f2x, f2y))],
    )

    qx, qy, qt = me.dynamicsymbols("x1 y1 theta")
    frame, origin = _inertial_frame()
    body = me.ReferenceFrame("B")
    body.orient_axis(frame, frame.z, qt)
    p1 = _point(origin, frame, "P1", (qx, qy))
    p2 = p1.locatenew("P2", h * body.x)
    p2.v2pt_theory(p1, frame, body)
    loads = [
        (p1, f1x * frame.x + (f1y - m1 * g) * frame.y),
        (p2, f2x * frame.x + (f2y - m2 * g) * frame.y),
    ]
    bodies = [me.Particle("p1", p1, m1), me.Particle("p2", p2, m2)]
    return Case(system, kanes_reference(frame, [qx, qy, qt], bodies, loads))


def moving_pivot_pendulum() -> Case:
    """Rheonomic: the pivot moves as x0 cos(omega t) along x."""
    m, length, g, x0, w = sp.symbols("m l g x0 omega")
    th = sp.Symbol("theta")
    pivot_x = x0 * sp.cos(w * lg.t)
    system = lg.System(
        coordinates=[th],
        parameters=[m, length, g, x0, w],
        particles=[lg.Particle("bob", m, (pivot_x + length * sp.sin(th), -length * sp.cos(th)))],
        gravity=(0, -g),
    )

    q = me.dynamicsymbols("theta")
    frame, origin = _inertial_frame()
    pivot = _point(origin, frame, "A", (x0 * sp.cos(w * TIME), 0))
    bob_point = _point(pivot, frame, "P", (length * sp.sin(q), -length * sp.cos(q)))
    bob = me.Particle("bob", bob_point, m)
    bob.potential_energy = m * g * bob_point.pos_from(origin).dot(frame.y)
    return Case(system, lagranges_reference(me.Lagrangian(frame, bob), [q]))


def planar_spring_with_drag() -> Case:
    """Particle in the plane, spring of rest length l0 to the origin, linear drag (Rayleigh)."""
    m, k, l0, c = sp.symbols("m k l0 c")
    x, y = lg.coordinates("x y")
    x_dot, y_dot = lg.velocity(x), lg.velocity(y)
    system = lg.System(
        coordinates=[x, y],
        parameters=[m, k, l0, c],
        particles=[lg.Particle("p", m, (x, y))],
        springs=[lg.Spring(between=("origin", "p"), stiffness=k, rest_length=l0)],
        dissipation=c * (x_dot**2 + y_dot**2) / 2,
    )

    qx, qy = me.dynamicsymbols("x y")
    frame, origin = _inertial_frame()
    point = _point(origin, frame, "P", (qx, qy))
    particle = me.Particle("p", point, m)
    particle.potential_energy = k * (sp.sqrt(qx**2 + qy**2) - l0) ** 2 / 2
    drag = [(point, -c * point.vel(frame))]
    return Case(
        system,
        lagranges_reference(me.Lagrangian(frame, particle), [qx, qy], forcelist=drag, frame=frame),
    )


def planar_spring_damper_elements() -> Case:
    """Particle in the plane tied to the origin by a Spring and a Damper (forces along the line)."""
    m, k, l0, c = sp.symbols("m k l0 c")
    x, y = lg.coordinates("x y")
    system = lg.System(
        coordinates=[x, y],
        parameters=[m, k, l0, c],
        particles=[lg.Particle("p", m, (x, y))],
        springs=[lg.Spring(between=("origin", "p"), stiffness=k, rest_length=l0)],
        dampers=[lg.Damper(between=("p", "origin"), coefficient=c)],
    )

    qx, qy = me.dynamicsymbols("x y")
    frame, origin = _inertial_frame()
    point = _point(origin, frame, "P", (qx, qy))
    r = point.pos_from(origin)
    length = sp.sqrt(qx**2 + qy**2)
    unit = r / length
    stretch_rate = point.vel(frame).dot(unit)
    load = (point, -k * (length - l0) * unit - c * stretch_rate * unit)
    return Case(system, kanes_reference(frame, [qx, qy], [me.Particle("p", point, m)], [load]))


def mass_spring_damper_chain() -> Case:
    """1-D: wall -k1,c1- m1 -k2,c2- m2, with a drive F0 cos(w t) on m2."""
    m1, m2, k1, k2, a1, a2, c1, c2, f0, w = sp.symbols("m1 m2 k1 k2 a1 a2 c1 c2 F0 w")
    x1, x2 = lg.coordinates("x1 x2")
    system = lg.System(
        coordinates=[x1, x2],
        parameters=[m1, m2, k1, k2, a1, a2, c1, c2, f0, w],
        particles=[lg.Particle("m1", m1, (x1,)), lg.Particle("m2", m2, (x2,))],
        springs=[
            lg.Spring(between=("origin", "m1"), stiffness=k1, rest_length=a1),
            lg.Spring(between=("m1", "m2"), stiffness=k2, rest_length=a2),
        ],
        dampers=[
            lg.Damper(between=("origin", "m1"), coefficient=c1),
            lg.Damper(between=("m1", "m2"), coefficient=c2),
        ],
        generalized_forces={x2: f0 * sp.cos(w * lg.t)},
    )

    q1, q2 = me.dynamicsymbols("x1 x2")
    frame, origin = _inertial_frame()
    p1 = _point(origin, frame, "P1", (q1,))
    p2 = _point(origin, frame, "P2", (q2,))
    wall = -k1 * (q1 - a1) - c1 * q1.diff(TIME)
    link = k2 * (q2 - q1 - a2) + c2 * (q2.diff(TIME) - q1.diff(TIME))  # pulls m1 toward m2
    loads = [(p1, (wall + link) * frame.x), (p2, (-link + f0 * sp.cos(w * TIME)) * frame.x)]
    bodies = [me.Particle("m1", p1, m1), me.Particle("m2", p2, m2)]
    return Case(system, kanes_reference(frame, [q1, q2], bodies, loads))


def _charged_particle_system() -> lg.System:
    """U = qe phi - qe A.v with A = B0/2 (-y, x, 0), phi = -E0 x (B0 along z, E0 along x)."""
    m, qe, b0, e0 = sp.symbols("m q_e B0 E0")
    x, y, z = lg.coordinates("x y z")
    v = (lg.velocity(x), lg.velocity(y), lg.velocity(z))
    a = (-b0 * y / 2, b0 * x / 2, 0)
    phi = -e0 * x
    return lg.System(
        coordinates=[x, y, z],
        parameters=[m, qe, b0, e0],
        particles=[lg.Particle("charge", m, (x, y, z))],
        velocity_potential=qe * phi - qe * sum(ai * vi for ai, vi in zip(a, v, strict=True)),
    )


def charged_particle_lagrangian() -> Case:
    """Against LagrangesMethod with L = m v^2/2 - qe phi + qe A.v written by hand."""
    m, qe, b0, e0 = sp.symbols("m q_e B0 E0")
    qs = me.dynamicsymbols("x y z")
    x, y, _ = qs
    v = [q.diff(TIME) for q in qs]
    vector_potential = (-b0 * y / 2, b0 * x / 2, 0)
    lagrangian = (
        m * sum(vi**2 for vi in v) / 2
        + qe * e0 * x
        + qe * sum(ai * vi for ai, vi in zip(vector_potential, v, strict=True))
    )
    return Case(_charged_particle_system(), lagranges_reference(lagrangian, qs))


def charged_particle_lorentz() -> Case:
    """Against KanesMethod with the Lorentz force qe (E + v x B) as a load."""
    m, qe, b0, e0 = sp.symbols("m q_e B0 E0")
    qs = me.dynamicsymbols("x y z")
    frame, origin = _inertial_frame()
    point = _point(origin, frame, "P", qs)
    lorentz = qe * (e0 * frame.x + point.vel(frame).cross(b0 * frame.z))
    return Case(
        _charged_particle_system(),
        kanes_reference(frame, qs, [me.Particle("charge", point, m)], [(point, lorentz)]),
    )


def compound_pendulum() -> Case:
    """A planar rigid body swinging about a pivot at distance l from its centre, with a torque."""
    m, length, g, inertia, tau = sp.symbols("m l g I tau")
    th = sp.Symbol("theta")
    system = lg.System(
        coordinates=[th],
        parameters=[m, length, g, inertia, tau],
        rigid_bodies=[
            lg.RigidBody("rod", m, inertia, (length * sp.sin(th), -length * sp.cos(th)), th)
        ],
        torques=[lg.Torque(body="rod", torque=tau)],
        gravity=(0, -g),
    )

    q = me.dynamicsymbols("theta")
    frame, origin = _inertial_frame()
    body = me.ReferenceFrame("B")
    body.orient_axis(frame, frame.z, q)
    centre = origin.locatenew("C", -length * body.y)  # body.y points from the centre to the pivot
    centre.v2pt_theory(origin, frame, body)
    rod = me.RigidBody("rod", centre, body, m, (me.inertia(body, 0, 0, inertia), centre))
    rod.potential_energy = m * g * centre.pos_from(origin).dot(frame.y)
    return Case(
        system,
        lagranges_reference(
            me.Lagrangian(frame, rod), [q], forcelist=[(body, tau * frame.z)], frame=frame
        ),
    )


def double_compound_pendulum() -> Case:
    """Two rods hinged end to end (half-lengths a1, a2), absolute angles, vs KanesMethod."""
    m1, m2, a1, a2, i1, i2, g = sp.symbols("m1 m2 a1 a2 I1 I2 g")
    th1, th2 = lg.coordinates("theta1 theta2")
    c1 = (a1 * sp.sin(th1), -a1 * sp.cos(th1))
    c2 = (2 * a1 * sp.sin(th1) + a2 * sp.sin(th2), -2 * a1 * sp.cos(th1) - a2 * sp.cos(th2))
    system = lg.System(
        coordinates=[th1, th2],
        parameters=[m1, m2, a1, a2, i1, i2, g],
        rigid_bodies=[lg.RigidBody("rod1", m1, i1, c1, th1), lg.RigidBody("rod2", m2, i2, c2, th2)],
        gravity=(0, -g),
    )

    q1, q2 = me.dynamicsymbols("theta1 theta2")
    frame, origin = _inertial_frame()
    b1, b2 = me.ReferenceFrame("B1"), me.ReferenceFrame("B2")
    b1.orient_axis(frame, frame.z, q1)
    b2.orient_axis(frame, frame.z, q2)
    centre1 = origin.locatenew("C1", -a1 * b1.y)
    centre1.v2pt_theory(origin, frame, b1)
    hinge = origin.locatenew("H", -2 * a1 * b1.y)
    hinge.v2pt_theory(origin, frame, b1)
    centre2 = hinge.locatenew("C2", -a2 * b2.y)
    centre2.v2pt_theory(hinge, frame, b2)
    rods = [
        me.RigidBody("rod1", centre1, b1, m1, (me.inertia(b1, 0, 0, i1), centre1)),
        me.RigidBody("rod2", centre2, b2, m2, (me.inertia(b2, 0, 0, i2), centre2)),
    ]
    loads = [(centre1, -m1 * g * frame.y), (centre2, -m2 * g * frame.y)]
    return Case(system, kanes_reference(frame, [q1, q2], rods, loads))


def n_link_pendulum(n: int = 3) -> Case:
    """n bobs on massless rods, absolute angles, vs KanesMethod with gravity loads."""
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    thetas = lg.coordinates([f"theta{i + 1}" for i in range(n)])
    particles, x, y = [], sp.Integer(0), sp.Integer(0)
    for i in range(n):
        x, y = x + lengths[i] * sp.sin(thetas[i]), y - lengths[i] * sp.cos(thetas[i])
        particles.append(lg.Particle(f"bob{i + 1}", masses[i], (x, y)))
    system = lg.System(
        coordinates=thetas, parameters=[*masses, *lengths, g], particles=particles, gravity=(0, -g)
    )

    qs = me.dynamicsymbols(f"theta1:{n + 1}")
    frame, origin = _inertial_frame()
    bodies, loads, previous = [], [], origin
    for i in range(n):
        link = me.ReferenceFrame(f"L{i + 1}")
        link.orient_axis(frame, frame.z, qs[i])
        point = previous.locatenew(f"P{i + 1}", -lengths[i] * link.y)
        point.v2pt_theory(previous, frame, link)
        bodies.append(me.Particle(f"bob{i + 1}", point, masses[i]))
        loads.append((point, -masses[i] * g * frame.y))
        previous = point
    return Case(system, kanes_reference(frame, qs, bodies, loads))


CASES: dict[str, Callable[[], Case]] = {
    "double_pendulum": double_pendulum,
    "spherical_pendulum": spherical_pendulum,
    "dumbbell": dumbbell,
    "moving_pivot_pendulum": moving_pivot_pendulum,
    "planar_spring_with_drag": planar_spring_with_drag,
    "planar_spring_damper_elements": planar_spring_damper_elements,
    "mass_spring_damper_chain": mass_spring_damper_chain,
    "charged_particle_lagrangian": charged_particle_lagrangian,
    "charged_particle_lorentz": charged_particle_lorentz,
    "compound_pendulum": compound_pendulum,
    "double_compound_pendulum": double_compound_pendulum,
    "n_link_pendulum_3": n_link_pendulum,
}
#: Accelerations compared symbolically too; the 3-link pendulum takes a few seconds.
SYMBOLIC = [
    pytest.param(name, marks=pytest.mark.slow) if name == "n_link_pendulum_3" else name
    for name in CASES
]
WITH_RESIDUALS = [
    "double_pendulum",
    "spherical_pendulum",
    "moving_pivot_pendulum",
    "planar_spring_with_drag",
    "charged_particle_lagrangian",
    "compound_pendulum",
]


@cache
def case(name: str) -> Case:
    return CASES[name]()


@cache
def derived(name: str) -> lg.EquationsOfMotion:
    return lg.derive(case(name).system)


# -- comparison helpers --------------------------------------------------------------------------


def vanishes(expr: sp.Expr) -> bool:
    """True when expr is identically zero.

    Cheap canonical forms first: the expanded trigonometric polynomial, then the same in
    exponentials (where sin^2 + cos^2 = 1 cancels by term collection); simplify last.
    """
    expr = sp.expand(sp.sympify(expr))
    if expr == 0 or sp.expand(sp.expand_trig(expr)) == 0:
        return True
    return sp.expand(expr.rewrite(sp.exp)) == 0 or sp.simplify(expr) == 0


def _state_symbols(eom: lg.EquationsOfMotion) -> set[sp.Symbol]:
    return {*eom.coordinates, *eom.velocities, *eom.parameters, eom.time}


def random_values(eom: lg.EquationsOfMotion, seed: int) -> dict[sp.Symbol, sp.Float]:
    """Coordinates, velocities, parameters and t drawn from [0.3, 1.7]."""
    rng = random.Random(seed)
    return {
        s: sp.Float(rng.uniform(0.3, 1.7), 30)
        for s in sorted(_state_symbols(eom), key=lambda s: s.name)
    }


def numeric_accelerations(
    mass: sp.Matrix, forcing: sp.Matrix, values: dict[sp.Symbol, sp.Float]
) -> np.ndarray:
    m = np.array(mass.xreplace(values).evalf(30), dtype=float)
    f = np.array(forcing.xreplace(values).evalf(30), dtype=float).reshape(-1)
    return np.linalg.solve(m, f)


# -- cross-checks ----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(CASES))
def test_reference_uses_only_declared_symbols(name: str) -> None:
    """Both sides speak the same plain symbols (no dynamicsymbols left after conversion)."""
    eom, ref = derived(name), case(name).reference
    allowed = _state_symbols(eom)
    for matrix in (eom.mass_matrix, eom.forcing, ref.mass_matrix, ref.forcing):
        assert not matrix.atoms(sp.Derivative, sp.core.function.AppliedUndef)
        assert matrix.free_symbols <= allowed


@pytest.mark.parametrize("name", list(CASES))
def test_accelerations_agree_numerically(name: str) -> None:
    """M^-1 forcing of lagrangian equals sympy.physics.mechanics' at random states."""
    eom, ref = derived(name), case(name).reference
    for seed in range(N_STATES):
        values = random_values(eom, seed)
        ours = numeric_accelerations(eom.mass_matrix, eom.forcing, values)
        theirs = numeric_accelerations(ref.mass_matrix, ref.forcing, values)
        scale = max(1.0, float(np.max(np.abs(theirs))))
        np.testing.assert_allclose(
            ours,
            theirs,
            rtol=RTOL,
            atol=RTOL * scale,
            err_msg=f"{name} vs {ref.method}, state {values}",
        )


@pytest.mark.parametrize("name", SYMBOLIC)
def test_accelerations_agree_symbolically(name: str) -> None:
    """M_ref adj(M) forcing - det(M) forcing_ref = 0 (same accelerations, no fractions)."""
    eom, ref = derived(name), case(name).reference
    mass = sp.Matrix(eom.mass_matrix)
    difference = (
        ref.mass_matrix * mass.adjugate() * sp.Matrix(eom.forcing) - mass.det() * ref.forcing
    )
    assert all(vanishes(e) for e in difference), f"{name}: {difference}"


@pytest.mark.parametrize("name", list(CASES))
def test_mass_matrix_agrees_symbolically(name: str) -> None:
    """Both libraries use u = q_dot, so M = d2T/dq_dot2 itself must agree, entry by entry."""
    eom, ref = derived(name), case(name).reference
    difference = sp.Matrix(eom.mass_matrix) - ref.mass_matrix
    assert all(vanishes(e) for e in difference), f"{name}: {difference}"


@pytest.mark.parametrize("name", WITH_RESIDUALS)
def test_residuals_agree_with_lagranges_method(name: str) -> None:
    """eom.equations = LagrangesMethod's d/dt dL/dqd - dL/dq - forces (same sign)."""
    eom, ref = derived(name), case(name).reference
    assert ref.residuals is not None
    difference = sp.Matrix(eom.equations) - ref.residuals
    assert all(vanishes(e) for e in difference), f"{name}: {difference}"


def test_dumbbell_matches_seed_003() -> None:
    """The three equations worked out by hand in seed 003 (the third one times h)."""
    m1, m2, h, g = sp.symbols("m1 m2 h g")
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")
    th, th_dot = sp.symbols("theta theta_dot")
    x1dd, y1dd, thdd = sp.symbols("x1_ddot y1_ddot theta_ddot")
    s, c = sp.sin(th), sp.cos(th)
    expected = [
        m1 * x1dd + m2 * (x1dd - h * c * th_dot**2 - h * s * thdd) - (f1x + f2x),
        m1 * y1dd + m2 * (y1dd - h * s * th_dot**2 + h * c * thdd) - (f1y + f2y - (m1 + m2) * g),
        h * (m2 * c * y1dd - m2 * s * x1dd + m2 * h * thdd - (-f2x * s + f2y * c - m2 * g * c)),
    ]
    equations = derived("dumbbell").equations
    assert all(vanishes(e - x) for e, x in zip(equations, expected, strict=True)), equations


# -- properties of the matrix form ---------------------------------------------------------------


@pytest.mark.parametrize("name", list(CASES))
def test_equations_are_matrix_form(name: str) -> None:
    """(a) equations = M q_ddot - forcing."""
    eom = derived(name)
    q_ddot = sp.Matrix(eom.accelerations)
    difference = sp.Matrix(eom.equations) - (eom.mass_matrix * q_ddot - eom.forcing)
    assert all(vanishes(e) for e in difference), difference


@pytest.mark.parametrize("name", list(CASES))
def test_coriolis_matrix_times_velocities_is_coriolis(name: str) -> None:
    """(b) C(q, q_dot) q_dot = coriolis."""
    eom = derived(name)
    difference = eom.coriolis_matrix * sp.Matrix(eom.velocities) - eom.coriolis
    assert all(vanishes(e) for e in difference), difference


@pytest.mark.parametrize("name", list(CASES))
def test_mass_matrix_rate_minus_twice_coriolis_is_skew(name: str) -> None:
    """(c) N = dM/dt - 2C is skew-symmetric, dM/dt = sum_l dM/dq_l q_dot_l."""
    eom = derived(name)
    assert not eom.mass_matrix.has(eom.time), "M(q, t): the identity needs dM/dt in full"
    mass_rate = sum(
        (eom.mass_matrix.diff(q) * v for q, v in zip(eom.coordinates, eom.velocities, strict=True)),
        sp.zeros(*eom.mass_matrix.shape),
    )
    n_matrix = mass_rate - 2 * eom.coriolis_matrix
    assert all(vanishes(e) for e in n_matrix + n_matrix.T), n_matrix


@pytest.mark.parametrize("name", list(CASES))
def test_forcing_is_sum_of_its_parts(name: str) -> None:
    """(d) forcing = Q + dissipation + velocity-potential forces - coriolis - time terms - G."""
    eom = derived(name)
    parts = (
        eom.generalized_forces
        + eom.dissipation_forces
        + eom.velocity_potential_forces
        - eom.coriolis
        - eom.time_terms
        - eom.gravity
    )
    assert all(vanishes(e) for e in eom.forcing - parts), eom.forcing - parts


def test_cases_cover_every_contribution() -> None:
    """The systems above exercise each piece of the forcing at least once (guards the suite)."""
    pieces = {
        "generalized_forces": False,
        "dissipation_forces": False,
        "velocity_potential_forces": False,
        "coriolis": False,
        "time_terms": False,
        "gravity": False,
    }
    for name in CASES:
        eom = derived(name)
        for piece in pieces:
            pieces[piece] |= any(e != 0 for e in getattr(eom, piece))
    assert all(pieces.values()), pieces
