"""The kinetic energy in matrix form: T = 1/2 q_dot^T M q_dot + T1 + T0 (or a general T).

For particles and bodies the mass matrix is built from Jacobians, M = sum m J^T J
(+ I g^T g for a body's angle), so T is never expanded as a whole; trigonometric products are
combined entry by entry (:mod:`lagrangian.derive.trig`).  The Coriolis/centripetal vector
C(q, q_dot) q_dot comes from the Christoffel symbols of M:

    (C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l,

computed as d(M q_dot)/dq . q_dot - grad_q(1/2 q_dot^T M q_dot).  The rest of
d/dt dT/dq_dot - dT/dq (explicit time dependence, terms of degree 0 and 1 in the velocities)
is kept apart as the time terms.
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from lagrangian.derive.assemble import Assembly
from lagrangian.derive.backend import Backend, depends_on
from lagrangian.derive.trig import combine_trig

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
    return mass, low_degree


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
    mass = [[se.expand(e) for e in row] for row in _hessian(kinetic, asm.q_dot)]
    momentum = [kinetic.diff(v) for v in asm.q_dot]
    coriolis = [
        se.expand(se.Add(*[p.diff(q) * qd for q, qd in zip(asm.q, asm.q_dot)]) - kinetic.diff(q))
        for p, q in zip(momentum, asm.q)
    ]
    time_terms = [se.expand(p.diff(asm.t)) for p in momentum]
    return KineticForm(mass, coriolis, time_terms, kinetic, False)
