"""The kinetic energy in matrix form: T = 1/2 q_dot^T M q_dot + T1 + T0 (or a general T).

For particles and bodies the mass matrix is built from Jacobians, M = sum m J^T J
(+ I g^T g for a planar body's angle, + J_w^T I J_w for a 3-D body whose body angular velocity
is omega_b = J_w q_dot + omega_t), so T is never expanded as a whole; trigonometric products
are combined entry by entry (:mod:`lagrangian.derivation.trig`).  The Coriolis/centripetal vector
C(q, q_dot) q_dot comes from the Christoffel symbols of M:

    (C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l,

computed as d(M q_dot)/dq . q_dot - grad_q(1/2 q_dot^T M q_dot).  The rest of
d/dt dT/dq_dot - dT/dq (explicit time dependence, terms of degree 0 and 1 in the velocities)
is kept apart as the time terms.
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from lagrangian.derivation.assemble import Assembly, Rotation
from lagrangian.derivation.backend import Backend
from lagrangian.derivation.trig import combine_trig
from lagrangian.model.probe import depends_on

Matrix = list[list[Backend]]


@dataclass(frozen=True)
class KineticForm:
    """M(q, t) (or M(q, q_dot, t) for a T that is not quadratic), C q_dot, time terms and T."""

    mass_matrix: Matrix
    coriolis: list[Backend]
    time_terms: list[Backend]
    kinetic_energy: Backend
    quadratic: bool


def _hessian(expr: Backend, symbols: tuple[Backend, ...]) -> Matrix:
    first = [expr.diff(s) for s in symbols]
    return [[first[i].diff(s) for s in symbols] for i in range(len(symbols))]


def _point_terms(asm: Assembly) -> tuple[Matrix, Backend]:
    """sum m J^T J (+ I g^T g) and the kinetic terms of degree 0 and 1 in the velocities."""
    n = len(asm.q)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    low_degree = se.Integer(0)
    combined: dict[Backend, Backend] = {}  # the same column pairs recur for every point below
    for point in asm.points:
        columns = [(point.mass, point.position)]
        if point.angle is not None and point.inertia != 0:
            columns.append((point.inertia, (point.angle,)))
        for weight, coordinates in columns:
            jac = [[x.diff(q) for q in asm.q] for x in coordinates]
            drift = [x.diff(asm.t) for x in coordinates]
            for j in range(n):
                for k in range(j, n):
                    term = se.Add(*[row[j] * row[k] for row in jac])
                    if term != 0:
                        if term not in combined:
                            combined[term] = combine_trig(term)
                        mass[j][k] += weight * combined[term]
            if any(d != 0 for d in drift):
                moving = [se.Add(*[row[k] * asm.q_dot[k] for k in range(n)]) for row in jac]
                low_degree += weight * se.Add(*[v * d for v, d in zip(moving, drift)])
                low_degree += weight * se.Add(*[d**2 for d in drift]) / 2
    for rotation in asm.rotations:
        low_degree += _rotation_terms(rotation, asm, mass, combined)
    return mass, low_degree


def _rotation_terms(
    rotation: Rotation, asm: Assembly, mass: Matrix, combined: dict[Backend, Backend]
) -> Backend:
    """Add J_w^T I J_w to the upper triangle of ``mass`` (omega_b = J_w q_dot + d, I symmetric)
    and return T's terms of degree 0 and 1: (J_w q_dot)^T I d + 1/2 d^T I d."""
    n, inertia = len(asm.q), rotation.inertia
    at_rest = {v: 0 for v in asm.q_dot}
    jac = [[w.diff(v) for v in asm.q_dot] for w in rotation.angular_velocity]
    drift = [w.subs(at_rest) for w in rotation.angular_velocity]
    for a in range(3):
        for b in range(a, 3):
            if inertia[a][b] == 0:
                continue
            for j in range(n):
                for k in range(j, n):
                    # 1/2 I_ab w_a w_b summed over a, b: I_ab (J_aj J_bk + J_bj J_ak) for a < b
                    term = jac[a][j] * jac[b][k] + (jac[b][j] * jac[a][k] if a != b else 0)
                    if term != 0:
                        if term not in combined:
                            combined[term] = combine_trig(term)
                        mass[j][k] += inertia[a][b] * combined[term]
    if all(d == 0 for d in drift):
        return se.Integer(0)
    moving = [se.Add(*[row[k] * asm.q_dot[k] for k in range(n)]) for row in jac]
    return se.Add(
        *[
            inertia[a][b] * (moving[a] * drift[b] + drift[a] * drift[b] / 2)
            for a in range(3)
            for b in range(3)
        ]
    )


def _linear_part(expr: Backend, asm: Assembly) -> Backend:
    """Terms of degree 0 and 1 in the velocities of an expression at most quadratic in them."""
    at_rest = {v: 0 for v in asm.q_dot}
    return expr.subs(at_rest) + se.Add(*[v * expr.diff(v).subs(at_rest) for v in asm.q_dot])


def _coriolis(mass: Matrix, asm: Assembly) -> list[Backend]:
    n = len(asm.q)
    momentum = [se.Add(*[mass[j][k] * asm.q_dot[k] for k in range(n)]) for j in range(n)]
    twice_t = se.Add(*[asm.q_dot[j] * momentum[j] for j in range(n)])
    result = []
    for j in range(n):
        rate = se.Add(*[momentum[j].diff(q) * qd for q, qd in zip(asm.q, asm.q_dot)])
        result.append(se.expand(rate - twice_t.diff(asm.q[j]) / 2))  # tidied by the caller
    return result


def kinetic_form(asm: Assembly) -> KineticForm:
    """Mass matrix, Coriolis vector, time terms and T of an assembled system."""
    n = len(asm.q)
    explicit = _hessian(asm.explicit_kinetic, asm.q_dot)
    point_mass, point_low = _point_terms(asm)
    quadratic = not any(depends_on(e, asm.q_dot) for row in explicit for e in row)
    if not quadratic:
        return _general_form(asm)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            mass[j][k] = combine_trig(explicit[j][k] + point_mass[j][k])
            mass[k][j] = mass[j][k]
    low = _linear_part(asm.explicit_kinetic, asm) + point_low
    quadratic_t = se.Add(
        *[mass[j][k] * asm.q_dot[j] * asm.q_dot[k] / 2 for j in range(n) for k in range(n)]
    )
    time_terms = []
    for j in range(n):
        explicit_time = se.Add(*[mass[j][k].diff(asm.t) * asm.q_dot[k] for k in range(n)])
        low_terms = asm.time_derivative(low.diff(asm.q_dot[j])) - low.diff(asm.q[j])
        time_terms.append(se.expand(explicit_time + low_terms))
    return KineticForm(mass, _coriolis(mass, asm), time_terms, quadratic_t + low, True)


def _general_form(asm: Assembly) -> KineticForm:
    """T not quadratic in the velocities (e.g. L = m^2 x_dot^4/12 + ...): M = d2T/dq_dot2
    depends on the velocities, and C q_dot is sum_k d2T/dq_dot_j dq_k q_dot_k - dT/dq_j."""
    kinetic = asm.explicit_kinetic
    for point in asm.points:
        velocity = asm.point_velocity(point.position)
        kinetic += point.mass * se.Add(*[v**2 for v in velocity]) / 2
        if point.angle is not None:
            kinetic += point.inertia * asm.time_derivative(point.angle) ** 2 / 2
    for rotation in asm.rotations:
        omega, inertia = rotation.angular_velocity, rotation.inertia
        kinetic += (
            se.Add(*[inertia[a][b] * omega[a] * omega[b] for a in range(3) for b in range(3)]) / 2
        )
    mass = [[se.expand(e) for e in row] for row in _hessian(kinetic, asm.q_dot)]
    momentum = [kinetic.diff(v) for v in asm.q_dot]
    coriolis = [
        se.expand(se.Add(*[p.diff(q) * qd for q, qd in zip(asm.q, asm.q_dot)]) - kinetic.diff(q))
        for p, q in zip(momentum, asm.q)
    ]
    time_terms = [se.expand(p.diff(asm.t)) for p in momentum]
    return KineticForm(mass, coriolis, time_terms, kinetic, False)
