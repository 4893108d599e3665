"""Gather a System's contributions into backend expressions: the explicit kinetic energy,
the inertial points (particles and body centres, with planar bodies' angles), the rotations of
3-D bodies, V, U, F and the applied generalized forces.

Everything here is a sum of the user's pieces; no equation is formed yet.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.derivation.backend import Backend, to_backend, vector_to_backend
from lagrangian.derivation.trig import combine_trig, size
from lagrangian.model import (
    Capacitor,
    Inductor,
    MutualInductance,
    Resistor,
    System,
    Torque,
    VoltageSource,
)
from lagrangian.model.rotation import (
    Orientation,
    angular_velocity_terms,
    spatial_angular_velocity,
)
from lagrangian.symbolic.native import to_symengine_sharing
from lagrangian.symbolic.symbols import acceleration, t, velocity


@dataclass(frozen=True)
class InertialPoint:
    """A point mass (or a body's centre of mass) at ``position``; for a planar body also the
    inertia and angle (``inertia`` 0 and ``angle`` None for a particle)."""

    mass: Backend
    position: tuple[Backend, ...]
    inertia: Backend
    angle: Backend | None
    #: A 3-D body's orientation (None for a particle or a planar body): the chain of
    #: rotations its centre may hang from (:func:`frames_carried`, read only where M is
    #: built from the Jacobian rows turned into those frames).
    orientation: Orientation | None = None


@dataclass(frozen=True)
class Rotation:
    """The rotation of a 3-D body: inertia I about its centre in body axes and the body
    angular velocity omega_b = vee(R^T R_dot) (linear in q_dot), so T_rot = 1/2 omega_b^T I
    omega_b (Murray, Li & Sastry 1994, ch. 4)."""

    inertia: tuple[tuple[Backend, ...], ...]
    angular_velocity: tuple[Backend, ...]


@dataclass(frozen=True)
class Assembly:
    """A System in backend form, contributions summed."""

    q: tuple[Backend, ...]
    q_dot: tuple[Backend, ...]
    q_ddot: tuple[Backend, ...]
    t: Backend
    explicit_kinetic: Backend  # T given as an expression (user T, velocity part of L, inductors)
    points: tuple[InertialPoint, ...]
    potential: Backend
    velocity_potential: Backend
    dissipation: Backend
    applied: tuple[Backend, ...]  # generalized forces Q_j not from V, U or F
    rotations: tuple[Rotation, ...] = ()  # 3-D bodies (their centres are among the points)

    def time_derivative(self, expr: Backend) -> Backend:
        """d/dt by the chain rule: sum(de/dq q_dot + de/dq_dot q_ddot) + de/dt."""
        result = expr.diff(self.t)
        for q, qd, qdd in zip(self.q, self.q_dot, self.q_ddot):
            result += expr.diff(q) * qd + expr.diff(qd) * qdd
        return result

    def point_velocity(self, position: tuple[Backend, ...]) -> list[Backend]:
        return [self.time_derivative(x) for x in position]


#: The unit vectors of the coordinate axes -> their index: a rotation's axis is looked up
#: whole (reading a SymPy matrix entry by entry and comparing each with 0 took most of
#: :func:`frames_carried`'s time).
_COORDINATE_AXES = {sp.ImmutableMatrix(sp.eye(3)[:, i]): i for i in range(3)}


def frames_carried(
    orientation: Orientation | None, position: tuple[Backend, ...], q: tuple[Backend, ...]
) -> tuple[tuple[int, Backend], ...]:
    """The leading rotations of ``orientation``'s chain whose angles are coordinates the
    centre at ``position`` moves with: the frames it hangs from (a bicycle's fork, from the
    heading, the lean and the rear frame's pitch).  The chain ends at the first rotation
    the centre does not move with (a wheel's spin about its axle, a constant tilt such as
    the steer axis'), or about an axis other than a coordinate axis.

    >>> import sympy as sp
    >>> from lagrangian.model.rotation import rotation_sequence
    >>> yaw, lean, spin = sp.symbols("yaw lean spin")
    >>> wheel = rotation_sequence([("z", yaw), ("x", lean), ("y", spin)])
    >>> q = tuple(to_backend(s) for s in (yaw, lean, spin))
    >>> r = se.Symbol("r")
    >>> frames_carried(wheel, (r * se.cos(q[0]), r * se.sin(q[0]), r * se.cos(q[1])), q)
    ((2, yaw), (0, lean))
    """
    if orientation is None:
        return ()
    moving = set().union(*(x.free_symbols for x in position)) & set(q)
    carried = []
    for unit, angle in orientation.factors():
        axis = _COORDINATE_AXES.get(unit)
        if axis is None:
            axis = _axis_equal(unit)
        if axis is None:
            break
        angle = to_backend(angle)
        if angle not in moving:
            break
        carried.append((axis, angle))
    return tuple(carried)


def _axis_equal(unit: Any) -> int | None:
    """The coordinate axis ``unit`` equals entry by entry, where the whole was not found: an
    axis given in floats (SymPy before 1.13 takes Float 1.0 as equal to 1 but hashes it
    apart, so the look-up misses what the comparison finds)."""
    axes = [i for i, e in enumerate(unit) if e != 0]
    return axes[0] if len(axes) == 1 and unit[axes[0]] == 1 else None


def _position(position: Any, shared: dict[Any, Backend]) -> tuple[Backend, ...]:
    """A position in the backend, each distinct SymPy subexpression converted once for all
    the positions that share ``shared``: a chain's positions repeat the terms of the points
    above them (link k's in every point below it), and a 3-D body's repeat the products of
    the sines and cosines of its frames (a bicycle's fork and front wheel: 3.3 ms converted
    term by term, 0.5 ms shared)."""
    return tuple(to_symengine_sharing(x, shared) for x in position)


def _points(system: System, shared: dict[Any, Backend]) -> dict[str, tuple[Backend, ...]]:
    return {name: _position(r, shared) for name, r in system.points().items()}


def _resolve(ref: object, points: dict[str, tuple[Backend, ...]]) -> tuple[Backend, ...]:
    return points[ref] if isinstance(ref, str) else tuple(vector_to_backend(ref))  # type: ignore[arg-type]


def _gravity_potential(system: System, points: tuple[InertialPoint, ...]) -> Backend:
    if system.gravity is None:
        return se.Integer(0)
    return gravity_potential(vector_to_backend(system.gravity), points)


def gravity_potential(gravity: list[Backend], points: tuple[InertialPoint, ...]) -> Backend:
    """V = -sum_p m_p g . r_p of a uniform gravity g over the inertial points (a potential
    that is the gravity's alone is equal to this very expression)."""
    return -se.Add(
        *[p.mass * se.Add(*[g * x for g, x in zip(gravity, p.position)]) for p in points]
    )


def _spring_potential(system: System, asm_points: dict[str, tuple[Backend, ...]]) -> Backend:
    total = se.Integer(0)
    for spring in system.springs:
        a, b = (_resolve(ref, asm_points) for ref in spring.between)
        k, rest = to_backend(spring.stiffness), to_backend(spring.rest_length)
        delta = [xb - xa for xa, xb in zip(a, b)]
        if len(delta) == 1:
            total += k * (delta[0] - rest) ** 2 / 2
        elif rest == 0:
            total += k * squared_length(delta) / 2
        else:
            total += k * (se.sqrt(squared_length(delta)) - rest) ** 2 / 2
    return total


def squared_length(delta: list[Backend]) -> Backend:
    """|delta|^2 as a textbook writes it: expanded and reduced by sin^2 + cos^2 = 1 when
    that is shorter, so a pendulum spring's length is sqrt(r^2), not
    sqrt(r^2 sin^2(theta) + r^2 cos^2(theta)).

    >>> r, theta = se.symbols("r theta")
    >>> squared_length([r * se.sin(theta), -r * se.cos(theta)])
    r**2
    """
    plain = se.Add(*[d**2 for d in delta])
    reduced = combine_trig(se.expand(plain))
    return reduced if size(reduced) < size(plain) else plain


def _applied_forces(
    system: System, asm: Assembly, named: dict[str, tuple[Backend, ...]]
) -> list[Backend]:
    """Q_j = user Q_j + sum F . dr/dq_j (virtual work) + torques + voltage sources."""
    n = len(asm.q)
    applied = [se.Integer(0)] * n
    torques = [_torque_forces(system, torque) for torque in system.torques]
    for j, q in enumerate(asm.q):
        symbol = system.coordinates[j]
        if symbol in system.generalized_forces:
            applied[j] += to_backend(system.generalized_forces[symbol])
        for force in system.forces:
            r = _resolve(force.at, named)
            f = vector_to_backend(force.force)
            applied[j] += se.Add(*[fi * x.diff(q) for fi, x in zip(f, r)])
        for forces in torques:
            applied[j] += forces[j]
        for element in system.circuit:
            if isinstance(element, VoltageSource) and element.coordinate == symbol:
                applied[j] += to_backend(element.voltage)
    return applied


def _torque_forces(system: System, torque: Torque) -> list[Backend]:
    """Q_j of a torque: tau d(angle)/dq_j (planar), tau . d(omega_s)/d(q_dot_j) (3-D body,
    tau in world axes: the virtual rotation is vee(dR R^T) = sum_j d(omega_s)/d(q_dot_j) dq_j)."""
    body = next(b for b in system.rigid_bodies if b.name == torque.body)
    if body.planar:
        tau, angle = to_backend(torque.torque), to_backend(body.angle)
        return [tau * angle.diff(to_backend(q)) for q in system.coordinates]
    omega = spatial_angular_velocity(body.orientation, system.coordinates)
    return [
        to_backend(sp.Add(*[tau * w.diff(velocity(q)) for tau, w in zip(torque.torque, omega)]))
        for q in system.coordinates
    ]


def _rotations(system: System) -> tuple[Rotation, ...]:
    rotations = []
    for body in system.rigid_bodies:
        if body.planar:
            continue
        # composed in the backend when it can be (the same as body_angular_velocity's)
        omega = angular_velocity_terms(body.orientation, system.coordinates)
        inertia = tuple(tuple(to_backend(e) for e in row) for row in body.inertia_tensor.tolist())
        rotations.append(Rotation(inertia, omega))
    return tuple(rotations)


def _circuit_energies(system: System) -> tuple[Backend, Backend, Backend]:
    """(magnetic energy, electric energy, resistive dissipation) of the circuit elements."""
    magnetic, electric, resistive = se.Integer(0), se.Integer(0), se.Integer(0)
    for e in system.circuit:
        if isinstance(e, Inductor):
            magnetic += to_backend(e.inductance) * to_backend(e.current) ** 2 / 2
        elif isinstance(e, MutualInductance):
            i_a, i_b = vector_to_backend(e.currents)
            magnetic += to_backend(e.inductance) * i_a * i_b
        elif isinstance(e, Capacitor):
            electric += to_backend(e.charge) ** 2 / (2 * to_backend(e.capacitance))
        elif isinstance(e, Resistor):
            resistive += to_backend(e.resistance) * to_backend(e.current) ** 2 / 2
    return magnetic, electric, resistive


def _damper_dissipation(
    system: System, asm: Assembly, named: dict[str, tuple[Backend, ...]]
) -> Backend:
    total = se.Integer(0)
    for damper in system.dampers:
        a, b = (_resolve(ref, named) for ref in damper.between)
        c = to_backend(damper.coefficient)
        delta = [xb - xa for xa, xb in zip(a, b)]
        rate = [asm.time_derivative(d) for d in delta]
        if len(delta) == 1:
            total += c * rate[0] ** 2 / 2
        else:  # rate of change of the distance: (delta . delta_dot) / |delta|
            dot = se.Add(*[d * r for d, r in zip(delta, rate)])
            total += c * dot**2 / (2 * squared_length(delta))
    return total


def assemble(system: System) -> Assembly:
    """The backend form of ``system`` with all contributions summed."""
    q = tuple(to_backend(s) for s in system.coordinates)
    q_dot = tuple(to_backend(velocity(s)) for s in system.coordinates)
    q_ddot = tuple(to_backend(acceleration(s)) for s in system.coordinates)
    lagrangian = to_backend(system.lagrangian)
    static_part = lagrangian.subs({v: 0 for v in q_dot})  # L(q, 0, t) acts as -V
    magnetic, electric, resistive = _circuit_energies(system)
    shared: dict[Any, Backend] = {}  # the positions' subexpressions, each converted once
    points = tuple(
        InertialPoint(to_backend(p.mass), _position(p.position, shared), se.Integer(0), None)
        for p in system.particles
    ) + tuple(
        InertialPoint(
            to_backend(b.mass),
            _position(b.position, shared),
            to_backend(b.inertia) if b.planar else se.Integer(0),
            to_backend(b.angle) if b.planar else None,
            None if b.planar else b.orientation,
        )
        for b in system.rigid_bodies
    )
    named = _points(system, shared)
    base = Assembly(
        q,
        q_dot,
        q_ddot,
        to_backend(t),
        explicit_kinetic=to_backend(system.kinetic) + (lagrangian - static_part) + magnetic,
        points=points,
        potential=to_backend(system.potential)
        - static_part
        + electric
        + _gravity_potential(system, points)
        + _spring_potential(system, named),
        velocity_potential=to_backend(system.velocity_potential),
        dissipation=to_backend(system.dissipation) + resistive,
        applied=(),
        rotations=_rotations(system),
    )
    return Assembly(
        **{
            **base.__dict__,
            "dissipation": base.dissipation + _damper_dissipation(system, base, named),
            "applied": tuple(_applied_forces(system, base, named)),
        }
    )
